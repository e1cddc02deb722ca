//! The stagewise search of `diagnose`: after the best first step (a
//! catalogue effect or a located law), search again on top of it, at every
//! place and with every catalogue effect not yet in the model, and keep
//! going while each new step pays for itself.
//!
//! A step on top of a level is **taken** when it
//! - lowers the chi-square by at least `2k + 2 ln M` (`k` its new free
//!   parameters, `M` the laws or effects it was chosen from: the AIC
//!   penalty plus the charge for having looked at `M`),
//! - lowers the Student-t deviance ([`super::robust`]) by as much, so that
//!   one bad run cannot pay for it,
//! - lowers the cross-validated MARE below the level's own,
//! - and reaches the floor or removes at least [`MIN_SHARE`] of what the
//!   level leaves above it (a step that shaves a misfit is not physics);
//!
//! among the steps taken, the lowest `AICc + 2 ln M` wins, the AICc of the
//! deviance the fits minimised ([`super::score`]: the chi-square, or the
//! Student-t deviance under `--likelihood student-t`). The search stops
//! at the noise floor, when no step is taken, or after [`MAX_STEPS`]. Each
//! step records the model beneath it (`on_top_of`, machine-readable).
//!
//! This is forward stagewise regression over a library of terms; the
//! charges make a null dataset gain no step.
//!
//! A path of two steps or more is then backfitted
//! ([`super::stagewise_backfit`]): each step re-located on top of the others;
//! a path left above the floor (one step or more) is also set against the
//! best pairs of laws placed from scratch.
//!
//! References: T. Hastie, R. Tibshirani & J. Friedman, *The Elements of
//! Statistical Learning*, 2nd ed. (2009), sec. 3.3.3 (forward stagewise);
//! K. P. Burnham & D. R. Anderson (2002), ch. 2 (AICc).

use super::candidate::{candidates, evaluate};
use super::diagnosis::{Candidate, DiagnoseSettings, Remainder, Step, Verdict, VerdictKind};
use super::discovery::write::exact_spec;
use super::discovery::{discover, explained_fraction, Discovery, Located, Reference};
use super::fit::FitError;
use super::robust::t_deviance_of;
use super::score::Deviance;
use super::verdict::Evidence;
use crate::data::Dataset;
use crate::effects::EffectInstance;
use crate::model::Model;
use rayon::prelude::*;

/// Most steps in one diagnosis (4).
pub const MAX_STEPS: usize = 4;

/// Share of what a level leaves above the noise floor that a step must
/// remove, unless it reaches the floor (one half, as for a partial finding).
pub const MIN_SHARE: f64 = 0.5;

/// A fitted level of the path: the model after some steps.
#[derive(Clone)]
pub struct Level {
    pub model: Model,
    pub chi2: f64,
    /// Free parameters fitted so far.
    pub k: usize,
    pub mare: f64,
    pub cv_mare: f64,
    pub chi2_reduced: Option<f64>,
    pub t_deviance: f64,
    /// The deviance its fits minimised when it is not the chi-square.
    pub minimised: Option<f64>,
    pub at_floor: bool,
}

impl Level {
    /// What the level is ranked by ([`super::score`]).
    pub fn deviance(&self) -> Deviance {
        Deviance {
            chi2: self.chi2,
            minimised: self.minimised,
        }
    }
}

/// The steps found, each with its level and (for a law) the finding.
pub struct Path {
    pub steps: Vec<(Step, Level, Option<Located>)>,
    /// Steps beyond the ones the single-step verdict already named.
    pub added: usize,
}

pub(super) struct Proposal {
    pub step: Step,
    pub level: Level,
    pub located: Option<Located>,
    /// `2 ln M`.
    pub charge: f64,
}

impl Proposal {
    fn key(&self, n: usize) -> f64 {
        self.level
            .deviance()
            .aicc(n, self.level.k)
            .unwrap_or(f64::INFINITY)
            + self.charge
    }

    fn taken(&self, prev: &Level, floor0: Option<f64>) -> bool {
        let k = (self.level.k - prev.k) as f64;
        let cost = 2.0 * k + self.charge;
        let share = explained_fraction(prev.chi2, self.level.chi2, floor0);
        prev.chi2 - self.level.chi2 >= cost
            && prev.t_deviance - self.level.t_deviance >= cost
            && self.level.cv_mare < prev.cv_mare
            && (self.level.at_floor || share.is_some_and(|f| f >= MIN_SHARE))
    }
}

fn on_top_of(model: &Model) -> Vec<String> {
    model.effects.iter().map(exact_spec).collect()
}

pub(super) fn n_obs(data: &Dataset) -> usize {
    super::noise::error_dofs(data).len()
}

