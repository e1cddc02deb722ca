//! The audit's ratio test: measured ratios between cases (`U_i / U_j`,
//! `Omega_i / Omega_j`) against the range that any model of the family can
//! produce. Ratios cancel what the cases share (body, oil, tube), so a
//! ratio outside every family member's range is a problem of the data, not
//! of a missing shared effect.
//!
//! **The family**: the model given (`--preset`, `--effect`, ...) plus any
//! combination of the cheap candidate catalogue effects (those `diagnose`
//! proposes by default: `candidate()` and not `costly()`, not already in
//! the model), each absent or present with its free parameters anywhere in
//! their bounds (fixed parameters at their defaults). It is sampled: the
//! base model, then `family_samples` members, each effect present with
//! probability 1/2, the free parameters on a Latin hypercube over their
//! bounds (McKay, Beckman & Conover, Technometrics 21 (1979) 239), seeded.
//! The sampled range is the [min, max] of each ratio over the members whose
//! predictions are finite: an inner estimate of the family's true range.
//!
//! A pair is out of range when the measured ratio lies beyond that range by
//! more than 3 standard uncertainties of the ratio; the ratio's relative
//! variance is the sum of both measurements' relative squared standard
//! errors and both predictions' relative squared per-case input bands
//! (shared inputs cancel to first order). A case is flagged when more than
//! half of its pairs are out of range (the other cases agree with each
//! other, this one with none); out-of-range pairs that single out no case
//! are flagged as pairs, the first [`MAX_LISTED_PAIRS`] of each quantity
//! one by one and the rest in one flag that counts them: at 10 000 cases
//! a family that misses the data leaves millions of such pairs (6.1
//! million flags, 1.9 GB of JSON), which nobody reads and no machine
//! should hold. Only the out-of-range pairs' indices are kept while the
//! pairs are tested, never all n^2/2 pairs.

use super::{AuditSettings, Flag, Severity};
use crate::data::Dataset;
use crate::effects::{EffectInstance, CATALOGUE};
use crate::model::{Model, ModelError};
use crate::workbench::propagate::{bands, Band};
use rand::rngs::StdRng;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::Serialize;

/// Out of range by more than this many standard uncertainties of the ratio.
const Z_OUT: f64 = 3.0;

/// Out-of-range pairs listed one flag each, per quantity; the rest are
/// counted in one flag.
pub const MAX_LISTED_PAIRS: usize = 50;

#[derive(Debug, Clone, Serialize)]
pub struct RatioSummary {
    /// The effects the family may add.
    pub family_effects: Vec<String>,
    /// Members sampled, and those with finite predictions on every case.
    pub members: usize,
    pub members_used: usize,
    pub pairs_tested: usize,
    pub pairs_out_of_range: usize,
}

/// The family members (module docs).
pub fn family(model: &Model, samples: usize, seed: u64) -> (Vec<String>, Vec<Model>) {
    let effects: Vec<&'static dyn crate::effects::Effect> = CATALOGUE
        .iter()
        .copied()
        .filter(|e| e.candidate() && !e.costly())
        .filter(|e| !model.effects.iter().any(|m| m.name() == e.name()))
        .filter(|e| model.can_take(*e))
        .collect();
    let dims: Vec<(usize, usize)> = effects
        .iter()
        .enumerate()
        .flat_map(|(k, e)| {
            e.params()
                .iter()
                .enumerate()
                .filter(|(_, p)| p.free)
                .map(move |(i, _)| (k, i))
        })
        .collect();
    let mut rng = StdRng::seed_from_u64(seed);
    // Latin hypercube: one permutation of the strata per dimension.
    let strata: Vec<Vec<usize>> = dims
        .iter()
        .map(|_| {
            let mut p: Vec<usize> = (0..samples).collect();
            p.shuffle(&mut rng);
            p
        })
        .collect();
    let mut members = vec![model.clone()];
    for s in 0..samples {
        let mut inst: Vec<EffectInstance> = effects
            .iter()
            .map(|e| EffectInstance::default_of(*e))
            .collect();
        let cells: Vec<f64> = strata
            .iter()
            .map(|perm| (perm[s] as f64 + rng.gen::<f64>()) / samples as f64)
            .collect();
        for (&(k, i), u) in dims.iter().zip(cells) {
            let spec = &effects[k].params()[i];
            inst[k].values[i] = spec.min + u * (spec.max - spec.min);
        }
        let mut m = model.clone();
        for e in inst {
            if rng.gen::<bool>() {
                m.effects.push(e);
            }
        }
        members.push(m);
    }
    (
        effects.iter().map(|e| e.name().to_string()).collect(),
        members,
    )
}

/// One pair's measured ratio against the family's range.
struct PairRange {
    r: f64,
    sd: f64,
    lo: f64,
    hi: f64,
}

impl PairRange {
    /// Standard uncertainties outside the range (0 inside).
    fn z(&self) -> f64 {
        if self.r < self.lo {
            (self.lo - self.r) / self.sd
        } else if self.r > self.hi {
            (self.r - self.hi) / self.sd
        } else {
            0.0
        }
    }

