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
//! are flagged as pairs.

use super::audit::{AuditSettings, Flag, Severity};
use super::propagate::bands;
use crate::data::Dataset;
use crate::effects::{EffectInstance, CATALOGUE};
use crate::model::{Model, ModelError};
use rand::rngs::StdRng;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;
use serde::Serialize;

/// Out of range by more than this many standard uncertainties of the ratio.
const Z_OUT: f64 = 3.0;

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
            let spec = effects[k].params()[i];
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

/// Run the ratio test; returns the summary and its flags.
pub fn ratio_test(
    model: &Model,
    data: &Dataset,
    s: &AuditSettings,
) -> Result<(RatioSummary, Vec<Flag>), ModelError> {
    let (names, members) = family(model, s.family_samples, s.seed);
    let preds: Vec<Vec<[f64; 2]>> = members
        .par_iter()
        .filter_map(|m| {
            let v: Option<Vec<[f64; 2]>> = data
                .cases
                .iter()
                .map(|c| m.predict(c).ok().map(|p| [p.u_mm_s, p.omega_body_hz]))
                .collect();
            v
        })
        .collect();
    let nominal: Vec<[f64; 2]> = data
        .cases
        .iter()
        .map(|c| model.predict(c).map(|p| [p.u_mm_s, p.omega_body_hz]))
        .collect::<Result<_, _>>()?;
    let band = bands(model, data)?;
    let mut flags = Vec::new();
    let (mut tested, mut out_total) = (0, 0);
    for q in 0..2 {
        let label = ["U", "Omega_b"][q];
        let obs: Vec<Option<(f64, f64)>> = data
            .cases
            .iter()
            .zip(&band)
            .zip(&nominal)
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
            .collect();
        let idx: Vec<usize> = (0..obs.len()).filter(|&i| obs[i].is_some()).collect();
        let mut bad: Vec<Vec<(usize, String)>> = vec![Vec::new(); data.cases.len()];
        let mut bad_pairs = Vec::new();
        // Each pair's range over the members, in parallel (n^2 / 2 pairs
        // times the members: the one quadratic part of the audit).
        // Per case, the members' predictions of this quantity (contiguous for the pair loop).
        let cols: Vec<Vec<f64>> = (0..data.cases.len())
            .map(|i| preds.iter().map(|p| p[i][q]).collect())
            .collect();
        let pairs: Vec<(usize, usize, f64, f64, f64, f64)> = idx
            .par_iter()
            .enumerate()
            .flat_map_iter(|(a, &i)| {
                let (obs, cols) = (&obs, &cols);
                idx[a + 1..].iter().filter_map(move |&j| {
                    let ((oi, ri), (oj, rj)) = (obs[i]?, obs[j]?);
                    let r = oi / oj;
                    let sd = r.abs() * (ri + rj).sqrt();
                    let (lo, hi) = cols[i]
                        .iter()
                        .zip(&cols[j])
                        .map(|(a, b)| a / b)
                        .filter(|x| x.is_finite())
                        .fold((f64::MAX, f64::MIN), |(l, h), x| (l.min(x), h.max(x)));
                    (lo <= hi).then_some((i, j, r, sd, lo, hi))
                })
            })
            .collect();
        for (i, j, r, sd, lo, hi) in pairs {
            tested += 1;
            let z = if r < lo {
                (lo - r) / sd
            } else if r > hi {
                (r - hi) / sd
            } else {
                0.0
            };
            if z > Z_OUT {
                out_total += 1;
                let text = format!(
                    "{label}({})/{label}({}) = {} measured, the family gives {} to {} ({z:.1} standard uncertainties outside)",
                    data.cases[i].id,
                    data.cases[j].id,
                    crate::format::fmt_sig(r, 3),
                    crate::format::fmt_sig(lo, 3),
                    crate::format::fmt_sig(hi, 3)
                );
                bad[i].push((j, text.clone()));
                bad[j].push((i, text.clone()));
                bad_pairs.push((i, j, text));
            }
        }
        let others = idx.len().saturating_sub(1);
        let singled: Vec<usize> = idx
            .iter()
            .copied()
            .filter(|&i| others >= 2 && 2 * bad[i].len() > others)
            .collect();
        for &i in &singled {
            flags.push(Flag {
                case: data.cases[i].id.clone(),
                kind: format!("ratio-{}", if q == 0 { "u" } else { "omega" }),
                detail: format!(
                    "{}: its measured {label} against the other cases is outside what any model of the family can produce in {} of {others} pairs (e.g. {}): check its recorded geometry and tail rate, and its {label} measurement",
                    data.cases[i].id,
                    bad[i].len(),
                    bad[i][0].1
                ),
                severity: Severity::Error,
            });
        }
        for (i, j, text) in bad_pairs {
            if singled.contains(&i) || singled.contains(&j) {
                continue;
            }
            flags.push(Flag {
                case: format!("{} & {}", data.cases[i].id, data.cases[j].id),
                kind: "ratio-pair".into(),
                detail: format!("{text}: one of the two is inconsistent with the model family, the data cannot say which"),
                severity: Severity::Warning,
            });
        }
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
