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
//! large one: one bad run cannot buy a law. `fit`, `diagnose` and `audit`
//! minimise it in every fit they make when given `--likelihood student-t`
//! ([`Likelihood`]; least squares is their default, so that they and the
//! page read the same statistics); `diagnose` ranks every candidate, law
//! and step by the AICc of the deviance it minimised ([`super::score`])
//! and requires every step to lower both the chi-square and `D_t` by its
//! charge; `fit`, `diagnose` and `audit` use the same test for a lone case.
//!
//! **A case stands alone** when, for a model:
//! (a) its residual is beyond the limit of the t model's one-bad-run test
//! at a false-alarm rate of 1 % per dataset ([`super::outlier`]: about 4
//! standard errors of the trial scatter the cases share, when they share
//! one), and
//! (a') the data are above the noise floor and the case's largest residual
//! is beyond the two-sided 1 % Student-t quantile of its own trials
//! (`t_{0.995, nu}` = 4.60 for five trials): the excess is this case's;
//! and in either case
//! (b) without that case the chi-square is at or below the noise floor of
//! the remaining quantities (the same quantile,
//! [`super::noise::chi2_noise_floor`]).
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

/// What a fit minimises, and how a residual is scored.
///
/// **Student-t** (`--likelihood student-t` of `fit`, `diagnose` and
/// `audit`): each normalised residual
/// is a Student-t variable with `nu` degrees of freedom, `nu = trials - 1`
/// of its own measurement unless stated; the objective is [`t_deviance`].
/// The t is chosen over Huber's loss because it is the residual's exact
/// sampling distribution when the model is right and the standard error
/// comes from `trials` Gaussian trials: its `nu` is read from the data, not
/// tuned (Huber's threshold would be a free choice). **Gaussian**: the
/// chi-square, the `nu -> inf` limit of the same deviance (the default
/// everywhere).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Likelihood {
    #[default]
    Gaussian,
    /// `nu = trials - 1` of each quantity.
    StudentT,
    /// The t with one stated `nu` for every quantity.
    StudentTWithNu(f64),
}

impl Likelihood {
    /// The degrees of freedom used for a quantity of `trials` trials
    /// (infinite for the Gaussian).
    pub fn nu(&self, trials: u32) -> f64 {
        match self {
            Likelihood::Gaussian => f64::INFINITY,
            Likelihood::StudentT => f64::from(trials.max(2) - 1),
            Likelihood::StudentTWithNu(nu) => *nu,
        }
    }

    /// The deviance of one residual `z` of a quantity with `trials` trials.
    pub fn deviance_one(&self, z: f64, trials: u32) -> f64 {
        let nu = self.nu(trials);
        if nu.is_infinite() {
            z * z
        } else {
            t_deviance_one(z, nu)
        }
    }

    /// The signed square root of [`Self::deviance_one`]: a least-squares
    /// solver minimising the sum of its squares minimises the deviance.
    /// Smooth through zero (`~ z sqrt((nu + 1)/nu)`).
    pub fn pseudo_residual(&self, z: f64, trials: u32) -> f64 {
        z.signum() * self.deviance_one(z, trials).sqrt()
    }

    /// `d pseudo_residual / d z`: the chain rule from the Jacobian of the
    /// residuals to that of the pseudo-residuals (1 for the Gaussian).
    pub fn pseudo_residual_slope(&self, z: f64, trials: u32) -> f64 {
        let nu = self.nu(trials);
        if nu.is_infinite() {
            return 1.0;
        }
        let d = t_deviance_one(z, nu);
        if d == 0.0 {
            ((nu + 1.0) / nu).sqrt()
        } else {
            (nu + 1.0) * z.abs() / ((nu + z * z) * d.sqrt())
        }
    }