    fn describe(&self, label: &str, a: &str, b: &str) -> String {
        format!(
            "{label}({a})/{label}({b}) = {} measured, the family gives {} to {} ({:.1} standard uncertainties outside)",
            crate::format::fmt_sig(self.r, 3),
            crate::format::fmt_sig(self.lo, 3),
            crate::format::fmt_sig(self.hi, 3),
            self.z()
        )
    }
}

/// Cases `i` and `j`'s ratio and its range over the members' predictions
/// `cols` (`None` when either is unmeasured or no member is finite).
fn pair_range(
    obs: &[Option<(f64, f64)>],
    cols: &[Vec<f64>],
    i: usize,
    j: usize,
) -> Option<PairRange> {
    let ((oi, ri), (oj, rj)) = (obs[i]?, obs[j]?);
    let r = oi / oj;
    let sd = r.abs() * (ri + rj).sqrt();
    let (lo, hi) = cols[i]
        .iter()
        .zip(&cols[j])
        .map(|(a, b)| a / b)
        .filter(|x| x.is_finite())
        .fold((f64::MAX, f64::MIN), |(l, h), x| (l.min(x), h.max(x)));
    (lo <= hi).then_some(PairRange { r, sd, lo, hi })
}

/// One quantity of every case: its measured mean and the ratio's relative
/// variance share (`None` when unmeasured or zero).
type Observed = Vec<Option<(f64, f64)>>;

/// Run the ratio test; returns the summary and its flags.
pub fn ratio_test(
    model: &Model,
    data: &Dataset,
    s: &AuditSettings,
) -> Result<(RatioSummary, Vec<Flag>), ModelError> {
    let (names, members) = family(model, s.family_samples, s.seed);
    let preds = member_predictions(&members, data);
    let nominal: Vec<[f64; 2]> = data
        .cases
        .iter()
        .map(|c| model.predict(c).map(|p| [p.u_mm_s, p.omega_body_hz]))
        .collect::<Result<_, _>>()?;
    let band = bands(model, data)?;
    let mut flags = Vec::new();
    let (mut tested, mut out_total) = (0, 0);
    for q in 0..2 {
        let obs = observed(data, &band, &nominal, q);
        // Per case, the members' predictions of this quantity (contiguous for the pair loop).
        let cols: Vec<Vec<f64>> = (0..data.cases.len())
            .map(|i| preds.iter().map(|p| p[i][q]).collect())
            .collect();
        let (n_tested, out) = out_of_range_pairs(&obs, &cols);
        tested += n_tested;
        out_total += out.len();
        flags.extend(quantity_flags(data, &obs, &cols, &out, n_tested, q));
    }
    Ok((
        RatioSummary {
            family_effects: names,
            members: members.len(),
            members_used: preds.len(),
            pairs_tested: tested,
            pairs_out_of_range: out_total,
        },
        flags,
    ))
}

/// Each member's (U, Omega_b) on every case; members with a failed
/// prediction on any case are left out of the range.
fn member_predictions(members: &[Model], data: &Dataset) -> Vec<Vec<[f64; 2]>> {
    members
        .par_iter()
        .filter_map(|m| {
            data.cases
                .iter()
                .map(|c| m.predict(c).ok().map(|p| [p.u_mm_s, p.omega_body_hz]))
                .collect()
        })
        .collect()
}

/// Quantity `q` (0 U, 1 Omega_b) of every case with its share of the
/// ratio's relative variance: the measurement's relative squared standard
/// error and the prediction's relative squared per-case input band.
fn observed(data: &Dataset, band: &[Band], nominal: &[[f64; 2]], q: usize) -> Observed {
    data.cases
        .iter()
        .zip(band)
        .zip(nominal)
        .map(|((c, b), nom)| {
            let m = if q == 0 { c.u_mm_s } else { c.omega_body_hz }?;
            let own = if q == 0 {
                b.u_per_case_sd_mm_s
            } else {
                b.omega_per_case_sd_hz
            };
            let rel2 = (m.standard_error() / m.mean).powi(2) + (own / nom[q]).powi(2);
            (m.mean != 0.0 && nom[q] != 0.0).then_some((m.mean, rel2))
        })
        .collect()
}

/// The pairs tested and those out of range, `i < j`. Each pair's range
/// over the members in parallel (n^2 / 2 pairs times the members: the one
/// quadratic part of the audit); only the out-of-range pairs are kept.
fn out_of_range_pairs(obs: &Observed, cols: &[Vec<f64>]) -> (usize, Vec<(u32, u32)>) {
    let idx: Vec<usize> = (0..obs.len()).filter(|&i| obs[i].is_some()).collect();
    idx.par_iter()
        .enumerate()
        .map(|(a, &i)| {
            let mut tested = 0;
            let mut out = Vec::new();
            for &j in &idx[a + 1..] {
                if let Some(p) = pair_range(obs, cols, i, j) {
                    tested += 1;
                    if p.z() > Z_OUT {
                        out.push((i as u32, j as u32));
                    }
                }
            }
            (tested, out)
        })
        .reduce(
            || (0, Vec::new()),
            |(t, mut o), (t2, o2)| {
                o.extend(o2);
                (t + t2, o)
            },
        )
}

