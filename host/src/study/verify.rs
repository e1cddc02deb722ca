//! The study file read as untrusted input: what `steps` and the page
//! print is only what the file stores, so every stored number is checked
//! before it is believed.
//!
//! 1. Every number is finite and in its range (an error, a chi-square and
//!    its floor are non-negative, a prediction finite, a p-value in 0..=1,
//!    at least one measured quantity).
//! 2. The chain holds: each step's `before` is the previous step's
//!    `after` (the start's, for step 1).
//! 3. Each snapshot is the model's: the base preset, then each step with
//!    its recorded parameters, is compared again with the pinned dataset,
//!    and its MARE, chi-square, reduced chi-square, noise floor, counts and
//!    every case's predictions must be the stored ones. The
//!    cross-validated MARE, the parameters' intervals and the two
//!    calibrations a step tried need the fits again and are checked by
//!    range only (an interval must hold its value). A deleted, swapped or duplicated step, an edited parameter,
//!    formula or preset, all change a recomputed number.
//!
//! Any failure names the step and the field.

use super::error::StudyError;
use super::file::{ParamRecord, ProfileRecord, StepRecord};
use super::snapshot::{CaseRow, Snapshot, Stats};
use super::Study;

/// Relative agreement required of a recomputed number: the same
/// computation on the same bytes, up to the order of parallel sums.
const REL_TOL: f64 = 1e-9;

/// The largest error (a fraction) believed: a model a million times off
/// is no step of a study, and a larger stored one prints as `inf %`.
const MAX_MARE: f64 = 1e6;

/// Where a failure is.
struct At<'a> {
    study: &'a Study,
    /// `the start` or `step N (`effect`)`.
    at: String,
}

impl At<'_> {
    fn fail(&self, field: &str, message: String) -> StudyError {
        StudyError::Unverified {
            file: self.study.path().to_path_buf(),
            at: self.at.clone(),
            field: field.into(),
            message,
        }
    }
}

/// Checks the whole study (module docs).
pub fn verify(study: &Study) -> Result<(), StudyError> {
    let f = study.file();
    let start = At {
        study,
        at: "the start".into(),
    };
    snapshot_numbers(&start, "start", &f.start)?;
    if f.start.stats.n == 0 {
        return Err(start.fail(
            "start.stats.n",
            "no measured quantity: the dataset has no measured case, so there is nothing the study's error could be computed on".into(),
        ));
    }
    recomputed(&start, "start", &f.start, 0)?;
    let mut previous = f.start.stats;
    for (i, step) in f.steps.iter().enumerate() {
        let at = At {
            study,
            at: format!(
                "step {} (`{}`)",
                i + 1,
                crate::data::limits::echo(&step.effect.name)
            ),
        };
        step_numbers(&at, step)?;
        chain(&at, &step.before, &previous)?;
        recomputed(&at, "after", &step.after, i + 1)?;
        previous = step.after.stats;
    }
    Ok(())
}

fn finite(at: &At, field: &str, v: f64) -> Result<(), StudyError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(at.fail(field, format!("stored {v}: not a finite number")))
    }
}

fn non_negative(at: &At, field: &str, v: f64) -> Result<(), StudyError> {
    finite(at, field, v)?;
    if v < 0.0 {
        return Err(at.fail(field, format!("stored {v}: cannot be negative")));
    }
    Ok(())
}

fn a_mare(at: &At, field: &str, v: f64) -> Result<(), StudyError> {
    non_negative(at, field, v)?;
    if v > MAX_MARE {
        return Err(at.fail(
            field,
            format!("stored {v}: an error above {MAX_MARE} (a fraction) is no model's"),
        ));
    }
    Ok(())
}

fn stats_numbers(at: &At, field: &str, s: &Stats) -> Result<(), StudyError> {
    a_mare(at, &format!("{field}.mare"), s.mare)?;
    a_mare(at, &format!("{field}.cv_mare"), s.cv_mare)?;
    non_negative(at, &format!("{field}.chi2"), s.chi2)?;
    if let Some(v) = s.chi2_reduced {
        non_negative(at, &format!("{field}.chi2_reduced"), v)?;
    }
    if let Some(v) = s.noise_floor_chi2 {
        non_negative(at, &format!("{field}.noise_floor_chi2"), v)?;
    }
    Ok(())
}