pub(super) type Floor<'a> = &'a (dyn Fn(usize) -> Option<f64> + Sync);

pub(super) fn step_of(
    kind: &'static str,
    name: String,
    prev: &Level,
    level: &Level,
    n: usize,
) -> Step {
    Step {
        kind,
        name,
        on_top_of: on_top_of(&prev.model),
        mare: level.mare,
        cv_mare: level.cv_mare,
        chi2_reduced: level.chi2_reduced,
        deviance: level.minimised,
        aicc: level.deviance().aicc(n, level.k),
        at_noise_floor: level.at_floor,
        explained_fraction: None,
    }
}

fn from_candidate(
    c: &Candidate,
    prev: &Level,
    data: &Dataset,
    floor: Floor,
    charge: f64,
) -> Option<Proposal> {
    let k = prev.k + c.params.len();
    let level = Level {
        model: c.model.clone(),
        chi2: c.score.chi2,
        k,
        mare: c.score.mare,
        cv_mare: c.score.cv_mare,
        chi2_reduced: c.score.chi2_reduced,
        t_deviance: t_deviance_of(&c.model, data).ok()?,
        minimised: c.score.deviance,
        at_floor: floor(k).is_some_and(|f| c.score.chi2 <= f),
    };
    let step = step_of("catalogue", c.effect.clone(), prev, &level, n_obs(data));
    Some(Proposal {
        step,
        level,
        located: None,
        charge,
    })
}

fn from_located(l: &Located, prev: &Level, data: &Dataset, charge: f64) -> Option<Proposal> {
    let level = Level {
        model: l.model.clone(),
        chi2: l.score.chi2,
        k: prev.k + l.params.len(),
        mare: l.score.mare,
        cv_mare: l.score.cv_mare,
        chi2_reduced: l.score.chi2_reduced,
        t_deviance: t_deviance_of(&l.model, data).ok()?,
        minimised: l.score.deviance,
        at_floor: l.score.at_noise_floor,
    };
    let step = step_of("located", l.describe(), prev, &level, n_obs(data));
    Some(Proposal {
        step,
        level,
        located: Some(l.clone()),
        charge,
    })
}

/// The same place, feature and form as a law already in the model.
fn repeats(l: &Located, seen: &[Located]) -> bool {
    seen.iter()
        .any(|o| o.place == l.place && o.feature == l.feature && o.form == l.form)
}

/// The search's settings for a step on top of a level: fewer exact refits
/// than the first search (five at most).
pub(super) fn step_settings(s: &DiagnoseSettings) -> super::discovery::DiscoverySettings {
    super::discovery::DiscoverySettings {
        top: s.discovery.top.min(5),
        ..s.discovery.clone()
    }
}

/// Every proposal on top of `prev`: the located laws and the catalogue
/// effects not yet in the model.
pub(super) fn proposals(
    prev: &Level,
    data: &Dataset,
    seen: &[Located],
    floor: Floor,
    s: &DiagnoseSettings,
    done: Option<&Discovery>,
) -> Result<Vec<Proposal>, FitError> {
    let reference = Reference {
        chi2: prev.chi2,
        k: prev.k,
        floor,
    };
    let settings = step_settings(s);
    let fresh;
    let d = match done {
        Some(d) => d,
        None => {
            fresh = discover(&prev.model, data, &reference, &settings)?;
            &fresh
        }
    };
    let charge = 2.0 * (d.screened.max(1) as f64).ln();
    let mut out: Vec<Proposal> = d
        .located
        .iter()
        .filter(|l| !repeats(l, seen))
        .filter_map(|l| from_located(l, prev, data, charge))
        .collect();
    let cands = candidates(&prev.model, s.include_costly);
    let charge = 2.0 * (cands.len().max(1) as f64).ln();
    let len = prev.model.effects.len();
    let fitted: Vec<Candidate> = cands
        .par_iter()
        .filter_map(|e| {
            let m = prev
                .model
                .clone()
                .with_effect(EffectInstance::default_of(*e));
            evaluate(&m, &[len], data, &floor).ok()
        })
        .collect();
    out.extend(
        fitted
            .iter()
            .filter_map(|c| from_candidate(c, prev, data, floor, charge)),
    );
    Ok(out)
}

pub(super) fn best_taken(
    list: Vec<Proposal>,
    prev: &Level,
    n: usize,
    floor0: Option<f64>,
) -> Option<Proposal> {
    list.into_iter()
        .filter(|p| p.taken(prev, floor0))
        .min_by(|a, b| a.key(n).total_cmp(&b.key(n)))
}

