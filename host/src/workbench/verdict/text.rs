//! How the verdict of `diagnose` is worded: numbers as every command and
//! the page print them, and the sentences of each kind. What is decided is
//! in [`super`] (a [`Decision`]) and [`crate::workbench::search`].

use super::{Decision, Evidence};
use crate::workbench::diagnosis::{Baseline, DiagnoseSettings, Verdict, VerdictKind};
use crate::workbench::discovery::Located;
use crate::workbench::experiments::separation::Suggestion;
use crate::workbench::search::level::{Found, Level};

/// A reduced chi-square in a note: 3 significant figures (`crate::format`).
pub fn fmt(x: Option<f64>) -> String {
    x.map(|v| crate::format::fmt_sig(v, 3))
        .unwrap_or_else(|| "n/a".into())
}

/// A share of the excess chi-square: two decimals just below 100 %.
pub fn frac(x: Option<f64>) -> String {
    x.map(|v| {
        if v > 0.99 && v < 1.0 {
            format!("{:.2} %", 100.0 * v)
        } else {
            format!("{:.0} %", 100.0 * v)
        }
    })
    .unwrap_or_else(|| "n/a".into())
}

/// "; to tell them apart, measure ..." for a discriminating case.
/// Rivals the single-step verdict cannot tell apart: `listed` names them
/// in the sentence, `names` in the verdict's list.
fn rivals_verdict(
    listed: String,
    names: Vec<String>,
    suggestion: Option<Suggestion>,
    fraction: Option<f64>,
    margin: f64,
) -> Verdict {
    let hint = suggestion.as_ref().map(hint).unwrap_or_default();
    let mut v = verdict_of(
        VerdictKind::Indistinguishable,
        format!(
            "indistinguishable on this data: {listed} fit equally well (AICc within {margin}){hint}"
        ),
    );
    v.indistinguishable = names;
    v.suggestion = suggestion;
    v.effect_explained_fraction = fraction;
    v
}

pub fn hint(g: &Suggestion) -> String {
    g.hint()
}

/// The note of the found set's verdict: every step in order with what it
/// removes, then the errors before and after.
pub fn found_set_note(base: &Baseline, path: &Found, last: &Level) -> String {
    let steps: Vec<String> = path
        .steps
        .iter()
        .enumerate()
        .map(|(i, (step, _, located))| {
            let what = match located {
                Some(l) => format!("located {} ({})", step.name, l.interpretation),
                None => format!("catalogue effect {}", step.name),
            };
            let of = if i == 0 {
                "of the excess chi-square".to_string()
            } else {
                format!("of what step {i} leaves")
            };
            format!(
                "{}. {}{what}: removes {} {of}",
                i + 1,
                if i == 0 { "" } else { "on top of it, " },
                frac(step.explained_fraction)
            )
        })
        .collect();
    let n = path.steps.len();
    let head = match (last.at_floor, n == 1) {
        (true, true) => "1 step reaches the noise floor".to_string(),
        (true, false) => format!("{n} steps reach the noise floor"),
        (false, true) => "1 step lowers the error but does not reach the noise floor".to_string(),
        (false, false) => {
            format!("{n} steps lower the error but do not reach the noise floor")
        }
    };
    format!(
        "{head}: {}. MARE {:.1} % -> {:.1} % (cross-validated {:.1} %), reduced chi-square {} -> {} (noise floor {})",
        steps.join("; "),
        100.0 * base.mare,
        100.0 * last.mare,
        100.0 * last.cv_mare,
        fmt(base.chi2_reduced),
        fmt(last.chi2_reduced),
        fmt(base.noise_floor_chi2_reduced)
    )
}

/// An empty verdict of `kind` with its note.
pub(crate) fn verdict_of(kind: VerdictKind, note: String) -> Verdict {
    Verdict {
        effect: None,
        explained: !matches!(kind, VerdictKind::Unexplained),
        kind,
        note,
        indistinguishable: Vec::new(),
        suggestion: None,
        effect_explained_fraction: None,
        located: Vec::new(),
        steps: Vec::new(),
        joint: None,
        sets: Vec::new(),
        agreed_places: Vec::new(),
        sets_margin: None,
        stability: Vec::new(),
    }
}

/// "MARE a -> b % (cross-validated c %), reduced chi-square ... (noise floor ...)".
fn errors(base: &Baseline, mare: f64, cv_mare: f64, chi2_reduced: Option<f64>) -> String {
    format!(
        "MARE {:.1} % -> {:.1} % (cross-validated {:.1} %), reduced chi-square {} -> {} (noise floor {})",
        100.0 * base.mare,
        100.0 * mare,
        100.0 * cv_mare,
        fmt(base.chi2_reduced),
        fmt(chi2_reduced),
        fmt(base.noise_floor_chi2_reduced)
    )
}

