//! `swimbot audit`: checks of the data themselves that need no physics
//! beyond the model family. Each finding is a [`Flag`]: the case, the kind
//! of check, a sentence a scientist can act on, and a severity. A clean
//! dataset gives no flags.
//!
//! 1. **Geometry** (here): the wire's chord length implied by each case's
//!    recorded helix, `ell = L_t sqrt(1 + (2 pi B_o / lambda)^2)`, against
//!    the stated fixed chord length, or (when the data only say it was
//!    fixed, `chord_fixed = true`) against the median of the other cases.
//!    The difference is judged in the chord's standard uncertainty,
//!    propagated analytically from the recorded `lambda`, `B_o`, `L_t`
//!    uncertainties, with a floor of 0.5 % of `ell` for rounding of the
//!    recorded values; beyond 2 is a warning, beyond 3 an error. The flag
//!    names the single recorded value whose correction would reconcile the
//!    case with the fewest standard uncertainties.
//! 2. **Ratios** ([`self::ratio`]): measured speeds and body rates
//!    of one case over another against the range the model family produces.
//! 3. **Influence and outliers** ([`self::influence`]): which single
//!    case drives the best-supported effect or its fitted value; which case
//!    no candidate fitted on the others can predict; and a case that stands
//!    alone under the model ([`super::robust`]: its residual beyond the
//!    one-bad-run limit of [`super::data_quality::outliers`], set at a false-alarm rate of
//!    1 % per dataset, and the others at the noise floor without it),
//!    judged in measurement standard errors as `diagnose` judges it.
//!
//! The fits of check 3 minimise the deviance of [`AuditSettings::likelihood`]
//! (`--likelihood`, as in `fit` and `diagnose`).
//!
//! Checks 2 and 3 use the measurements with the input uncertainty combined
//! ([`super::propagate::with_input_uncertainty`]), so that a residual the
//! inputs can explain is not flagged.
//!
//! Reference for the chord relation: the paper's `alpha = L_t / ell`
//! (eqs. 6-7 and the text on the fixed chord length).

pub mod influence;
mod influence_words;
pub mod loo;
pub mod ratio;

use super::propagate::with_input_uncertainty;
use crate::data::quantities::chord_length_mm;
use crate::data::{Case, Dataset};
use crate::model::{Model, ModelError};
use serde::Serialize;
use std::f64::consts::PI;

/// How serious a flag is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Severity {
    Warning,
    Error,
}

/// One finding of the audit.
#[derive(Debug, Clone, Serialize)]
pub struct Flag {
    pub case: String,
    /// `chord-length`, `ratio-u`, `ratio-omega`, `ratio-pair`,
    /// `influence-verdict`, `influence-parameter`, `outlier`.
    pub kind: String,
    pub detail: String,
    pub severity: Severity,
}

/// One case's chord length against its reference.
#[derive(Debug, Clone, Serialize)]
pub struct ChordCheck {
    pub case: String,
    pub chord_mm: f64,
    pub chord_sd_mm: f64,
    pub reference_mm: f64,
    /// `(chord - reference) / reference`.
    pub rel_diff: f64,
    /// The difference in combined standard uncertainties.
    pub z: f64,
}

/// What the audit found, with the numbers behind it.
#[derive(Debug, Clone, Serialize)]
pub struct Audit {
    pub dataset: String,
    pub model: String,
    pub flags: Vec<Flag>,
    pub chords: Vec<ChordCheck>,
    pub ratio: self::ratio::RatioSummary,
    pub influence: self::influence::InfluenceSummary,
}

/// Settings of [`audit`]; `Default` gives the documented values.
#[derive(Debug, Clone)]
pub struct AuditSettings {
    /// Members of the model family sampled for the ratio test (256).
    pub family_samples: usize,
    pub seed: u64,
    /// What the influence check's fits minimise (least squares).
    pub likelihood: super::robust::Likelihood,
    /// Called with the stage's number (from 1) and a short message as each
    /// of the [`AUDIT_STAGES`] starts (progress display).
    pub progress: Option<super::progress::Progress>,
}

/// The audit's stages, for a progress display.
pub const AUDIT_STAGES: u64 = 4;

impl Default for AuditSettings {
    fn default() -> Self {
        AuditSettings {
            family_samples: 256,
            seed: 12,
            likelihood: super::robust::Likelihood::Gaussian,
            progress: None,
        }
    }
}

/// Run every check on `data`; `model` is the family's base.
pub fn audit(model: &Model, data: &Dataset, s: &AuditSettings) -> Result<Audit, ModelError> {
    let say = |k: u64, m: &str| super::progress::say(&s.progress, k, m);
    say(1, "chords and the inputs' uncertainty");
    let (mut flags, chords) = chord_checks(data);
    let combined = with_input_uncertainty(model, data)?;
    say(2, "ratio test against the model family");
    let (ratio, ratio_flags) = self::ratio::ratio_test(model, data, s)?;
    flags.extend(ratio_flags);
    say(3, "influence: leave-one-out refits");
    let (influence, influence_flags) = self::influence::influence(model, &combined, s.likelihood);
    flags.extend(influence_flags);
    // The bad runs ([`super::data_quality::bad_runs`]), judged in
    // measurement standard errors as `diagnose` judges them; an error when a
    // run's case stands out with the inputs' uncertainty combined too, else
    // a warning.
    let bad_runs = super::data_quality::bad_runs::bad_runs;
    say(4, "bad runs");
    let combined_runs = bad_runs(model, &combined, 0.95)?;
    let named = bad_runs(model, data, 0.95)?;
    for l in named.iter().flat_map(|b| &b.runs) {
        let all = named.as_ref().expect("a run comes from a finding");
        if !flags
            .iter()
            .any(|f| f.kind == "outlier" && f.case == l.case)
        {
            let also = combined_runs
                .as_ref()
                .is_some_and(|c| c.names_case(&l.case));
            let note = if also {
                ""
            } else {
                " (judged in measurement standard errors; with the inputs' uncertainty combined it is not beyond the limit)"
            };
            flags.push(Flag {
                case: l.case.clone(),
                kind: "outlier".into(),
                detail: format!("{}: {}{note}", l.case, all.sentence()),
                severity: if also {
                    Severity::Error
                } else {
                    Severity::Warning
                },
            });
        }
    }
    Ok(Audit {
        dataset: data.name.clone(),
        model: model.describe(),
        flags,
        chords,
        ratio,
        influence,
    })
}

