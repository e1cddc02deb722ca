//! The response table: how each measured quantity of each case answers a
//! change at each place of the model, computed once per diagnosis.
//!
//! A correction at one place changes one number per case (a multiplier `m`
//! or a load), so a case's predicted U and Omega_b are one-dimensional
//! functions of it. The table samples them once:
//!
//! - multiplier places: on a uniform grid in `ln m` over
//!   `[ln MIN_MULTIPLIER, ln 50]` (81 points, step 0.106), read back by
//!   cubic Catmull-Rom interpolation (error O(h^3), below 1e-3 relative on
//!   the paper's cases: see the unit test; the exact refits do not use it);
//!   outside the grid the end value;
//! - load places: the force balance (eq. 11) is linear in the load, so the
//!   answer is exactly `y0 + s load`, with `s` from one extra solve.
//!
//! Every candidate law is then scored by arithmetic on the table, with no
//! model solve: a few hundred candidates cost less than one pass of exact
//! fits. The best few are refitted with the real model afterwards.

use crate::data::Dataset;
use crate::effects::correction::{Form, LocatedCorrection, MIN_MULTIPLIER};
use crate::effects::place::Place;
use crate::effects::EffectInstance;
use crate::model::{Model, ModelError};
use crate::workbench::compare::case_residuals;
use rayon::prelude::*;

const GRID: usize = 81;
const LN_MAX: f64 = 3.912_023_005_428_146; // ln 50

fn ln_min() -> f64 {
    MIN_MULTIPLIER.ln()
}

fn step() -> f64 {
    (LN_MAX - ln_min()) / (GRID - 1) as f64
}

/// One measured quantity of one case.
#[derive(Debug, Clone, Copy)]
pub struct Obs {
    pub case: usize,
    pub observed: f64,
    pub sigma: f64,
}

enum Response {
    /// `y[obs * GRID + g]` at `ln m = ln_min + g h`.
    Grid(Vec<f64>),
    /// `dy / d load` per observation (load in mN or µN m).
    Linear(Vec<f64>),
}

/// The table for one model on one dataset.
pub struct Table {
    pub obs: Vec<Obs>,
    /// Predictions of the unchanged model, per observation.
    pub base: Vec<f64>,
    responses: Vec<(Place, Response)>,
    /// Per load place: the median load that doubles or cancels a prediction.
    load_scales: Vec<(Place, f64)>,
}

/// The model with a constant correction at `place` (built once per place
/// and build; the value is set in the instance).
fn with_value(model: &Model, place: Place, v: f64) -> Model {
    let c = LocatedCorrection::new(place, None, Form::Constant, 1.0, 1.0)
        .expect("a constant fits every place");
    model.clone().with_effect(EffectInstance {
        effect: std::sync::Arc::new(c).into(),
        values: vec![v],
    })
}

fn set_value(m: &mut Model, v: f64) {
    m.effects.last_mut().expect("with_value added it").values[0] = v;
}

pub(super) fn predictions(model: &Model, data: &Dataset) -> Result<Vec<f64>, ModelError> {
    let mut out = Vec::new();
    for case in &data.cases {
        let p = model.predict(case)?;
        out.extend(
            case_residuals(case, &p)
                .into_iter()
                .map(|(_, r)| r.predicted),
        );
    }
    Ok(out)
}

impl Table {
    /// Build the table of `model` on `data` (parallel over places).
    pub fn build(model: &Model, data: &Dataset) -> Result<Table, ModelError> {
        let mut obs = Vec::new();
        for (i, case) in data.cases.iter().enumerate() {
            let p = model.predict(case)?;
            obs.extend(case_residuals(case, &p).into_iter().map(|(_, r)| Obs {
                case: i,
                observed: r.observed,
                sigma: r.sigma,
            }));
        }
        let base = predictions(model, data)?;
        let responses: Vec<(Place, Response)> = Place::ALL
            .par_iter()
            .map(|&place| -> Result<(Place, Response), ModelError> {
                if place.is_additive() {
                    let y1 = predictions(&with_value(model, place, 1.0), data)?;
                    let s = y1.iter().zip(&base).map(|(a, b)| a - b).collect();
                    return Ok((place, Response::Linear(s)));
                }
                let mut y = vec![0.0; base.len() * GRID];
                let mut probe = with_value(model, place, 1.0);
                for g in 0..GRID {
                    set_value(&mut probe, (ln_min() + g as f64 * step()).exp());
                    let yg = predictions(&probe, data)?;
                    for (o, v) in yg.into_iter().enumerate() {
                        y[o * GRID + g] = v;
                    }
                }
                Ok((place, Response::Grid(y)))
            })
            .collect::<Result<_, _>>()?;
        let load_scales = responses
            .iter()
            .filter_map(|(p, r)| match r {
                Response::Linear(s) => {
                    let mut v: Vec<f64> = s
                        .iter()
                        .zip(&base)
                        .map(|(s, y)| (y / s).abs())
                        .filter(|x| x.is_finite() && *x > 0.0)
                        .collect();
                    v.sort_by(f64::total_cmp);
                    Some((*p, v.get(v.len() / 2).copied().unwrap_or(1.0)))
                }
                Response::Grid(_) => None,
            })
            .collect();
        Ok(Table {
            obs,
            base,
            responses,
            load_scales,
        })
    }

