//! Are the stated intervals right? With means only, a model's residuals
//! above the noise floor are either an effect it misses or intervals
//! stated too narrow. This module tests the second: one scale factor `k`
//! on the intervals of a set of cases (every case included) that explains
//! the excess, with no structure left for a law.
//!
//! **Scale.** Each residual over its own standard error is `T_nu` under
//! honest intervals (`nu = trials - 1`); its two-sided p-value is turned
//! into a normal score `w = Phi^-1(1 - p/2)`, so that `w^2 ~ chi^2_1`
//! whatever the trials. A case's score is the mean `w^2` of its
//! quantities.
//!
//! **Statistic.** The cases sorted by score, for each leading set `S` of
//! at least [`MIN_SET_FRACTION`] of the cases (at least three) the
//! likelihood ratio of "the intervals on `S` are too narrow by one factor"
//! against "as stated" is `C (m - 1 - ln m)` (`C` quantities, `m` their
//! mean `w^2`, when above 1); the statistic is its largest value over the
//! sets. Its null distribution (the selection of `S` included) is drawn by
//! Monte Carlo with a fixed seed ([`DRAWS`] datasets of the same shape);
//! the intervals are called too narrow beyond its `1 - FALSE_ALARM`
//! quantile ([`FALSE_ALARM`] = 1 % per dataset).
//!
//! **No structure.** An effect the model misses also raises the residuals
//! of some cases, but it orders them by the design: the residuals on `S`
//! share a sign, or follow a feature. The finding is kept only when the
//! signs on `S`, and on all cases, are those of a fair coin (two-sided
//! binomial test at 1 % per quantity) and no recorded field, derived
//! group or column the lab recorded has a Spearman correlation with the
//! residuals beyond its 1 % limit (Bonferroni over the features and the
//! two quantities).
//!
//! **Power.** The test is made on at least [`MIN_CASES`] cases, and a
//! factor above [`MAX_FACTOR`] is never reported: the ways a lab misstates
//! an interval (a standard error given as the 95 % half-width, x1.96 to
//! x2.78; a standard error for a standard deviation, x sqrt(trials), about
//! 2.2 for five trials) stay below it, while residuals ten standard errors
//! out on a few cases are a model that misses or bad runs.
//!
//! **Factor.** `k` maximises the Student-t likelihood of the residuals on
//! `S` scaled by `1/k` (a one-dimensional golden-section search); it is
//! reported as "~k".
//!
//! References: A. P. Dempster, N. M. Laird & D. B. Rubin, J. R. Stat. Soc.
//! B 39 (1977) 1 (likelihood of a scale mixture); C. Spearman, Am. J.
//! Psychol. 15 (1904) 72; R. A. Fisher, *Statistical Methods for Research
//! Workers* (1925), the binomial sign test.

use crate::data::quantities::{FEATURES, FIELDS};
use crate::data::Dataset;
use crate::stats::spearman_p;
use crate::workbench::compare::Quantity;
use crate::workbench::noise::chi2_noise_floor;
use crate::workbench::robust::{t_deviance_one, Obs};
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use serde::Serialize;
use statrs::distribution::{Binomial, ContinuousCDF, DiscreteCDF, Normal, StudentsT};

/// The stated false-alarm rate per dataset of the interval test (1 %).
pub const FALSE_ALARM: f64 = 0.01;

/// The smallest set of cases whose intervals are judged together: fewer
/// are a few bad runs ([`super::outliers`]).
pub const MIN_SET_FRACTION: f64 = 0.2;

/// The fewest cases the test is made on: with fewer, the sign and trend
/// guards cannot tell an effect the model misses from intervals stated too
/// narrow (six cases that share a sign pass a 1 % sign test).
pub const MIN_CASES: usize = 12;

/// The largest factor reported: beyond it the excess is not a misstated
/// interval but a model that misses (module docs, "Power").
pub const MAX_FACTOR: f64 = 4.0;

/// Monte Carlo draws of the statistic's null distribution.
pub const DRAWS: usize = 1000;

/// The stated intervals judged too narrow on a set of cases.
#[derive(Debug, Clone, Serialize)]
pub struct IntervalFinding {
    /// The cases whose intervals look too narrow, worst first.
    pub cases: Vec<String>,
    /// The factor by which they look too narrow.
    pub factor: f64,
    /// The likelihood-ratio statistic and its 1 % limit under honest intervals.
    pub statistic: f64,
    pub limit: f64,
    pub false_alarm: f64,
    /// Reduced chi-square with the stated intervals, with those widened by
    /// `factor`, and the noise floor (reduced).
    pub chi2_reduced_stated: f64,
    pub chi2_reduced_widened: f64,
    pub floor_reduced: f64,
    /// The cases in the dataset.
    pub total_cases: usize,
}

impl IntervalFinding {
    /// Whether the widened intervals leave the model at the noise floor.
    pub fn explains_all(&self) -> bool {
        self.chi2_reduced_widened <= self.floor_reduced
    }