/// The flags of one quantity: each case out of range with more than half
/// of the others, then the pairs that single out no case (the first
/// [`MAX_LISTED_PAIRS`] one by one, the rest counted).
fn quantity_flags(
    data: &Dataset,
    obs: &Observed,
    cols: &[Vec<f64>],
    out: &[(u32, u32)],
    n_tested: usize,
    q: usize,
) -> Vec<Flag> {
    let label = ["U", "Omega_b"][q];
    // Per case: how many of its pairs are out, and its first partner.
    let mut bad = vec![(0usize, usize::MAX); data.cases.len()];
    for &(i, j) in out {
        for (k, other) in [(i, j), (j, i)] {
            let b = &mut bad[k as usize];
            b.0 += 1;
            b.1 = b.1.min(other as usize);
        }
    }
    let text = |i: usize, j: usize| {
        let (a, b) = (i.min(j), i.max(j));
        pair_range(obs, cols, a, b).map_or_else(String::new, |p| {
            p.describe(label, &data.cases[a].id, &data.cases[b].id)
        })
    };
    let others = obs.iter().filter(|o| o.is_some()).count().saturating_sub(1);
    let singled: Vec<bool> = (0..data.cases.len())
        .map(|i| obs[i].is_some() && others >= 2 && 2 * bad[i].0 > others)
        .collect();
    let mut flags = Vec::new();
    for i in (0..data.cases.len()).filter(|&i| singled[i]) {
        flags.push(Flag {
            case: data.cases[i].id.clone(),
            kind: format!("ratio-{}", if q == 0 { "u" } else { "omega" }),
            detail: format!(
                "{}: its measured {label} against the other cases is outside what any model of the family can produce in {} of {others} pairs (e.g. {}): check its recorded geometry and tail rate, and its {label} measurement",
                data.cases[i].id,
                bad[i].0,
                text(i, bad[i].1)
            ),
            severity: Severity::Error,
        });
    }
    let unsingled: Vec<(usize, usize)> = out
        .iter()
        .map(|&(i, j)| (i as usize, j as usize))
        .filter(|&(i, j)| !singled[i] && !singled[j])
        .collect();
    for &(i, j) in unsingled.iter().take(MAX_LISTED_PAIRS) {
        flags.push(Flag {
            case: format!("{} & {}", data.cases[i].id, data.cases[j].id),
            kind: "ratio-pair".into(),
            detail: format!("{}: one of the two is inconsistent with the model family, the data cannot say which", text(i, j)),
            severity: Severity::Warning,
        });
    }
    if unsingled.len() > MAX_LISTED_PAIRS {
        flags.push(Flag {
            case: format!("{} more pairs", unsingled.len() - MAX_LISTED_PAIRS),
            kind: "ratio-pairs-not-listed".into(),
            detail: format!(
                "{} pairs' {label} ratios of {n_tested} tested are outside the family's range without singling out a case; the first {MAX_LISTED_PAIRS} are listed, the other {} only counted: a family that misses this many pairs misses the data as a whole (check the model family and the data's shared setup)",
                unsingled.len(),
                unsingled.len() - MAX_LISTED_PAIRS
            ),
            severity: Severity::Warning,
        });
    }
    flags
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cases whose measured speeds are spread far wider than any member
    /// of the family could make them: many out-of-range pairs.
    fn scattered(n: usize) -> Dataset {
        let mut data = crate::data::paper();
        let cases = data.cases.clone();
        data.cases = (0..n)
            .map(|i| {
                let mut c = cases[i % cases.len()].clone();
                c.id = format!("s{i}");
                let u = c.u_mm_s.as_mut().expect("the paper measured U");
                u.mean *= 0.3 + 1.4 * (i as f64 * 0.618_034).fract();
                u.ci_half_width = 1e-3 * u.mean;
                c
            })
            .collect();
        data
    }

    #[test]
    fn out_of_range_pairs_beyond_the_listed_are_counted_not_listed() {
        let data = scattered(60);
        let s = AuditSettings {
            family_samples: 16,
            ..Default::default()
        };
        let (summary, flags) = ratio_test(&Model::base(), &data, &s).unwrap();
        let listed = flags.iter().filter(|f| f.kind == "ratio-pair").count();
        let summaries: Vec<&Flag> = flags
            .iter()
            .filter(|f| f.kind == "ratio-pairs-not-listed")
            .collect();
        assert!(summary.pairs_out_of_range > MAX_LISTED_PAIRS, "{summary:?}");
        assert!(listed <= 2 * MAX_LISTED_PAIRS, "{listed}");
        assert!(!summaries.is_empty(), "the rest is counted");
        let counted: usize = summaries
            .iter()
            .map(|f| f.case.split(' ').next().unwrap().parse::<usize>().unwrap())
            .sum();
        assert!(
            listed + counted <= summary.pairs_out_of_range,
            "{listed} + {counted} of {}",
            summary.pairs_out_of_range
        );
        assert!(flags.len() <= 2 * data.cases.len() + 2 * (MAX_LISTED_PAIRS + 1));
    }
}