fn snapshot_numbers(at: &At, field: &str, s: &Snapshot) -> Result<(), StudyError> {
    stats_numbers(at, &format!("{field}.stats"), &s.stats)?;
    for (k, c) in s.cases.iter().enumerate() {
        let name = |v: &str| format!("{field}.case[{k}].{v} (case {})", echo(&c.id));
        finite(at, &name("u_pred_mm_s"), c.u_pred_mm_s)?;
        finite(at, &name("omega_pred_hz"), c.omega_pred_hz)?;
        for (v, x) in [
            ("n_waves", Some(c.n_waves)),
            ("amplitude_ratio", Some(c.amplitude_ratio)),
            ("frequency_hz", Some(c.frequency_hz)),
            ("u_obs_mm_s", c.u_obs_mm_s),
            ("u_ci_mm_s", c.u_ci_mm_s),
            ("u_rel_err", c.u_rel_err),
            ("omega_obs_hz", c.omega_obs_hz),
            ("omega_ci_hz", c.omega_ci_hz),
            ("omega_rel_err", c.omega_rel_err),
        ] {
            if let Some(x) = x {
                finite(at, &name(v), x)?;
            }
        }
    }
    Ok(())
}

fn params_numbers(at: &At, field: &str, ps: &[ParamRecord]) -> Result<(), StudyError> {
    for (k, p) in ps.iter().enumerate() {
        let name = |v: &str| format!("{field}[{k}].{v} ({}.{})", echo(&p.effect), echo(&p.name));
        for (v, x) in [("lo", p.lo), ("hi", p.hi)] {
            if let Some(x) = x {
                finite(at, &name(v), x)?;
            }
        }
        if let (Some(lo), Some(hi)) = (p.lo, p.hi) {
            if !(lo <= p.value && p.value <= hi) {
                return Err(at.fail(
                    &name("lo"),
                    format!(
                        "stored interval {lo} .. {hi} does not hold the value {}",
                        p.value
                    ),
                ));
            }
        }
        if let Some(q) = &p.profile {
            profile_numbers(at, &name("profile"), p.value, q)?;
        }
    }
    Ok(())
}

/// A stored profile interval: finite ends on either side of the value (an
/// open end is absent, never an infinity).
fn profile_numbers(at: &At, field: &str, value: f64, q: &ProfileRecord) -> Result<(), StudyError> {
    for (v, x) in [("low", q.low), ("high", q.high)] {
        if let Some(x) = x {
            finite(at, &format!("{field}.{v}"), x)?;
        }
    }
    let holds = q.low.is_none_or(|l| l <= value) && q.high.is_none_or(|h| value <= h);
    if !holds {
        let end = |x: Option<f64>| x.map_or("open".to_string(), |x| x.to_string());
        return Err(at.fail(
            field,
            format!(
                "stored profile interval {} .. {} does not hold the value {value}",
                end(q.low),
                end(q.high)
            ),
        ));
    }
    Ok(())
}

fn step_numbers(at: &At, s: &StepRecord) -> Result<(), StudyError> {
    stats_numbers(at, "before", &s.before)?;
    snapshot_numbers(at, "after", &s.after)?;
    params_numbers(at, "param", &s.params)?;
    params_numbers(at, "refitted", &s.refitted)?;
    if let Some(c) = &s.choice {
        for (t, trial) in [("held", &c.held), ("joint", &c.joint)] {
            a_mare(at, &format!("choice.{t}.mare"), trial.mare)?;
            non_negative(at, &format!("choice.{t}.chi2"), trial.chi2)?;
        }
        if let Some(f) = c.f {
            non_negative(at, "choice.f", f)?;
        }
        if let Some(p) = c.p {
            if !(0.0..=1.0).contains(&p) {
                return Err(at.fail("choice.p", format!("stored {p}: a p-value is in 0..=1")));
            }
        }
    }
    Ok(())
}

fn close(a: f64, b: f64) -> bool {
    a == b || (a - b).abs() <= REL_TOL * a.abs().max(b.abs())
}

fn close_opt(a: Option<f64>, b: Option<f64>) -> bool {
    match (a, b) {
        (Some(x), Some(y)) => close(x, y),
        (None, None) => true,
        _ => false,
    }
}

fn show(v: Option<f64>) -> String {
    v.map_or_else(|| "none".into(), |x| format!("{x}"))
}

