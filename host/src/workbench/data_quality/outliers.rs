//! Several bad runs: which measured quantities are beyond what the
//! Student-t model allows, found by the generalized extreme studentized
//! deviate procedure (Rosner 1983) at a stated false-alarm rate per
//! dataset.
//!
//! **Statistic.** Under the t likelihood ([`crate::workbench::robust`]) the
//! likelihood ratio of "quantity `i` carries its own offset" against "it
//! does not" is `(nu + 1) ln(1 + z_i^2 / nu)`, monotone in `|z_i|`: each
//! step's statistic is the largest `|z|` left, and under a right model each
//! `|z|` is `|T_nu|`.
//!
//! **Scale.** A residual over its own standard error, estimated from five
//! trials, is `T_4`: so heavy-tailed that, over 84 quantities, the
//! family-wise 1 % limit is about 11 standard errors and a run 6 off is
//! never told from noise. When the cases of one quantity (`U` or
//! `Omega_b`) share one relative trial scatter, which Bartlett's test
//! checks (it is kept unless rejected at [`HOMOGENEITY_LEVEL`]), that
//! scatter is estimated from all of them, `s_p^2 = sum nu_i s_i^2 / sum
//! nu_i` (`s_i` the relative standard deviation of one trial), and each
//! residual is judged against `s_p |obs_i| / sqrt(n_i)` with
//! `nu_p = sum nu_i` degrees of freedom: nearly normal, the limit falls to
//! about 4. When the scatter is not common, each quantity keeps its own
//! standard error and `nu_i`.
//!
//! **Several runs (generalized ESD).** Step `j = 1..r_max` takes the
//! quantity furthest beyond its limit among those not yet taken; the limit
//! of step `j` is the two-sided t quantile at the Šidák level
//! `(1 - alpha)^{1/(N - j + 1)}` for the `N - j + 1` quantities left. The
//! number of bad runs is the LAST step whose quantity is beyond its limit,
//! and every quantity taken up to it is named: a second bad run cannot
//! mask the first (Rosner's reason for testing down from `r_max`, not up
//! from one). Rosner's limits are for a scale estimated from the residuals
//! themselves; here the scale comes from the trials, independent of the
//! residuals, so each step's limit is that of the largest of `N - j + 1`
//! t variables. `r_max` = [`MAX_BAD_RUNS`], at most a tenth of the
//! quantities: more than that is not a few bad runs but intervals that are
//! wrong or an effect the model misses ([`super::intervals`]).
//!
//! **False alarms.** A right model has one run or more named in about
//! `alpha` = [`FALSE_ALARM`] (1 %) of datasets (`host/tests/data_quality.rs`
//! measures it over drawn null datasets).
//!
//! References: B. Rosner, Technometrics 25 (1983) 165 (generalized ESD);
//! M. S. Bartlett, Proc. R. Soc. A 160 (1937) 268 (homogeneity of
//! variances); Z. Šidák, J. Am. Stat. Assoc. 62 (1967) 626; K. L. Lange,
//! R. J. A. Little & J. M. G. Taylor, J. Am. Stat. Assoc. 84 (1989) 881.

use crate::data::{Case, Dataset};
use crate::workbench::compare::Quantity;
use crate::workbench::robust::Obs;
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The stated false-alarm rate per dataset of the bad-run test (1 %).
pub const FALSE_ALARM: f64 = 0.01;

/// Bartlett's test rejects a common scatter below this p-value (1 %).
pub const HOMOGENEITY_LEVEL: f64 = 0.01;

/// The most bad runs the test names (module docs, `r_max`).
pub const MAX_BAD_RUNS: usize = 5;

/// How one quantity kind's residuals are scaled.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Scale {
    /// The pooled relative standard deviation of one trial, and its dof.
    Pooled { rel_sd: f64, nu: f64 },
    /// Each quantity's own standard error.
    Own,
}

/// One measurement's relative standard deviation of one trial, its trials.
fn rel_trial_sd(c: &Case, q: Quantity) -> Option<(f64, u32)> {
    let m = match q {
        Quantity::U => c.u_mm_s,
        Quantity::Omega => c.omega_body_hz,
    }?;
    let n = m.trials.max(2);
    let s = m.standard_error() * f64::from(n).sqrt() / m.mean.abs();
    (s.is_finite() && s > 0.0).then_some((s, n))
}

/// Bartlett's p-value for equal variances `s^2` with `nu` dof each.
pub fn bartlett_p(sd_nu: &[(f64, f64)]) -> Option<f64> {
    let k = sd_nu.len();
    if k < 2 {
        return None;
    }
    let nu_p: f64 = sd_nu.iter().map(|p| p.1).sum();
    let pooled = sd_nu.iter().map(|(s, nu)| nu * s * s).sum::<f64>() / nu_p;
    let m = nu_p * pooled.ln() - sd_nu.iter().map(|(s, nu)| nu * (s * s).ln()).sum::<f64>();
    let inv: f64 = sd_nu.iter().map(|p| 1.0 / p.1).sum();
    let c = 1.0 + (inv - 1.0 / nu_p) / (3.0 * (k as f64 - 1.0));
    let chi = ChiSquared::new(k as f64 - 1.0).ok()?;
    Some(chi.sf(m / c))
}

