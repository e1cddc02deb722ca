//! The floors of a dataset with a few quantities left out, from one set
//! of draws (common random numbers): the audit's outlier check.

use super::{count_a_floor, DrawPlan, SEED};
use rand::rngs::StdRng;
use rand::SeedableRng;
use rand_distr::{Distribution, StudentT};

/// The floors of every "all the quantities but a few" from one set of
/// draws (common random numbers): the audit's outlier check needs the
/// floor with each case left out, and with the input uncertainty combined
/// every case has degrees of freedom of its own, so drawing each such
/// floor on its own was one full Monte Carlo per distinct case (hundreds
/// at 10 000 cases, each of 20 000 quantities). Here each draw keeps its
/// total over all the quantities and, per value of the degrees of freedom,
/// the last few samples (as many as any one leave-out removes of that
/// value); the sum without a case is the total less that case's samples,
/// which are draws of the same distribution, so each leave-out floor is
/// an exact Monte Carlo of its own quantities.
pub struct LeaveOutDraws {
    /// Per value of the degrees of freedom (bits), in order: how many
    /// samples of it each draw keeps apart.
    groups: Vec<(u64, usize)>,
    /// Per draw: the sum over every quantity.
    totals: Vec<f64>,
    /// Per group: per draw, its kept samples one after the other.
    kept: Vec<Vec<f64>>,
    quantities: usize,
}

impl LeaveOutDraws {
    /// Draws over the quantities `all` (degrees of freedom, bits -> count),
    /// keeping per value the most that one leave-out removes (`spare`);
    /// the same seeds and [`DrawPlan`] as [`super::chi2_noise_floor`].
    pub fn new(
        all: &std::collections::BTreeMap<u64, usize>,
        spare: &std::collections::BTreeMap<u64, usize>,
    ) -> LeaveOutDraws {
        count_a_floor();
        let groups: Vec<(u64, usize, usize, StudentT<f64>)> = all
            .iter()
            .map(|(&d, &count)| {
                let keep = spare.get(&d).copied().unwrap_or(0).min(count);
                let t = StudentT::new(f64::from_bits(d)).expect("dof >= 1");
                (d, count, keep, t)
            })
            .collect();
        let quantities: usize = all.values().sum();
        let plan = DrawPlan::for_quantities(quantities);
        let chunk = |c: usize| -> (Vec<f64>, Vec<Vec<f64>>) {
            let mut rng = StdRng::seed_from_u64(SEED + c as u64);
            let draws = plan.draws_in(c);
            let mut totals = Vec::with_capacity(draws);
            let mut kept: Vec<Vec<f64>> = groups
                .iter()
                .map(|g| Vec::with_capacity(draws * g.2))
                .collect();
            for _ in 0..draws {
                let mut total = 0.0;
                for ((_, count, keep, t), out) in groups.iter().zip(&mut kept) {
                    for i in 0..*count {
                        let x = t.sample(&mut rng).powi(2);
                        total += x;
                        if i >= count - keep {
                            out.push(x);
                        }
                    }
                }
                totals.push(total);
            }
            (totals, kept)
        };
        use rayon::prelude::*;
        let parts: Vec<(Vec<f64>, Vec<Vec<f64>>)> =
            (0..plan.chunks()).into_par_iter().map(chunk).collect();
        let mut totals = Vec::with_capacity(plan.draws);
        let mut kept: Vec<Vec<f64>> = vec![Vec::new(); groups.len()];
        for (t, k) in parts {
            totals.extend(t);
            for (all, part) in kept.iter_mut().zip(k) {
                all.extend(part);
            }
        }
        LeaveOutDraws {
            groups: groups.iter().map(|g| (g.0, g.2)).collect(),
            totals,
            kept,
            quantities,
        }
    }

    /// [`super::chi2_noise_floor`] of the quantities without `left_out` (degrees
    /// of freedom, bits -> count; each at most its `spare`), `None` when
    /// nothing is left to test or more is left out than was kept.
    pub fn floor(
        &self,
        left_out: &std::collections::BTreeMap<u64, usize>,
        k: usize,
        level: f64,
    ) -> Option<f64> {
        let mut taken: Vec<(&Vec<f64>, usize, usize)> = Vec::new();
        for (&d, &m) in left_out {
            let g = self.groups.iter().position(|g| g.0 == d)?;
            if m > self.groups[g].1 {
                return None;
            }
            taken.push((&self.kept[g], self.groups[g].1, m));
        }
        let n = self.quantities - left_out.values().sum::<usize>();
        if n <= k {
            return None;
        }
        let mut sums: Vec<f64> = self
            .totals
            .iter()
            .enumerate()
            .map(|(j, total)| {
                let less: f64 = taken
                    .iter()
                    .map(|(kept, keep, m)| kept[j * keep..j * keep + m].iter().sum::<f64>())
                    .sum();
                total - less
            })
            .collect();
        let at = ((level * sums.len() as f64) as usize).min(sums.len() - 1);
        let (_, q, _) = sums.select_nth_unstable_by(at, f64::total_cmp);
        Some(*q * (n - k) as f64 / n as f64)
    }
}