/// `d ell / d x` for `x` = wavelength, amplitude, tail length.
fn chord_gradient(c: &Case) -> [(&'static str, &'static str, f64); 3] {
    let k = 2.0 * PI * c.amplitude_mm / c.wavelength_mm;
    let root = (1.0 + k * k).sqrt();
    let l = c.tail_length_mm;
    [
        (
            "wavelength_mm",
            "wavelength",
            -l * k * k / (c.wavelength_mm * root),
        ),
        (
            "amplitude_mm",
            "amplitude",
            l * k * (2.0 * PI / c.wavelength_mm) / root,
        ),
        ("tail_length_mm", "axial length", root),
    ]
}

fn chord_sd_mm(c: &Case) -> f64 {
    let var: f64 = chord_gradient(c)
        .iter()
        .map(|(f, _, g)| (g * c.inputs.standard(c, f)).powi(2))
        .sum();
    var.sqrt().max(0.005 * chord_length_mm(c))
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// The geometry check (module docs, check 1).
pub fn chord_checks(data: &Dataset) -> (Vec<Flag>, Vec<ChordCheck>) {
    let fixed: Vec<&Case> = data.cases.iter().filter(|c| c.inputs.chord_fixed).collect();
    let mut flags = Vec::new();
    let mut checks = Vec::new();
    for c in &fixed {
        let chord = chord_length_mm(c);
        let sd = chord_sd_mm(c);
        let (reference, ref_sd, against) = match c.inputs.chord_length_mm {
            Some(l) => (l, 0.0, format!("the stated fixed chord length {l:.1} mm")),
            None => {
                let others: Vec<&&Case> = fixed.iter().filter(|o| o.id != c.id).collect();
                if others.len() < 2 {
                    continue;
                }
                let m = median(others.iter().map(|o| chord_length_mm(o)).collect());
                // Standard error of a median: 1.2533 s / sqrt(n).
                let s = 1.2533 * median(others.iter().map(|o| chord_sd_mm(o)).collect())
                    / (others.len() as f64).sqrt();
                (m, s, format!("the others' (median {m:.1} mm)"))
            }
        };
        let z = (chord - reference) / (sd * sd + ref_sd * ref_sd).sqrt();
        let rel = (chord - reference) / reference;
        checks.push(ChordCheck {
            case: c.id.clone(),
            chord_mm: chord,
            chord_sd_mm: sd,
            reference_mm: reference,
            rel_diff: rel,
            z,
        });
        if z.abs() <= 2.0 {
            continue;
        }
        flags.push(Flag {
            case: c.id.clone(),
            kind: "chord-length".into(),
            detail: format!(
                "{}: the chord length implied by its geometry ({chord:.1} mm) is {:.0} % {} {against}, {:.1} times its input uncertainty; {}",
                c.id,
                100.0 * rel.abs(),
                if rel < 0.0 { "below" } else { "above" },
                z.abs(),
                reconcile_hint(c, reference)
            ),
            severity: if z.abs() > 3.0 { Severity::Error } else { Severity::Warning },
        });
    }
    (flags, checks)
}

/// The recorded values whose correction alone would reconcile the chord,
/// the most plausible first: fewest standard uncertainties away (relative
/// change when no uncertainty is given).
fn reconcile_hint(c: &Case, reference: f64) -> String {
    let delta = reference - chord_length_mm(c);
    let mut options: Vec<(f64, String)> = Vec::new();
    for (field, name, g) in chord_gradient(c) {
        if g == 0.0 {
            continue;
        }
        // Solve exactly along this one input (the chord is monotone in each).
        let x0 = crate::data::uncertainty::field_value(c, field).unwrap_or(0.0);
        let Some(x) = solve_chord(c, field, reference, x0 + delta / g) else {
            continue;
        };
        let u = c.inputs.standard(c, field);
        let cost = if u > 0.0 {
            (x - x0).abs() / u
        } else {
            1e3 * (x - x0).abs() / x0
        };
        options.push((cost, format!("{name} {x:.1} mm instead of {x0:.1} mm")));
    }
    options.sort_by(|a, b| a.0.total_cmp(&b.0));
    if options.is_empty() {
        return "check its recorded wavelength, amplitude and axial length".into();
    }
    let list: Vec<String> = options.into_iter().map(|o| o.1).collect();
    format!(
        "check its recorded geometry: any one of {} would reconcile it",
        list.join(", or ")
    )
}

/// Newton on one field so that the case's chord equals `target`.
fn solve_chord(c: &Case, field: &str, target: f64, start: f64) -> Option<f64> {
    let mut case = c.clone();
    let mut x = start;
    for _ in 0..30 {
        if !(x.is_finite() && x > 0.0) {
            return None;
        }
        crate::data::uncertainty::set_field(&mut case, field, x);
        let g = chord_gradient(&case)
            .iter()
            .find(|(f, _, _)| *f == field)
            .map(|t| t.2)?;
        let step = (chord_length_mm(&case) - target) / g;
        x -= step;
        if step.abs() < 1e-9 * x.abs() {
            return Some(x);
        }
    }
    None
}