    /// The typical load at a load place (1 elsewhere).
    pub fn load_scale(&self, place: Place) -> f64 {
        self.load_scales
            .iter()
            .find(|(p, _)| *p == place)
            .map_or(1.0, |x| x.1)
    }

    /// Whether a change at `place` moves any prediction at all (the
    /// local-drag places do not with a non-local tail model).
    pub fn is_sensitive(&self, place: Place) -> bool {
        let scale = self.base.iter().map(|y| y.abs()).fold(0.0, f64::max);
        match self.response(place) {
            Response::Linear(s) => s.iter().any(|x| x.abs() > 1e-9 * scale.max(1e-300)),
            Response::Grid(y) => (0..self.obs.len()).any(|o| {
                let row = &y[o * GRID..(o + 1) * GRID];
                (row[0] - row[GRID - 1]).abs() > 1e-9 * scale.max(1e-300)
            }),
        }
    }

    fn response(&self, place: Place) -> &Response {
        &self
            .responses
            .iter()
            .find(|(p, _)| *p == place)
            .expect("every place is tabulated")
            .1
    }

    /// The predicted value of observation `o` when the place's value is `v`.
    pub fn predict(&self, place: Place, o: usize, v: f64) -> f64 {
        match self.response(place) {
            Response::Linear(s) => self.base[o] + s[o] * v,
            Response::Grid(y) => interpolate(&y[o * GRID..(o + 1) * GRID], v),
        }
    }

    /// Normalised residuals of a correction with parameters `p`, given its
    /// scaled feature per case, on the observations `subset`.
    pub fn residuals_into(
        &self,
        c: &LocatedCorrection,
        p: &[f64],
        feature: &CaseFeature,
        subset: &[usize],
        out: &mut Vec<f64>,
    ) {
        out.clear();
        let resp = self.response(c.place);
        // A multiplier power law `k x^q` with k > 0 is a straight line in
        // `ln m`: its grid position needs neither `powf` nor `ln`.
        let ln_line = (matches!(resp, Response::Grid(_)) && c.form == Form::PowerLaw && p[0] > 0.0)
            .then(|| p[0].ln());
        // A case's quantities sit next to each other in `obs` and share one
        // law value (or grid position).
        let mut last: Option<(usize, f64)> = None;
        for &o in subset {
            let ob = self.obs[o];
            let v = match last {
                Some((case, v)) if case == ob.case => v,
                _ => {
                    let (x, ln_x) = (feature.x[ob.case], feature.ln_x[ob.case]);
                    let v = match (resp, ln_line) {
                        (Response::Linear(_), _) => c.law_with_ln(p, x, ln_x),
                        (Response::Grid(_), Some(ln_k)) => to_grid(ln_k + p[1] * ln_x),
                        (Response::Grid(_), None) => {
                            to_grid(c.law_with_ln(p, x, ln_x).max(MIN_MULTIPLIER).ln())
                        }
                    };
                    last = Some((ob.case, v));
                    v
                }
            };
            let y = match resp {
                Response::Linear(s) => self.base[o] + s[o] * v,
                Response::Grid(y) => at_position(&y[o * GRID..(o + 1) * GRID], v),
            };
            out.push((y - ob.observed) / ob.sigma);
        }
    }
}

/// A law's scaled feature on every case, with its logarithm: the screen
/// evaluates each law tens of times, and `x^q` as `exp(q ln x)` saves a
/// `powf` per case and evaluation.
#[derive(Debug, Clone)]
pub struct CaseFeature {
    pub x: Vec<f64>,
    ln_x: Vec<f64>,
}

