//! The robust likelihood: residuals judged as Student-t variables, and the
//! test for a single case that stands alone.
//!
//! A residual divided by a standard error estimated from `n` trials is
//! Student-t with `nu = n - 1` degrees of freedom ([`super::noise`]), so
//! its honest likelihood is the t density, not the normal one. Its
//! deviance (minus twice the log-likelihood, up to a constant) is
//!
//! `D_t = sum (nu + 1) ln(1 + z^2 / nu)`,
//!
//! which grows like `z^2` for small residuals and only like `ln z` for a
//! large one: one bad run cannot buy a law. `diagnose` requires every step
//! to lower both the chi-square and `D_t` by its charge; `fit` and `audit`
//! use the same test for a lone case.
//!
//! **A case stands alone** (the stated threshold) when, for a model:
//! (a) the chi-square on all cases is above the noise floor,
//! (b) without that one case it is at or below the floor of the remaining
//! quantities (the same quantile, [`super::noise::chi2_noise_floor`]), and
//! (c) its largest residual is beyond the two-sided 1 % Student-t quantile
//! of its trials (`t_{0.995, nu}`: 4.60 for five trials).
//! Then no effect is needed for the other cases, and the one case is what
//! to check or re-measure.
//!
//! References: K. L. Lange, R. J. A. Little & J. M. G. Taylor, "Robust
//! statistical modeling using the t distribution", J. Am. Stat. Assoc. 84
//! (1989) 881; P. J. Huber & E. M. Ronchetti, *Robust Statistics*, 2nd ed.
//! (2009), ch. 4.

use super::compare::{case_residuals, Quantity};
use super::noise::{chi2_noise_floor, error_dofs};
use crate::data::{Case, Dataset};
use crate::model::{Model, ModelError};
use rayon::prelude::*;
use serde::Serialize;

/// Per-quantity two-sided level of condition (c): 1 %.
pub const LONE_CASE_CONFIDENCE: f64 = 0.99;

/// One normalised residual with its degrees of freedom.
#[derive(Debug, Clone, Copy)]
pub struct Obs {
    pub case: usize,
    pub quantity: Quantity,
    pub z: f64,
    pub trials: u32,
}

impl Obs {
    fn nu(&self) -> f64 {
        f64::from(self.trials.max(2) - 1)
    }
}

/// The normalised residuals of `model` on every measured quantity.
pub fn observations(model: &Model, data: &Dataset) -> Result<Vec<Obs>, ModelError> {
    let per_case: Vec<Vec<Obs>> = data
        .cases
        .par_iter()
        .enumerate()
        .map(|(i, c)| {
            let p = model.predict(c)?;
            Ok(case_residuals(c, &p)
                .into_iter()
                .map(|(q, r)| Obs {
                    case: i,
                    quantity: q,
                    z: r.normalised(),
                    trials: trials_of(c, q),
                })
                .collect())
        })
        .collect::<Result<_, ModelError>>()?;
    Ok(per_case.into_iter().flatten().collect())
}

fn trials_of(c: &Case, q: Quantity) -> u32 {
    match q {
        Quantity::U => c.u_mm_s.map_or(2, |m| m.trials),
        Quantity::Omega => c.omega_body_hz.map_or(2, |m| m.trials),
    }
}

/// The Student-t deviance of one residual: `(nu + 1) ln(1 + z^2/nu)`.
pub fn t_deviance_one(z: f64, nu: f64) -> f64 {
    (nu + 1.0) * (z * z / nu).ln_1p()
}

/// The Student-t deviance of a set of residuals (module docs).
pub fn t_deviance(obs: &[Obs]) -> f64 {
    obs.iter().map(|o| t_deviance_one(o.z, o.nu())).sum()
}

/// The Student-t deviance of `model` on `data`.
pub fn t_deviance_of(model: &Model, data: &Dataset) -> Result<f64, ModelError> {
    Ok(t_deviance(&observations(model, data)?))
}

/// A case that stands alone (module docs), with the numbers behind it.
#[derive(Debug, Clone, Serialize)]
pub struct LoneCase {
    pub case: String,
    /// `U` or `Omega_b`: its largest residual.
    pub quantity: &'static str,
    /// That residual in standard errors.
    pub z: f64,
    /// The Student-t threshold it exceeds, `t_{0.995, nu}`.
    pub threshold: f64,
    pub chi2_reduced_with: f64,
    pub chi2_reduced_without: f64,
    /// The noise floor (reduced) of the quantities without the case.
    pub floor_reduced_without: f64,
}