    /// The sentence printed before anything is located.
    pub fn sentence(&self) -> String {
        let list = if self.cases.len() > 8 {
            format!(
                "{} and {} more",
                self.cases[..8].join(", "),
                self.cases.len() - 8
            )
        } else {
            self.cases.join(", ")
        };
        let follows = if self.explains_all() {
            "with them widened the model meets every case to the noise, so no effect is needed; re-estimate those intervals from their trials before reading any law into these data"
        } else {
            "with them widened the model is still above the noise floor: what is located below is judged on the widened intervals"
        };
        format!(
            "the stated intervals look too narrow by ~{} on {} of {} cases ({list}): their residuals scatter more than the intervals allow, with no sign or trend that an effect would leave (likelihood ratio {} beyond its 1 % limit {}; reduced chi-square {} as stated, {} widened, floor {}); {follows}",
            crate::format::fmt_sig(self.factor, 2),
            self.cases.len(),
            self.total_cases,
            crate::format::fmt_sig(self.statistic, 3),
            crate::format::fmt_sig(self.limit, 3),
            crate::format::fmt_sig(self.chi2_reduced_stated, 3),
            crate::format::fmt_sig(self.chi2_reduced_widened, 3),
            crate::format::fmt_sig(self.floor_reduced, 3),
        )
    }
}

/// The normal score of a t residual (module docs, **Scale**).
fn normal_score(z: f64, nu: f64) -> f64 {
    let t = StudentsT::new(0.0, 1.0, nu).expect("nu >= 1");
    let p = (2.0 * t.sf(z.abs())).clamp(1e-300, 1.0);
    let n = Normal::new(0.0, 1.0).expect("unit normal");
    n.inverse_cdf(1.0 - 0.5 * p).max(0.0)
}

/// The largest likelihood ratio over leading sets (module docs), with the
/// size of its set; `cases` holds each case's (sum w^2, quantities),
/// sorted by mean w^2, largest first.
fn statistic(cases: &[(f64, usize)]) -> (f64, usize) {
    let n = cases.len();
    let min_set = ((MIN_SET_FRACTION * n as f64).ceil() as usize).max(3);
    let (mut a, mut c) = (0.0, 0usize);
    let mut best = (0.0, 0);
    for (i, &(s, q)) in cases.iter().enumerate() {
        a += s;
        c += q;
        if i + 1 < min_set || c == 0 {
            continue;
        }
        let m = a / c as f64;
        let lr = if m > 1.0 {
            c as f64 * (m - 1.0 - m.ln())
        } else {
            0.0
        };
        if lr > best.0 {
            best = (lr, i + 1);
        }
    }
    best
}

fn sort_by_score(cases: &mut [(f64, usize, usize)]) {
    cases.sort_by(|x, y| (y.0 / y.1 as f64).total_cmp(&(x.0 / x.1 as f64)));
}

/// The `1 - FALSE_ALARM` quantile of the statistic under honest intervals
/// for cases of `shape` (quantities per case).
fn null_limit(shape: &[usize]) -> f64 {
    let mut rng = StdRng::seed_from_u64(0x1_7e7a);
    let mut stats: Vec<f64> = (0..DRAWS)
        .map(|_| {
            let mut cases: Vec<(f64, usize, usize)> = shape
                .iter()
                .enumerate()
                .map(|(i, &q)| {
                    let s: f64 = (0..q)
                        .map(|_| {
                            let x: f64 = StandardNormal.sample(&mut rng);
                            x * x
                        })
                        .sum();
                    (s, q, i)
                })
                .collect();
            sort_by_score(&mut cases);
            let flat: Vec<(f64, usize)> = cases.iter().map(|c| (c.0, c.1)).collect();
            statistic(&flat).0
        })
        .collect();
    stats.sort_by(f64::total_cmp);
    stats[((1.0 - FALSE_ALARM) * DRAWS as f64) as usize - 1]
}

/// The interval test on a model's residuals `obs` (module docs); `level`
/// is the noise floor's quantile.
pub fn calibrate(obs: &[Obs], data: &Dataset, level: f64) -> Option<IntervalFinding> {
    let n_cases = data.cases.len();
    if n_cases < MIN_CASES {
        return None;
    }
    let chi2: f64 = obs.iter().map(|o| o.z * o.z).sum();
    let dofs: Vec<f64> = obs.iter().map(nu).collect();
    let floor = chi2_noise_floor(&dofs, 0, level)?;
    if chi2 <= floor {
        return None;
    }
    let mut per_case = vec![(0.0, 0usize, 0usize); n_cases];
    for (i, c) in per_case.iter_mut().enumerate() {
        c.2 = i;
    }
    for o in obs {
        let w = normal_score(o.z, nu(o));
        per_case[o.case].0 += w * w;
        per_case[o.case].1 += 1;
    }
    per_case.retain(|c| c.1 > 0);
    sort_by_score(&mut per_case);
    let flat: Vec<(f64, usize)> = per_case.iter().map(|c| (c.0, c.1)).collect();
    let (stat, size) = statistic(&flat);
    let shape: Vec<usize> = per_case.iter().map(|c| c.1).collect();
    let limit = null_limit(&shape);
    if stat <= limit {
        return None;
    }
    let set: Vec<usize> = per_case[..size].iter().map(|c| c.2).collect();
    if !unstructured(obs, data, &set) {
        return None;
    }
    let in_set: Vec<&Obs> = obs.iter().filter(|o| set.contains(&o.case)).collect();
    let factor = scale_factor(&in_set);
    let widened: f64 = obs
        .iter()
        .map(|o| {
            let k = if set.contains(&o.case) { factor } else { 1.0 };
            (o.z / k).powi(2)
        })
        .sum();
    let n = obs.len() as f64;
    if factor > MAX_FACTOR {
        return None;
    }
    Some(IntervalFinding {
        cases: set.iter().map(|&i| data.cases[i].id.clone()).collect(),
        factor,
        statistic: stat,
        limit,
        false_alarm: FALSE_ALARM,
        chi2_reduced_stated: chi2 / n,
        chi2_reduced_widened: widened / n,
        floor_reduced: floor / n,
        total_cases: n_cases,
    })
}

