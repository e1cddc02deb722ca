//! How the audit's influence and outlier findings
//! ([`super::influence::Finding`]) are worded: one sentence a
//! scientist can act on per finding, with its severity.

use super::influence::Finding;
use super::{Flag, Severity};
use crate::format::{fmt_sig, fmt_value_unc};

impl Finding {
    /// The audit's flag for this finding.
    pub fn flag(&self) -> Flag {
        let (case, kind, detail, severity) = match self {
            Finding::MakesAConclusion { case, without } => (
                case,
                "influence-verdict",
                format!(
                    "{case}: with all cases no candidate is clearly best; without this case {without} is (ahead by 4 or more in AICc): this one case stands against that conclusion, check its record or re-measure it"
                ),
                Severity::Warning,
            ),
            Finding::ChangesTheConclusion { case, with, without } => (
                case,
                "influence-verdict",
                format!(
                    "{case}: with all cases the best-supported effect is {with}; without this case it is {}: the conclusion rests on this one case, re-measure it before relying on it",
                    without
                        .as_deref()
                        .map(|s| format!("{s} instead"))
                        .unwrap_or_else(|| "undecided".into())
                ),
                Severity::Warning,
            ),
            Finding::MovesAParameter {
                case,
                effect,
                name,
                value,
                ci95,
                without,
            } => (
                case,
                "influence-parameter",
                format!(
                    "{case}: leaving it out moves the fitted {effect} {name} from {} (95 % interval) to {}, beyond the interval: this case drives the fitted value",
                    fmt_value_unc(*value, *ci95),
                    fmt_sig(*without, 3)
                ),
                Severity::Warning,
            ),
            Finding::Outlier {
                case,
                best,
                quantity,
                z,
                limit,
            } => (
                case,
                "outlier",
                format!(
                    "{case}: the other cases are fitted to the noise (best: {best}), but this case's {quantity} stays {z:.1} combined standard errors away (limit {limit:.1}) under every model that fits them: no candidate effect removes it; check this case's record or re-measure it"
                ),
                Severity::Error,
            ),
        };
        Flag {
            case: case.clone(),
            kind: kind.into(),
            detail,
            severity,
        }
    }
}