/// The first steps the single-step verdict already chose, or (when it found
/// nothing at the floor) the best first step that is taken.
fn first_steps(base: &Level, e: &Evidence, v: &Verdict, floor: Floor) -> Vec<Proposal> {
    let (data, ranking, pairs, disc) = (e.data, e.ranking, e.pairs, e.discovery);
    let n_cat = ranking.len().max(1) as f64;
    let mut out = Vec::new();
    match v.kind {
        VerdictKind::NoneNeeded | VerdictKind::Indistinguishable => {}
        VerdictKind::Identified => {
            let c = ranking
                .iter()
                .chain(pairs)
                .find(|c| Some(&c.effect) == v.effect.as_ref());
            if let Some(p) = c.and_then(|c| from_candidate(c, base, data, floor, 2.0 * n_cat.ln()))
            {
                if let Some(l) = v.located.first() {
                    if let Some(q) = from_located(l, &p.level, data, 0.0) {
                        out.push(p);
                        out.push(q);
                        return out;
                    }
                }
                out.push(p);
            }
        }
        VerdictKind::Located => {
            if let Some(p) = v
                .located
                .first()
                .and_then(|l| from_located(l, base, data, 0.0))
            {
                out.push(p);
            }
        }
        VerdictKind::Unexplained => {
            let mut list: Vec<Proposal> = ranking
                .iter()
                .filter_map(|c| from_candidate(c, base, data, floor, 2.0 * n_cat.ln()))
                .collect();
            if let Some(d) = disc {
                let charge = 2.0 * (d.screened.max(1) as f64).ln();
                list.extend(
                    d.located
                        .iter()
                        .filter_map(|l| from_located(l, base, data, charge)),
                );
            }
            out.extend(best_taken(list, base, n_obs(data), floor(0)));
        }
    }
    out
}

/// The stagewise path for `model` on the evidence's data (module docs).
pub fn stagewise(
    model: &Model,
    e: &Evidence,
    v: &Verdict,
    floor: Floor,
    s: &DiagnoseSettings,
) -> Result<Path, FitError> {
    let (data, base, disc, rem) = (e.data, e.base, e.discovery, e.remainder);
    let base_level = Level {
        model: model.clone(),
        chi2: base.chi2,
        k: 0,
        mare: base.mare,
        cv_mare: base.mare,
        chi2_reduced: base.chi2_reduced,
        t_deviance: t_deviance_of(model, data)?,
        minimised: Deviance::of_model(model, data, base.chi2)?.minimised,
        at_floor: base.at_noise_floor,
    };
    let mut path: Steps = Vec::new();
    for p in first_steps(&base_level, e, v, floor) {
        path.push((p.step, p.level, p.located));
    }
    let first = path.len();
    extend(&mut path, data, floor, s, rem)?;
    let laws = disc.map_or(1, |d| d.screened);
    let backfitted = super::stagewise_backfit::backfit(model, data, &path, floor, s, laws)?;
    let mut added = path.len().saturating_sub(first);
    if let Some(alt) = backfitted {
        added = added.max(1);
        path = alt;
    }
    // Each step's share of what the level beneath it left above the floor.
    let floor0 = floor(0);
    let mut prev_chi2 = base.chi2;
    for (step, level, located) in &mut path {
        step.explained_fraction = explained_fraction(prev_chi2, level.chi2, floor0);
        if let Some(l) = located {
            l.on_top_of = step.on_top_of.clone();
        }
        prev_chi2 = level.chi2;
    }
    Ok(Path { added, steps: path })
}

pub(super) type Steps = Vec<(Step, Level, Option<Located>)>;

/// Take steps on top of the path's last level while one is taken.
fn extend(
    path: &mut Steps,
    data: &Dataset,
    floor: Floor,
    s: &DiagnoseSettings,
    rem: Option<&Remainder>,
) -> Result<(), FitError> {
    let n = n_obs(data);
    while let Some(prev) = path.last().map(|p| p.1.clone()) {
        if prev.at_floor || path.len() >= MAX_STEPS {
            break;
        }
        // The search on top of a catalogue effect may already be done
        // (`diagnose`'s remainder): reuse it.
        let done = rem.filter(|r| {
            path.len() == 1 && path[0].0.kind == "catalogue" && path[0].0.name == r.effect
        });
        let seen: Vec<Located> = path.iter().filter_map(|p| p.2.clone()).collect();
        let list = proposals(&prev, data, &seen, floor, s, done.map(|r| &r.discovery))?;
        let Some(p) = best_taken(list, &prev, n, floor(0)) else {
            break;
        };
        path.push((p.step, p.level, p.located));
    }
    Ok(())
}