impl CaseFeature {
    pub fn new(x: Vec<f64>) -> CaseFeature {
        let ln_x = x.iter().map(|v| v.ln()).collect();
        CaseFeature { x, ln_x }
    }
}

/// Catmull-Rom interpolation of a row sampled on the `ln m` grid.
fn interpolate(row: &[f64], m: f64) -> f64 {
    at_position(row, to_grid(m.ln()))
}

/// Where `ln m` falls on the grid, in grid steps (clamped to its ends: a
/// multiplier below the floor reads the floor's row).
fn to_grid(ln_m: f64) -> f64 {
    ((ln_m - ln_min()) / step()).clamp(0.0, (GRID - 1) as f64)
}

/// A row's Catmull-Rom value at grid position `t`.
fn at_position(row: &[f64], t: f64) -> f64 {
    if t.is_nan() {
        return f64::NAN;
    }
    // `t` is in [0, GRID - 1] (`to_grid`), where truncation is the floor;
    // `f64::floor` is a libm call on the baseline x86-64 target, once per
    // screened case.
    let i = (t as usize).min(GRID - 2);
    let u = t - i as f64;
    let p1 = row[i];
    let p2 = row[i + 1];
    let p0 = if i > 0 { row[i - 1] } else { 2.0 * p1 - p2 };
    let p3 = if i + 2 < GRID {
        row[i + 2]
    } else {
        2.0 * p2 - p1
    };
    let (u2, u3) = (u * u, u * u * u);
    0.5 * ((2.0 * p1)
        + (-p0 + p2) * u
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * u2
        + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * u3)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::Effect;

    #[test]
    fn the_table_matches_the_model_between_grid_points_and_loads_are_linear() {
        let data = crate::data::paper();
        let model = Model::base();
        let t = Table::build(&model, &data).unwrap();
        let mut worst: f64 = 0.0;
        for place in Place::ALL {
            for v in [0.37, 0.93, 1.71, 6.3] {
                let exact = predictions(&with_value(&model, place, v), &data).unwrap();
                for (o, y) in exact.iter().enumerate() {
                    let rel = (t.predict(place, o, v) - y).abs() / y.abs();
                    worst = worst.max(rel);
                }
            }
        }
        assert!(worst < 1e-3, "worst relative interpolation error {worst}");
        eprintln!("worst relative interpolation error {worst:.2e}");
        assert!(t.is_sensitive(Place::DriveRate) && t.is_sensitive(Place::LoadTorque));
    }

    /// The screen's evaluation (per case once, powers as `exp(q ln x)`, a
    /// multiplier power law straight in `ln m`) reads the same residuals as
    /// the law written out and interpolated quantity by quantity.
    #[test]
    fn residuals_match_the_law_evaluated_per_quantity() {
        let data = crate::data::paper();
        let t = Table::build(&Model::base(), &data).unwrap();
        let q = crate::data::quantities::by_id("pitch_angle_deg").unwrap();
        let all: Vec<usize> = (0..t.obs.len()).collect();
        let mut worst: f64 = 0.0;
        for place in [Place::BodyRotation, Place::TailTorque, Place::LoadForce] {
            for form in Form::ALL.into_iter().filter(|f| f.fits(place)) {
                let feature = form
                    .needs_feature()
                    .then_some(crate::data::Feature::Quantity(q));
                let c = LocatedCorrection::new(place, feature, form, 60.0, 1.0).unwrap();
                let f = CaseFeature::new(data.cases.iter().map(|k| c.x(k)).collect());
                for p in [[0.8, 2.3], [1.7, -1.1], [-0.4, 0.5], [1e-4, 3.0]] {
                    let p = &p[..c.params().len()];
                    let mut fast = Vec::new();
                    t.residuals_into(&c, p, &f, &all, &mut fast);
                    for (&o, r) in all.iter().zip(&fast) {
                        let ob = t.obs[o];
                        let v = c.law(p, f.x[ob.case]);
                        let y = match t.response(place) {
                            Response::Linear(s) => t.base[o] + s[o] * v,
                            Response::Grid(y) => {
                                interpolate(&y[o * GRID..(o + 1) * GRID], v.max(MIN_MULTIPLIER))
                            }
                        };
                        let slow = (y - ob.observed) / ob.sigma;
                        worst = worst.max((r - slow).abs() / slow.abs().max(1.0));
                    }
                }
            }
        }
        assert!(worst < 1e-9, "worst relative difference {worst:e}");
    }
}