/// The scale of quantity kind `q` on `data` (module docs).
pub fn scale_of(data: &Dataset, q: Quantity) -> Scale {
    let sd_nu: Vec<(f64, f64)> = data
        .cases
        .iter()
        .filter_map(|c| rel_trial_sd(c, q))
        .map(|(s, n)| (s, f64::from(n - 1)))
        .collect();
    match bartlett_p(&sd_nu) {
        Some(p) if p >= HOMOGENEITY_LEVEL => {
            let nu: f64 = sd_nu.iter().map(|p| p.1).sum();
            let var = sd_nu.iter().map(|(s, n)| n * s * s).sum::<f64>() / nu;
            Scale::Pooled {
                rel_sd: var.sqrt(),
                nu,
            }
        }
        _ => Scale::Own,
    }
}

/// A residual judged for the bad-run test: in the scale's standard
/// errors, with the limit it must exceed.
#[derive(Debug, Clone, Copy)]
pub struct Judged {
    pub obs: Obs,
    /// The residual in pooled (or own) standard errors.
    pub z: f64,
    pub limit: f64,
    pub pooled: bool,
    /// The degrees of freedom of the scale it is judged in.
    pub nu: f64,
}

/// The two-sided t quantile at the Šidák level for `n` quantities.
pub fn limit(nu: f64, n: usize, alpha: f64) -> f64 {
    let per = (1.0 - alpha).powf(1.0 / n.max(1) as f64);
    // `student_t_quantile` takes trials (nu + 1); a pooled nu is an integer sum.
    crate::stats::student_t_quantile(per, (nu.round() as u32).saturating_add(1))
}

/// Every residual of `obs` judged against its limit (module docs).
pub fn judge(obs: &[Obs], data: &Dataset, alpha: f64) -> Vec<Judged> {
    let scales = [Quantity::U, Quantity::Omega].map(|q| scale_of(data, q));
    let n = obs.len();
    obs.iter()
        .map(|o| {
            let c = &data.cases[o.case];
            let scale = scales[(o.quantity == Quantity::Omega) as usize];
            match (scale, rel_trial_sd(c, o.quantity)) {
                (Scale::Pooled { rel_sd, nu }, Some((own, _))) => Judged {
                    obs: *o,
                    // z was over own SE = own |obs| / sqrt(n): rescale.
                    z: o.z * own / rel_sd,
                    limit: limit(nu, n, alpha),
                    pooled: true,
                    nu,
                },
                _ => {
                    let nu = f64::from(o.trials.max(2) - 1);
                    Judged {
                        obs: *o,
                        z: o.z,
                        limit: limit(nu, n, alpha),
                        pooled: false,
                        nu,
                    }
                }
            }
        })
        .collect()
}

impl Judged {
    /// How far beyond its limit (above 1: beyond).
    pub fn excess(&self) -> f64 {
        self.z.abs() / self.limit
    }
}

/// The residual furthest beyond its limit, if any is beyond.
pub fn worst_beyond(judged: &[Judged]) -> Option<Judged> {
    judged
        .iter()
        .copied()
        .max_by(|a, b| a.excess().total_cmp(&b.excess()))
        .filter(|j| j.excess() > 1.0)
}

/// The generalized ESD (module docs) over `obs`: the bad runs, most
/// extreme first (empty when none is beyond its limit).
pub fn esd(obs: &[Obs], data: &Dataset, alpha: f64) -> Vec<Judged> {
    let n = obs.len();
    let r_max = (n / 10).clamp(1, MAX_BAD_RUNS).min(n.saturating_sub(2));
    // Judged once: a residual's z and nu do not change between steps, only
    // the number of quantities its limit is for.
    let mut left = judge(obs, data, alpha);
    let mut taken = Vec::new();
    let mut count = 0;
    for step in 0..r_max {
        // One quantile per distinct nu (most quantities share one).
        let mut cache: Vec<(f64, f64)> = Vec::new();
        for j in &mut left {
            j.limit = match cache.iter().find(|c| c.0 == j.nu) {
                Some(c) => c.1,
                None => {
                    let l = limit(j.nu, n - step, alpha);
                    cache.push((j.nu, l));
                    l
                }
            };
        }
        let Some(at) =
            (0..left.len()).max_by(|&a, &b| left[a].excess().total_cmp(&left[b].excess()))
        else {
            break;
        };
        let j = left.swap_remove(at);
        if j.excess() > 1.0 {
            count = step + 1;
        }
        taken.push(j);
    }
    taken.truncate(count);
    taken
}