/// Step N's `before` is what the model was after step N - 1.
fn chain(at: &At, before: &Stats, previous: &Stats) -> Result<(), StudyError> {
    let pairs = [
        ("before.mare", before.mare, previous.mare),
        ("before.cv_mare", before.cv_mare, previous.cv_mare),
        ("before.chi2", before.chi2, previous.chi2),
    ];
    for (field, b, p) in pairs {
        if !close(b, p) {
            return Err(at.fail(
                field,
                format!("stored {b}, but the step before it ends at {p}: each step's before is the previous step's after (a step deleted, moved or edited by hand?)"),
            ));
        }
    }
    if before.n != previous.n || before.free_params != previous.free_params {
        return Err(at.fail(
            "before.n",
            "the counts differ from the step before it: each step's before is the previous step's after".into(),
        ));
    }
    Ok(())
}

fn mismatch(at: &At, field: &str, stored: String, computed: String) -> StudyError {
    at.fail(
        field,
        format!(
            "stored {stored}, but the model the study records (its preset and its steps up to here, with their parameters) gives {computed} on its dataset: the file was edited by hand or written by a swimbot whose physics differs; `swimbot init --force` starts the study again"
        ),
    )
}

/// The snapshot `stored` is what the base with the first `k` steps gives.
fn recomputed(at: &At, field: &str, stored: &Snapshot, k: usize) -> Result<(), StudyError> {
    let model = at.study.model_upto(k)?;
    let now = Snapshot::of(&model, at.study.dataset(), &[]).map_err(|e| {
        at.fail(
            field,
            format!("the model recorded here cannot predict the dataset: {e}"),
        )
    })?;
    let (s, c) = (&stored.stats, &now.stats);
    let floats = [
        ("stats.mare", Some(s.mare), Some(c.mare)),
        ("stats.chi2", Some(s.chi2), Some(c.chi2)),
        ("stats.chi2_reduced", s.chi2_reduced, c.chi2_reduced),
        (
            "stats.noise_floor_chi2",
            s.noise_floor_chi2,
            c.noise_floor_chi2,
        ),
    ];
    for (name, a, b) in floats {
        if !close_opt(a, b) {
            return Err(mismatch(at, &format!("{field}.{name}"), show(a), show(b)));
        }
    }
    let counts = [
        ("stats.n", s.n, c.n),
        ("stats.free_params", s.free_params, c.free_params),
        (
            "case (the number of cases)",
            stored.cases.len(),
            now.cases.len(),
        ),
    ];
    for (name, a, b) in counts {
        if a != b {
            return Err(mismatch(
                at,
                &format!("{field}.{name}"),
                a.to_string(),
                b.to_string(),
            ));
        }
    }
    if s.at_noise_floor != c.at_noise_floor {
        return Err(mismatch(
            at,
            &format!("{field}.stats.at_noise_floor"),
            s.at_noise_floor.to_string(),
            c.at_noise_floor.to_string(),
        ));
    }
    for (k, (a, b)) in stored.cases.iter().zip(&now.cases).enumerate() {
        case(at, &format!("{field}.case[{k}]"), a, b)?;
    }
    Ok(())
}

fn case(at: &At, field: &str, stored: &CaseRow, now: &CaseRow) -> Result<(), StudyError> {
    if stored.id != now.id {
        return Err(mismatch(
            at,
            &format!("{field}.id"),
            echo(&stored.id),
            echo(&now.id),
        ));
    }
    let id = echo(&stored.id);
    let floats = [
        (
            "u_pred_mm_s",
            Some(stored.u_pred_mm_s),
            Some(now.u_pred_mm_s),
        ),
        (
            "omega_pred_hz",
            Some(stored.omega_pred_hz),
            Some(now.omega_pred_hz),
        ),
        ("u_obs_mm_s", stored.u_obs_mm_s, now.u_obs_mm_s),
        ("u_ci_mm_s", stored.u_ci_mm_s, now.u_ci_mm_s),
        ("u_rel_err", stored.u_rel_err, now.u_rel_err),
        ("omega_obs_hz", stored.omega_obs_hz, now.omega_obs_hz),
        ("omega_ci_hz", stored.omega_ci_hz, now.omega_ci_hz),
        ("omega_rel_err", stored.omega_rel_err, now.omega_rel_err),
        ("n_waves", Some(stored.n_waves), Some(now.n_waves)),
        (
            "amplitude_ratio",
            Some(stored.amplitude_ratio),
            Some(now.amplitude_ratio),
        ),
        (
            "frequency_hz",
            Some(stored.frequency_hz),
            Some(now.frequency_hz),
        ),
    ];
    for (name, a, b) in floats {
        if !close_opt(a, b) {
            return Err(mismatch(
                at,
                &format!("{field}.{name} (case {id})"),
                show(a),
                show(b),
            ));
        }
    }
    Ok(())
}

fn echo(s: &str) -> String {
    crate::data::limits::echo(s).to_string()
}