impl LoneCase {
    /// One sentence for the terminal and the audit.
    pub fn sentence(&self) -> String {
        format!(
            "one case stands out: {}'s {} is {:.1} standard errors off (beyond the Student-t threshold {:.2}); without it the model fits the other cases to the noise (reduced chi-square {} -> {}, floor {}): check this case's record or re-measure it",
            self.case,
            self.quantity,
            self.z,
            self.threshold,
            crate::format::fmt_sig(self.chi2_reduced_with, 3),
            crate::format::fmt_sig(self.chi2_reduced_without, 3),
            crate::format::fmt_sig(self.floor_reduced_without, 3)
        )
    }
}

/// The case that stands alone under `model`, if one does; `level` is the
/// noise floor's quantile (0.95 in every command).
pub fn lone_case(
    model: &Model,
    data: &Dataset,
    level: f64,
) -> Result<Option<LoneCase>, ModelError> {
    let obs = observations(model, data)?;
    Ok(lone_case_of(&obs, data, level))
}

/// [`lone_case`] from residuals already computed.
pub fn lone_case_of(obs: &[Obs], data: &Dataset, level: f64) -> Option<LoneCase> {
    let n = obs.len();
    if n < 3 || data.cases.len() < 3 {
        return None;
    }
    let chi2: f64 = obs.iter().map(|o| o.z * o.z).sum();
    let floor_all = chi2_noise_floor(&error_dofs(data), 0, level)?;
    if chi2 <= floor_all {
        return None;
    }
    // The case contributing most is the only one whose removal can do
    // more than any other's.
    let mut per_case = vec![0.0; data.cases.len()];
    for o in obs {
        per_case[o.case] += o.z * o.z;
    }
    let (worst, share) = per_case
        .iter()
        .copied()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let big = obs
        .iter()
        .filter(|o| o.case == worst)
        .max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))?;
    let threshold = crate::stats::student_t_quantile(LONE_CASE_CONFIDENCE, big.trials);
    if big.z.abs() <= threshold {
        return None;
    }
    // The floor of a subset of the quantities is below the whole set's:
    // when even that is exceeded without the case, skip the Monte Carlo.
    if chi2 - share > floor_all {
        return None;
    }
    let mut rest = data.clone();
    rest.cases.remove(worst);
    let n_rest = obs.iter().filter(|o| o.case != worst).count();
    let floor_rest = chi2_noise_floor(&error_dofs(&rest), 0, level)?;
    let without = chi2 - share;
    (without <= floor_rest).then(|| LoneCase {
        case: data.cases[worst].id.clone(),
        quantity: big.quantity.label(),
        z: big.z,
        threshold,
        chi2_reduced_with: chi2 / n as f64,
        chi2_reduced_without: without / n_rest.max(1) as f64,
        floor_reduced_without: floor_rest / n_rest.max(1) as f64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_t_deviance_is_quadratic_near_zero_and_logarithmic_far_out() {
        let nu = 4.0;
        // (nu + 1)/nu z^2 for small z: the t density's curvature at 0.
        let small = t_deviance_one(1e-3, nu);
        assert!((small / 1e-6 - 1.25).abs() < 1e-3, "{small}");
        // From 10 to 100 standard errors the normal deviance grows 100-fold,
        // the t deviance by about 2 (nu + 1) ln 10 only.
        let (a, b) = (t_deviance_one(10.0, nu), t_deviance_one(100.0, nu));
        assert!((b - a - 10.0 * 10f64.ln()).abs() < 0.5, "{a} {b}");
        // Many degrees of freedom: the normal deviance.
        assert!((t_deviance_one(2.0, 1e6) - 4.0).abs() < 1e-4);
    }

    #[test]
    fn the_threshold_for_five_trials_is_the_stated_one() {
        let t = crate::stats::student_t_quantile(LONE_CASE_CONFIDENCE, 5);
        assert!((t - 4.604).abs() < 0.01, "{t}");
    }
}