/// The verdict of a decision, worded.
pub fn word(d: Decision, e: &Evidence, s: &DiagnoseSettings) -> Verdict {
    let base = e.base;
    match d {
        Decision::AtFloor => verdict_of(
            VerdictKind::NoneNeeded,
            format!(
                "none needed: the model already fits to the noise (reduced chi-square {} against a noise floor of {})",
                fmt(base.chi2_reduced),
                fmt(base.noise_floor_chi2_reduced)
            ),
        ),
        Decision::NotOutOfSample { best } => verdict_of(
            VerdictKind::NoneNeeded,
            format!(
                "none needed: the baseline's chi-square is above the noise floor (reduced {} against {}), but the best candidate, {}, does not lower the cross-validated error ({:.2} % against the baseline's {:.2} %): the excess is not an effect this data can support",
                fmt(base.chi2_reduced),
                fmt(base.noise_floor_chi2_reduced),
                best.effect,
                100.0 * best.score.cv_mare,
                100.0 * base.mare
            ),
        ),
        Decision::Catalogue { best, fraction } => {
            let mut v = verdict_of(
                VerdictKind::Identified,
                format!(
                    "missing: {} (removes {} of the excess chi-square). {}",
                    best.effect,
                    frac(fraction),
                    errors(base, best.score.mare, best.score.cv_mare, best.score.chi2_reduced)
                ),
            );
            v.effect = Some(best.effect.clone());
            v.effect_explained_fraction = fraction;
            v
        }
        Decision::CatalogueRivals {
            names,
            suggestion,
            fraction,
        } => {
            let listed = format!("{}: they", names.join(", "));
            rivals_verdict(listed, names, suggestion, fraction, s.clear_margin)
        }
        Decision::CatalogueOrLaw {
            effect,
            law,
            suggestion: g,
        } => {
            let mut v = verdict_of(
                VerdictKind::Indistinguishable,
                format!(
                    "indistinguishable on this data: {} and the located {} ({}) fit equally well (AICc {:.1} against {:.1}){}",
                    effect.effect,
                    law.describe(),
                    law.interpretation,
                    effect.score.aicc.unwrap_or(f64::NAN),
                    law.score.aicc.unwrap_or(f64::NAN),
                    hint(&g)
                ),
            );
            v.indistinguishable = vec![effect.effect.clone(), law.describe()];
            v.effect_explained_fraction = crate::stats::excess_removed(
                base.chi2,
                effect.score.chi2,
                super::floor0(base),
            );
            v.suggestion = Some(g);
            v.located = vec![law.clone()];
            v
        }
        Decision::Law {
            law,
            beneath,
            beats,
        } => law_verdict(base, law, beneath, beats),
        Decision::LawRivals {
            laws,
            suggestion,
            beneath_fraction,
        } => {
            let names: Vec<String> = laws.iter().map(|l| l.describe()).collect();
            let listed = names.join("; ");
            let mut v = rivals_verdict(listed, names, suggestion, beneath_fraction, s.clear_margin);
            v.located = laws.into_iter().cloned().collect();
            v
        }
        Decision::Unexplained {
            closest,
            partial,
            rival,
        } => unexplained_verdict(e, closest, partial, rival, s),
    }
}

fn law_verdict(
    base: &Baseline,
    law: &Located,
    beneath: Option<(&crate::workbench::diagnosis::Candidate, Option<f64>)>,
    beats: Option<(&crate::workbench::diagnosis::Candidate, f64)>,
) -> Verdict {
    let how = errors(
        base,
        law.score.mare,
        law.score.cv_mare,
        law.score.chi2_reduced,
    );
    let mut v = match beneath {
        Some((c, f)) => {
            let mut v = verdict_of(
                VerdictKind::Identified,
                format!(
                    "missing: {} (removes {} of the excess chi-square) and, beyond it, located: {} ({}; removes {} of what {} leaves). {how}",
                    c.effect,
                    frac(f),
                    law.describe(),
                    law.interpretation,
                    frac(law.explained_fraction),
                    c.effect
                ),
            );
            v.effect = Some(c.effect.clone());
            v.effect_explained_fraction = f;
            v
        }
        None => verdict_of(
            VerdictKind::Located,
            format!(
                "no catalogue effect explains it; located: {} ({}; removes {} of the excess chi-square). {how}",
                law.describe(),
                law.interpretation,
                frac(law.explained_fraction)
            ),
        ),
    };
    if let Some((cb, by)) = beats {
        v.note.push_str(&format!(
            "; it beats the best catalogue effect at the floor, {}, by {by:.1} in AICc",
            cb.effect
        ));
    }
    v.located = vec![law.clone()];
    v
}

fn unexplained_verdict(
    e: &Evidence,
    closest: Option<(&crate::workbench::diagnosis::Candidate, Option<f64>)>,
    located: Vec<Located>,
    rival: Option<(String, String, Option<Suggestion>)>,
    s: &DiagnoseSettings,
) -> Verdict {
    let base = e.base;
    let closest = closest
        .map(|(c, f)| {
            format!(
                "; {} removes {} of the excess chi-square (MARE {:.1} % -> {:.1} %) but not all",
                c.effect,
                frac(f),
                100.0 * base.mare,
                100.0 * c.score.mare
            )
        })
        .unwrap_or_else(|| {
            "; no catalogue effect removes even half of the excess chi-square".into()
        });
    let partial_note = located
        .first()
        .map(|l| {
            format!(
                "; the best located correction, {}, removes {} ({}) but does not reach the floor",
                l.describe(),
                frac(l.explained_fraction),
                l.interpretation
            )
        })
        .unwrap_or_default();
    let mut v = verdict_of(
        VerdictKind::Unexplained,
        format!(
            "unexplained: no catalogue effect{}, and no located correction, brings the fit to the noise floor (reduced chi-square {}){closest}{partial_note}",
            if e.pairs.is_empty() { "" } else { " or pair" },
            fmt(base.noise_floor_chi2_reduced)
        ),
    );
    if let Some((a, b, g)) = rival {
        v.note.push_str(&format!(
            "; it and {b} are indistinguishable on this design (AICc within {})",
            s.clear_margin
        ));
        if let Some(g) = &g {
            v.note.push_str(&hint(g));
        }
        v.indistinguishable = vec![a, b];
        v.suggestion = g;
    }
    v.located = located;
    v
}
