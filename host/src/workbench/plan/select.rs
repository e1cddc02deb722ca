//! The greedy sequential choice of runs (the sequential construction of a
//! T-optimal design, Atkinson & Fedorov 1975, sec. 4; as optbayesexpt
//! chooses one setting at a time): each step adds the candidate run that
//! most raises the smallest accumulated distance `D_ij` over the pairs
//! still to separate ([`super::criterion`]: maximin, so that no pair is
//! left unseparated while another is separated twice), ties broken by the
//! total; a run is planned once.
//!
//! **The rivals are held** at their fits on the study's data, not refitted
//! in expectation to each planned outcome. Refitting (the alternative's
//! parameters moved to absorb the other's predictions, Atkinson & Fedorov's
//! `min_theta`) costs a nonlinear fit per candidate, pair and step; held,
//! the distance is an upper bound on the refitted one where a rival can
//! bend to follow the new runs. The honest check is the one the loop makes:
//! the runs merged, every step recalibrated and `diagnose` run again.
//!
//! **Exact ties.** A pair whose predictions agree to round-off on every
//! run the rig can make (relative difference below
//! [`crate::workbench::experiments::separation::SAME_MODEL_REL`]) is the
//! same model for any measurement of U or Omega_b: no run separates it,
//! and it is reported, not planned for.

use super::candidates::Candidate;
use super::criterion::Noise;
use super::reach::{Reach, HEADROOM};
use super::rivals::Rivals;
use crate::model::Prediction;
use crate::workbench::experiments::separation::SAME_MODEL_REL;
use rayon::prelude::*;

/// One planned run.
#[derive(Debug, Clone)]
pub struct PlannedRun {
    pub candidate: Candidate,
    /// The pair it separates most, and by how many standard deviations.
    pub separates: (usize, usize),
    pub separation_sigma: f64,
    /// The first rival's prediction (the run's expected U, for its duration).
    pub expected: Prediction,
}

/// A plan: its runs, the separation each pair reaches, the exact ties.
#[derive(Debug, Clone)]
pub struct Plan {
    pub runs: Vec<PlannedRun>,
    /// Per pair separated: `sqrt(D_ij)` over the plan.
    pub pair_sigma: Vec<((usize, usize), f64)>,
    /// Pairs no run separates (the same model).
    pub ties: Vec<(usize, usize)>,
    /// Candidate runs the rig offered.
    pub offered: usize,
    /// Of them, those the motor can hold and every rival can predict.
    pub reachable: usize,
}

impl Plan {
    /// The smallest separation the plan reaches over the pairs it separates.
    pub fn worst_sigma(&self) -> Option<f64> {
        self.pair_sigma.iter().map(|p| p.1).reduce(f64::min)
    }
}

/// The tail's lab rate `f` a set-point (the motor's rate `m = f +
/// Omega_b`) gives, by the first rival: in Stokes flow `Omega_b = r f`,
/// so `f = m / (1 + r)`, with `r` read from a prediction at `f = m`.
/// Every rival then predicts the same run (the lab's rate is measured, not
/// modelled). `None`: the model fails there.
fn at_set_point(c: &mut Candidate, first: &crate::model::Model) -> Option<()> {
    let m = c.set_point_hz;
    c.case.frequency_hz = m;
    let p = first.predict(&c.case).ok()?;
    let r = p.omega_body_hz / m;
    let f = m / (1.0 + r);
    (f.is_finite() && f > 0.0).then(|| c.case.frequency_hz = f)
}

/// The candidates the robot can run for the models `rivals` (each at its
/// set-point's lab rate, those the motor cannot hold dropped): what a plan
/// chooses from, and what a random design of the same rig draws from.
pub fn reachable(mut cands: Vec<Candidate>, rivals: &Rivals, reach: &dyn Reach) -> Vec<Candidate> {
    let preds = predictions(&mut cands, rivals, reach);
    cands
        .into_iter()
        .zip(preds)
        .filter_map(|(c, p)| p.map(|_| c))
        .collect()
}