fn nu(o: &Obs) -> f64 {
    f64::from(o.trials.max(2) - 1)
}

/// The factor maximising the t likelihood of `z / k` on `obs` (module
/// docs, **Factor**): golden-section search on `ln k` in [0, ln 20].
fn scale_factor(obs: &[&Obs]) -> f64 {
    let cost = |lk: f64| -> f64 {
        let k = lk.exp();
        obs.iter()
            .map(|o| t_deviance_one(o.z / k, nu(o)) + 2.0 * lk)
            .sum()
    };
    let (mut a, mut b) = (0.0f64, 20f64.ln());
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if cost(c) < cost(d) {
            b = d;
        } else {
            a = c;
        }
    }
    (0.5 * (a + b)).exp()
}

/// The **No structure** guard (module docs).
fn unstructured(obs: &[Obs], data: &Dataset, set: &[usize]) -> bool {
    for q in [Quantity::U, Quantity::Omega] {
        let of = |in_set: bool| -> Vec<bool> {
            obs.iter()
                .filter(|o| o.quantity == q && (!in_set || set.contains(&o.case)))
                .map(|o| o.z > 0.0)
                .collect()
        };
        if !fair_coin(&of(true)) || !fair_coin(&of(false)) {
            return false;
        }
    }
    let features: Vec<Vec<f64>> = FEATURES
        .iter()
        .chain(FIELDS)
        .map(|f| {
            data.cases
                .iter()
                .map(|c| (f.value)(c))
                .collect::<Vec<f64>>()
        })
        // The lab's recorded columns too: a column it wrote down is where a
        // drift it suspected (the oil's temperature) leaves its trend.
        .chain(
            crate::data::recorded::features(data)
                .into_iter()
                .map(|(_, xs)| xs),
        )
        .filter(|v: &Vec<f64>| v.iter().any(|x| *x != v[0]))
        .collect();
    let tests = (2 * features.len()).max(1);
    for q in [Quantity::U, Quantity::Omega] {
        let pts: Vec<(usize, f64)> = obs
            .iter()
            .filter(|o| o.quantity == q)
            .map(|o| (o.case, o.z))
            .collect();
        if pts.len() < 5 {
            continue;
        }
        let z: Vec<f64> = pts.iter().map(|p| p.1).collect();
        for f in &features {
            let x: Vec<f64> = pts.iter().map(|p| f[p.0]).collect();
            if spearman_p(&x, &z) * (tests as f64) < 0.01 {
                return false;
            }
        }
    }
    true
}

/// Two-sided binomial test that `signs` are fair coin tosses, at 1 %.
fn fair_coin(signs: &[bool]) -> bool {
    let n = signs.len() as u64;
    if n < 4 {
        return true;
    }
    let k = signs.iter().filter(|s| **s).count() as u64;
    let b = Binomial::new(0.5, n).expect("p in [0, 1]");
    let tail = b.cdf(k.min(n - k));
    (2.0 * tail).min(1.0) >= 0.01
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_normal_score_of_a_t_residual_keeps_its_tail_probability() {
        // With many dof the t is the normal: the score is |z|.
        assert!((normal_score(1.96, 1e6) - 1.96).abs() < 1e-3);
        // t_4's 97.5 % quantile 2.776 has the normal's 1.96 as its score.
        assert!((normal_score(-2.776, 4.0) - 1.96).abs() < 2e-3);
    }

    #[test]
    fn the_statistic_is_zero_without_excess_and_grows_with_it() {
        let honest = vec![(1.0, 1); 10];
        assert_eq!(statistic(&honest).0, 0.0);
        let mut wide = vec![(4.0, 1); 5];
        wide.extend(vec![(1.0, 1); 5]);
        let (lr, size) = statistic(&wide);
        assert_eq!(size, 5);
        assert!((lr - 5.0 * (3.0 - 4f64.ln())).abs() < 1e-12);
    }

    #[test]
    fn the_sign_test_sees_an_unfair_coin() {
        assert!(fair_coin(&[true, false, true, false, true, false]));
        assert!(!fair_coin(&[true; 12]));
    }
}
