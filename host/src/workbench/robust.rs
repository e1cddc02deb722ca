//! The robust likelihood: residuals judged as Student-t variables.
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
//! charge.
//!
//! The bad runs a model names, judged in this likelihood, are
//! [`super::data_quality::bad_runs`]'s.
//!
//! References: K. L. Lange, R. J. A. Little & J. M. G. Taylor, "Robust
//! statistical modeling using the t distribution", J. Am. Stat. Assoc. 84
//! (1989) 881; P. J. Huber & E. M. Ronchetti, *Robust Statistics*, 2nd ed.
//! (2009), ch. 4.

use super::compare::{case_residuals, Quantity};
use crate::data::{Case, Dataset};
use crate::model::{Model, ModelError};
use rayon::prelude::*;

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