/// Every rival's prediction at every candidate (`None`: one fails there,
/// or the motor cannot hold its set-point, [`super::reach`]).
fn predictions(
    cands: &mut [Candidate],
    rivals: &Rivals,
    reach: &dyn Reach,
) -> Vec<Option<Vec<Prediction>>> {
    cands
        .par_iter_mut()
        .map(|c| {
            let first = &rivals.models.first()?.model;
            at_set_point(c, first)?;
            let max = reach.max_rate_hz(first, &c.case)?;
            if c.set_point_hz > HEADROOM * max {
                return None;
            }
            rivals
                .models
                .iter()
                .map(|r| r.model.predict(&c.case).ok())
                .collect()
        })
        .collect()
}

fn rel_diff(a: &Prediction, b: &Prediction) -> f64 {
    let r = |x: f64, y: f64| (x - y).abs() / (0.5 * (x.abs() + y.abs())).max(1e-300);
    r(a.u_mm_s, b.u_mm_s).max(r(a.omega_body_hz, b.omega_body_hz))
}

/// The pick that raises the worst accumulated distance most (module docs).
fn best_pick(d2: &[Vec<f64>], acc: &[f64], used: &[bool]) -> Option<usize> {
    let score = |k: usize| {
        let min = (0..acc.len())
            .map(|p| acc[p] + d2[k][p])
            .fold(f64::INFINITY, f64::min);
        (min, d2[k].iter().sum::<f64>())
    };
    (0..d2.len())
        .filter(|&k| !used[k])
        .map(|k| (k, score(k)))
        .max_by(|a, b| a.1 .0.total_cmp(&b.1 .0).then(a.1 .1.total_cmp(&b.1 .1)))
        .map(|(k, _)| k)
}

/// Plan `runs` runs among `cands` that separate the `rivals` (module docs).
pub fn plan(
    mut cands: Vec<Candidate>,
    rivals: &Rivals,
    noise: &Noise,
    runs: usize,
    reach: &dyn Reach,
) -> Plan {
    let preds = predictions(&mut cands, rivals, reach);
    let usable: Vec<usize> = (0..cands.len()).filter(|&k| preds[k].is_some()).collect();
    let (mut live, mut ties) = (Vec::new(), Vec::new());
    for &(i, j) in &rivals.pairs {
        let largest = usable
            .iter()
            .filter_map(|&k| preds[k].as_ref())
            .filter_map(|p| Some(rel_diff(p.get(i)?, p.get(j)?)))
            .fold(0.0, f64::max);
        match largest < SAME_MODEL_REL {
            true => ties.push((i, j)),
            false => live.push((i, j)),
        }
    }
    let d2: Vec<Vec<f64>> = usable
        .iter()
        .map(|&k| {
            let p = preds[k].as_ref().expect("usable");
            live.iter()
                .map(|&(i, j)| noise.distance2(&p[i], &p[j]))
                .collect()
        })
        .collect();
    let mut acc = vec![0.0; live.len()];
    let mut used = vec![false; usable.len()];
    let mut picked = Vec::new();
    while !live.is_empty() && picked.len() < runs {
        let Some(k) = best_pick(&d2, &acc, &used) else {
            break;
        };
        used[k] = true;
        for (a, d) in acc.iter_mut().zip(&d2[k]) {
            *a += d;
        }
        let (p, best) = d2[k]
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .map(|(p, d)| (p, *d))
            .expect("a live pair");
        let ci = usable[k];
        picked.push(PlannedRun {
            candidate: cands[ci].clone(),
            separates: live[p],
            separation_sigma: best.sqrt(),
            expected: preds[ci].as_ref().expect("usable")[0],
        });
    }
    Plan {
        runs: picked,
        pair_sigma: live
            .iter()
            .copied()
            .zip(acc.iter().map(|a| a.sqrt()))
            .collect(),
        ties,
        offered: cands.len(),
        reachable: usable.len(),
    }
}
