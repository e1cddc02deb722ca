//! How far apart two sets' keys must be before the data tell them apart,
//! measured on the data's own design: the margin of the model confidence
//! set (`super::rivals`), calibrated by a parametric bootstrap.
//!
//! A fixed AICc margin (Burnham & Anderson's "within 4") holds for two
//! models compared once. The search compares the found set with dozens of
//! sets at other places, each refitted with its own law forms, so the
//! best of the wrong ones beats the truth by more than 4 far more often
//! than one time in twenty: on a drawn three-effect design (36 cases) the
//! true set's places sat 5.2 above the found set's key. How far is read
//! from the data instead:
//!
//! 1. The **candidates**: the found set and the acceptable sets at other
//!    places within [`WINDOW`] of its key (one per combination of places,
//!    at the noise floor when the found set is; at most [`CANDIDATES`]).
//! 2. [`DRAWS`] data sets are drawn from the found set's fitted model: each
//!    measured mean is the model's prediction plus its standard error
//!    times a Student-t variable with the degrees of freedom of its trials
//!    (the noise law of the floor, [`crate::workbench::noise`]), with fixed
//!    seeds.
//! 3. On each draw every candidate is refitted jointly (from its fitted
//!    values) and keyed as on the data; the draw's **excess** is the found
//!    set's key minus the best candidate's: how far a wrong set beat the
//!    set that made the data (0 when none did).
//! 4. The margin is the [`LEVEL`] quantile of the excesses, and never less
//!    than the fixed margin: a set whose key is within it of the found
//!    set's is one the data cannot rule out.
//!
//! This is the plug-in bootstrap of a selection statistic: the found set
//! stands in for the unknown truth, so the margin is right to the extent
//! that the found set's fit resembles the truth's; a set far better than
//! everything else gets a small margin, a design where many places trade
//! gets a large one. Its cost is `DRAWS x candidates` joint refits, paid
//! only when some set lies within the window (never on data far above the
//! floor, where no rival is stated).
//!
//! References: B. Efron & R. J. Tibshirani, *An Introduction to the
//! Bootstrap* (1993), ch. 6 (the parametric bootstrap); P. R. Hansen,
//! A. Lunde & J. M. Nason, Econometrica 79 (2011) 453 (the model
//! confidence set, its bootstrap calibration); K. P. Burnham & D. R.
//! Anderson, *Model Selection and Multimodel Inference*, 2nd ed. (2002),
//! sec. 2.6 (the fixed margin and its limits).

use super::fitted::{Ctx, Fitted};
use super::set::joint;
use crate::data::{Dataset, Measured};
use crate::workbench::noise::error_dofs;
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, StudentT};
use rayon::prelude::*;

/// Data sets drawn from the found set (40: the 95 % quantile is then the
/// 38th of the 40 ordered excesses).
pub const DRAWS: usize = 40;

/// Most candidates refitted on each draw, the found set included (10).
pub const CANDIDATES: usize = 10;

/// How far above (or below) the found set's key a set may lie to be a
/// candidate (25: far beyond any margin measured on the drawn designs).
pub const WINDOW: f64 = 25.0;

/// The quantile of the excesses taken as the margin (0.95).
pub const LEVEL: f64 = 0.95;

const SEED: u64 = 0xca1b;

/// The margin used, and how it was found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Margin {
    /// Keys within this of the found set's are not told apart.
    pub value: f64,
    /// The bootstrap behind it; `None` for the fixed margin (no candidate
    /// within the window, or every draw failed).
    pub calibrated: Option<Calibration>,
}

/// What the bootstrap measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Calibration {
    /// The [`LEVEL`] quantile of the excesses.
    pub quantile: f64,
    /// Draws whose every candidate was refitted.
    pub draws: usize,
    /// Sets refitted on each draw, the found set included.
    pub candidates: usize,
}

/// The candidates (module docs, step 1) for `chosen` among `all`, the
/// found set first; `ok` says whether a set could be stated as a rival.
pub(super) fn candidates<'a>(
    all: &'a [Fitted],
    chosen: &'a Fitted,
    ok: impl Fn(&Fitted) -> bool,
) -> Vec<&'a Fitted> {
    let mut out = vec![chosen];
    let mut seen = vec![chosen.signature()];
    for f in all {
        if out.len() >= CANDIDATES {
            break;
        }
        let near = (f.joint.key - chosen.joint.key).abs() <= WINDOW;
        if near && !seen.contains(&f.signature()) && ok(f) {
            seen.push(f.signature());
            out.push(f);
        }
    }
    out
}

