//! Where the model fails: relative residuals against the library of case
//! quantities ([`crate::data::quantities::FEATURES`]: amplitude against body
//! radius, number of waves, pitch angle, gap ratios of tail and body to the
//! wall, L_t/D_ch, f, the wire's shear rate, ...). A strong correlation
//! points at the physics that depends on that feature; the located search
//! ([`super::discovery`]) then tests laws in it at each place of the model.
//! Recorded setup fields and their groups (viscosity, Reynolds number, ...)
//! are in the library when they vary in the data and are not a monotone
//! function of a feature already in it; so are the lab's recorded numbers
//! ([`crate::data::recorded`]: the oil's temperature, ...) and, when the
//! cases carry them (`diagnose` attaches them once:
//! [`crate::model::columns`]), the model's own quantities (load torque,
//! thrust, drag, power, predicted U and Omega_b, Reynolds numbers:
//! [`crate::data::model_quantities`]), so that an error which follows the
//! load shows as a trend in the load.

use super::compare::{Comparison, Quantity};
use crate::data::{Case, Dataset};
use serde::Serialize;
use std::borrow::Cow;

pub use crate::data::quantities::FEATURES;

/// Correlation of one quantity's relative residual with one feature.
#[derive(Debug, Clone, Serialize)]
pub struct Trend {
    pub quantity: Quantity,
    /// The feature's formula in the paper's symbols, or a recorded
    /// variable's name with `(recorded)`.
    pub feature: Cow<'static, str>,
    /// Its id in [`crate::data::quantities`], or the recorded name.
    pub feature_id: Cow<'static, str>,
    /// Pearson correlation over the cases.
    pub r: f64,
    /// Least-squares slope of the relative error per unit feature.
    pub slope: f64,
}

/// Every (quantity, feature) trend, strongest first; features that do not
/// vary across the cases are left out.
pub fn trends(data: &Dataset, cmp: &Comparison) -> Vec<Trend> {
    let mut out = Vec::new();
    for q in [Quantity::U, Quantity::Omega] {
        let pts: Vec<(usize, f64)> = cmp
            .cases
            .iter()
            .enumerate()
            .filter_map(|(i, k)| match q {
                Quantity::U => k.u().rel_err.map(|e| (i, e)),
                Quantity::Omega => k.omega().rel_err.map(|e| (i, e)),
            })
            .collect();
        if pts.len() < 3 {
            continue;
        }
        let ys: Vec<f64> = pts.iter().map(|(_, e)| *e).collect();
        // The library's quantities, then every recorded number (also one
        // the search cannot use: a column zero on some case, say).
        let library = super::discovery::search::usable_features(data)
            .into_iter()
            .filter_map(|u| u.feature.quantity())
            .map(|f| {
                (
                    Cow::from(f.name),
                    Cow::from(f.id),
                    column(data, |c| f.of(c)),
                )
            });
        let recorded = crate::data::recorded::features(data)
            .into_iter()
            .map(|(id, xs)| (Cow::from(format!("{id} (recorded)")), Cow::from(id), xs));
        for (feature, feature_id, all) in library.chain(recorded) {
            let xs: Vec<f64> = pts.iter().map(|(i, _)| all[*i]).collect();
            if let Some((r, slope)) = pearson(&xs, &ys) {
                out.push(Trend {
                    quantity: q,
                    feature,
                    feature_id,
                    r,
                    slope,
                });
            }
        }
    }
    out.sort_by(|a, b| b.r.abs().total_cmp(&a.r.abs()));
    out
}

fn column(data: &Dataset, f: impl Fn(&Case) -> f64) -> Vec<f64> {
    data.cases.iter().map(f).collect()
}

fn pearson(x: &[f64], y: &[f64]) -> Option<(f64, f64)> {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|v| (v - mx).powi(2)).sum();
    let syy: f64 = y.iter().map(|v| (v - my).powi(2)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    if sxx <= 1e-12 * mx.abs().max(1.0).powi(2) * n || syy == 0.0 {
        return None;
    }
    Some((sxy / (sxx * syy).sqrt(), sxy / sxx))
}