    /// Its name in the reports.
    pub fn label(&self) -> String {
        match self {
            Likelihood::Gaussian => "Gaussian (chi-square)".into(),
            Likelihood::StudentT => "Student-t (nu = trials - 1)".into(),
            Likelihood::StudentTWithNu(nu) => format!("Student-t (nu = {nu})"),
        }
    }

    /// The expected deviance of one residual of a perfect model:
    /// `(nu + 1) (psi((nu + 1)/2) - psi(nu/2))` for the t (`ln(1 + T^2/nu)`
    /// of a t variable is a log-beta-prime variable), 1 for the Gaussian.
    pub fn expected_deviance_one(&self, trials: u32) -> f64 {
        use statrs::function::gamma::digamma;
        let nu = self.nu(trials);
        if nu.is_infinite() || nu > 1e6 {
            return 1.0;
        }
        (nu + 1.0) * (digamma(0.5 * (nu + 1.0)) - digamma(0.5 * nu))
    }

    /// The Fisher information of one residual about its location, in
    /// units of its standard error: `(nu + 1)/(nu + 3)` for the t, 1 for
    /// the Gaussian (Lange, Little & Taylor 1989, sec. 2).
    pub fn fisher_information_one(&self, trials: u32) -> f64 {
        let nu = self.nu(trials);
        if nu.is_infinite() {
            1.0
        } else {
            (nu + 1.0) / (nu + 3.0)
        }
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

/// The deviance of `lik` for `model` on `data` (the chi-square for the
/// Gaussian): what a fit under `lik` minimises.
pub fn deviance_of(model: &Model, data: &Dataset, lik: Likelihood) -> Result<f64, ModelError> {
    Ok(observations(model, data)?
        .iter()
        .map(|o| lik.deviance_one(o.z, o.trials))
        .sum())
}

/// A case that stands alone (module docs), with the numbers behind it.
#[derive(Debug, Clone, Serialize)]
pub struct LoneCase {
    pub case: String,
    /// `U` or `Omega_b`: its residual furthest beyond its limit.
    pub quantity: &'static str,
    /// That residual in the case's own standard errors.
    pub z: f64,
    /// The same residual in the standard errors it is judged in: pooled
    /// over the cases when they share one trial scatter, else its own.
    pub z_judged: f64,
    /// Whether `z_judged` is over a pooled standard error.
    pub pooled: bool,
    /// The limit `|z_judged|` exceeds.
    pub threshold: f64,
    /// `limit`: beyond the one-bad-run limit ([`super::outlier`]);
    /// `excess`: the data are above the noise floor only by this case
    /// (module docs, (a')).
    pub rule: &'static str,
    /// The false-alarm rate per dataset of the rule on a right model:
    /// the limit's (1 %), or the floor's (5 %) for `excess`.
    pub false_alarm: f64,
    pub chi2_reduced_with: f64,
    pub chi2_reduced_without: f64,
    /// The noise floor (reduced) of the quantities without the case.
    pub floor_reduced_without: f64,
}

impl LoneCase {
    /// One sentence for the terminal and the audit.
    pub fn sentence(&self) -> String {
        let limit = |z: String| {
            format!(
                "{z}, beyond the limit {:.2} that a right model exceeds somewhere in {} % of datasets",
                self.threshold,
                100.0 * self.false_alarm
            )
        };
        let why = match (self.rule, self.pooled) {
            ("excess", _) => format!(
                "{:.1} of its own standard errors off, beyond the 1 % Student-t quantile {:.2} of its trials, and the data are above the noise floor by this case alone",
                self.z, self.threshold
            ),
            (_, true) => limit(format!(
                "{:.1} standard errors of the trial scatter the cases share off ({:.1} of its own)",
                self.z_judged, self.z
            )),
            _ => limit(format!("{:.1} of its own standard errors off", self.z)),
        };
        format!(
            "one case stands out: {}'s {} is {why}; without it the model fits the other cases to the noise (reduced chi-square {} -> {}, floor {}): check this case's record or re-measure it",
            self.case,
            self.quantity,
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
    let judged = super::outlier::judge(obs, data, super::outlier::FALSE_ALARM);
    let chi2: f64 = obs.iter().map(|o| o.z * o.z).sum();
    let (worst, rule, false_alarm) = match super::outlier::worst_beyond(&judged) {
        Some(w) => (w, "limit", super::outlier::FALSE_ALARM),
        None => (excess_case(obs, chi2, data, level)?, "excess", 1.0 - level),
    };
    let bad = worst.obs.case;
    let without: f64 = obs
        .iter()
        .filter(|o| o.case != bad)
        .map(|o| o.z * o.z)
        .sum();
    let mut rest = data.clone();
    rest.cases.remove(bad);
    let n_rest = obs.iter().filter(|o| o.case != bad).count();
    let floor_rest = chi2_noise_floor(&error_dofs(&rest), 0, level)?;
    (without <= floor_rest).then(|| LoneCase {
        case: data.cases[bad].id.clone(),
        quantity: worst.obs.quantity.label(),
        z: worst.obs.z,
        z_judged: worst.z,
        pooled: worst.pooled,
        threshold: worst.limit,
        rule,
        false_alarm,
        chi2_reduced_with: chi2 / n as f64,
        chi2_reduced_without: without / n_rest.max(1) as f64,
        floor_reduced_without: floor_rest / n_rest.max(1) as f64,
    })
}

/// Rule (a'): the data are above the floor and the largest residual is
/// beyond the two-sided 1 % Student-t quantile of its own trials.
fn excess_case(
    obs: &[Obs],
    chi2: f64,
    data: &Dataset,
    level: f64,
) -> Option<super::outlier::Judged> {
    let big = obs.iter().max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))?;
    let threshold = crate::stats::student_t_quantile(0.99, big.trials);
    if big.z.abs() <= threshold || chi2 <= chi2_noise_floor(&error_dofs(data), 0, level)? {
        return None;
    }
    Some(super::outlier::Judged {
        obs: *big,
        z: big.z,
        limit: threshold,
        pooled: false,
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
    fn the_gaussian_is_the_limit_of_the_t_likelihood() {
        let (g, t) = (Likelihood::Gaussian, Likelihood::StudentTWithNu(1e9));
        for z in [0.1, 1.0, 3.0, -6.0] {
            assert!((g.deviance_one(z, 5) - t.deviance_one(z, 5)).abs() < 1e-6 * z * z);
            assert!((g.pseudo_residual(z, 5) - t.pseudo_residual(z, 5)).abs() < 1e-6);
        }
        assert_eq!(Likelihood::StudentT.nu(5), 4.0);
        // The slope is the derivative of the pseudo-residual, through zero too.
        for z in [-7.0, -0.3, 0.0, 1e-9, 2.5] {
            let l = Likelihood::StudentT;
            let h = 1e-6;
            let num = (l.pseudo_residual(z + h, 5) - l.pseudo_residual(z - h, 5)) / (2.0 * h);
            assert!((num - l.pseudo_residual_slope(z, 5)).abs() < 1e-6, "{z}");
        }
        assert!((t.fisher_information_one(5) - 1.0).abs() < 1e-8);
        assert!((t.expected_deviance_one(5) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn the_expected_t_deviance_is_its_mean_under_the_t() {
        // Monte Carlo mean of (nu + 1) ln(1 + T^2/nu) for T ~ t_4 against
        // the digamma formula.
        use rand::SeedableRng;
        use rand_distr::{Distribution, StudentT};
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let t = StudentT::new(4.0).unwrap();
        let m: f64 = (0..200_000)
            .map(|_| t_deviance_one(t.sample(&mut rng), 4.0))
            .sum::<f64>()
            / 200_000.0;
        let e = Likelihood::StudentT.expected_deviance_one(5);
        assert!((m - e).abs() < 0.01, "{m} {e}");
        assert!((e - 1.402).abs() < 0.001, "{e}");
    }
}