/// The calibrated margin for the found set `sets[0]` against the other
/// candidates; the fixed margin when there is no other.
pub(super) fn margin(ctx: &Ctx, sets: &[&Fitted]) -> Margin {
    let fixed = Margin {
        value: ctx.s.clear_margin,
        calibrated: None,
    };
    if sets.len() < 2 {
        return fixed;
    }
    let truth = &sets[0].joint.fit.model;
    let Ok(predicted) = predictions(truth, ctx.data) else {
        return fixed;
    };
    let mut excess: Vec<f64> = (0..DRAWS)
        .into_par_iter()
        .filter_map(|b| {
            let data = drawn(ctx.data, &predicted, b as u64)?;
            let keys: Vec<f64> = sets
                .iter()
                .map(|f| joint(ctx.model0, &f.members, &data, ctx.floor, ctx.s.likelihood))
                .map(|j| j.map(|j| j.key).ok().filter(|k| k.is_finite()))
                .collect::<Option<Vec<f64>>>()?;
            let best = keys.iter().copied().fold(f64::INFINITY, f64::min);
            Some(keys[0] - best)
        })
        .collect();
    if excess.len() < DRAWS / 2 {
        return fixed;
    }
    excess.sort_by(f64::total_cmp);
    // The empirical quantile (the smallest value with at least LEVEL of
    // the draws at or below it).
    let at = ((LEVEL * excess.len() as f64).ceil() as usize).clamp(1, excess.len()) - 1;
    let quantile = excess[at];
    Margin {
        value: quantile.max(ctx.s.clear_margin),
        calibrated: Some(Calibration {
            quantile,
            draws: excess.len(),
            candidates: sets.len(),
        }),
    }
}

/// Each case's predicted `(U, Omega_b)` under `model`.
fn predictions(
    model: &crate::model::Model,
    data: &Dataset,
) -> Result<Vec<(f64, f64)>, crate::model::ModelError> {
    data.cases
        .iter()
        .map(|c| model.predict(c).map(|p| (p.u_mm_s, p.omega_body_hz)))
        .collect()
}

/// `data` with every measured mean replaced by the prediction plus its
/// standard error times a Student-t draw (module docs, step 2).
fn drawn(data: &Dataset, predicted: &[(f64, f64)], draw: u64) -> Option<Dataset> {
    let mut rng = StdRng::seed_from_u64(SEED ^ draw.wrapping_mul(0x9e37_79b9_7f4a_7c15));
    let mut dofs = error_dofs(data).into_iter();
    let mut out = data.clone();
    for (c, &(u, w)) in out.cases.iter_mut().zip(predicted) {
        for (m, mean) in [(&mut c.u_mm_s, u), (&mut c.omega_body_hz, w)] {
            if let Some(m) = m.as_mut() {
                let t = StudentT::new(dofs.next()?).ok()?;
                resample(m, mean, t.sample(&mut rng));
            }
        }
    }
    Some(out)
}

fn resample(m: &mut Measured, mean: f64, t: f64) {
    m.mean = mean + m.standard_error() * t;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;

    /// The drawn means scatter about the model as the floor assumes: each
    /// residual in standard errors is Student-t with the trials' degrees of
    /// freedom (five trials: nu = 4, median |t| = 0.7407).
    #[test]
    fn drawn_means_scatter_about_the_model_as_student_t() {
        let data = crate::data::paper();
        let model = Model::base();
        let predicted = predictions(&model, &data).expect("the base model predicts");
        let mut t: Vec<f64> = Vec::new();
        for draw in 0..200 {
            let d = drawn(&data, &predicted, draw).expect("a draw");
            for (c, &(u, w)) in d.cases.iter().zip(&predicted) {
                for (m, p) in [(&c.u_mm_s, u), (&c.omega_body_hz, w)] {
                    if let Some(m) = m {
                        assert_eq!(m.trials, 5);
                        t.push(((m.mean - p) / m.standard_error()).abs());
                    }
                }
            }
        }
        t.sort_by(f64::total_cmp);
        let median = t[t.len() / 2];
        // 2400 draws: the sample median's standard error is about 0.02.
        assert!((median - 0.7407).abs() < 0.06, "median |t| = {median}");
    }

    /// The same draw gives the same data; another draw does not.
    #[test]
    fn draws_are_seeded() {
        let data = crate::data::paper();
        let predicted = predictions(&Model::base(), &data).expect("predicts");
        let mean = |d: &Dataset| d.cases[0].u_mm_s.expect("measured").mean;
        let a = drawn(&data, &predicted, 3).expect("a draw");
        let b = drawn(&data, &predicted, 3).expect("a draw");
        let c = drawn(&data, &predicted, 4).expect("a draw");
        assert_eq!(mean(&a), mean(&b));
        assert_ne!(mean(&a), mean(&c));
    }
}
