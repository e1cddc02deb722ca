//! The levels of a found set of `diagnose`: each step (a catalogue effect
//! or a located law) with the fitted model up to it, and the first steps
//! the single-step verdict already chose. The set itself is chosen by the
//! search over subsets ([`crate::workbench::search`]).
//!
//! References: K. P. Burnham & D. R. Anderson (2002), ch. 2 (AICc).

use crate::data::Dataset;
use crate::model::Model;
use crate::workbench::diagnosis::{Candidate, SetMember, Verdict, VerdictKind};
use crate::workbench::discovery::write::exact_spec;
use crate::workbench::discovery::Located;
use crate::workbench::robust::t_deviance_of;
use crate::workbench::score::Deviance;
use crate::workbench::verdict::Evidence;

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
    /// What the level is ranked by ([`crate::workbench::score`]).
    pub fn deviance(&self) -> Deviance {
        Deviance {
            chi2: self.chi2,
            minimised: self.minimised,
        }
    }
}

/// The steps found, each with its level and (for a law) the finding.
pub struct Found {
    pub steps: Vec<(SetMember, Level, Option<Located>)>,
    /// Steps beyond the ones the single-step verdict already named.
    pub added: usize,
    /// The other sets the data cannot tell from this one
    /// (`super::rivals`), best key first.
    pub rivals: Vec<Rival>,
    /// The margin the rivals were judged by ([`super::calibrate`]); `None`
    /// when no rival was sought.
    pub margin: Option<super::calibrate::Margin>,
}

/// A set at other places whose key is within the AICc margin of the found
/// set's (`super::rivals`).
pub struct Rival {
    /// Each member as the verdict names it.
    pub members: Vec<String>,
    /// Its places and catalogue names, sorted.
    pub places: Vec<String>,
    /// Its key minus the found set's.
    pub key_difference: f64,
    pub at_floor: bool,
    /// The starting model with the set at its joint values.
    pub model: Model,
}

pub(super) struct Proposal {
    pub step: SetMember,
    pub level: Level,
    pub located: Option<Located>,
}

fn on_top_of(model: &Model) -> Vec<String> {
    model.effects.iter().map(exact_spec).collect()
}

pub(super) fn n_obs(data: &Dataset) -> usize {
    crate::workbench::noise::error_dofs(data).len()
}

pub(super) type Floor<'a> = &'a (dyn Fn(usize) -> Option<f64> + Sync);

pub(super) fn step_of(
    kind: &'static str,
    name: String,
    prev: &Level,
    level: &Level,
    n: usize,
) -> SetMember {
    SetMember {
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

fn from_candidate(c: &Candidate, prev: &Level, data: &Dataset, floor: Floor) -> Option<Proposal> {
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
    })
}

fn from_located(l: &Located, prev: &Level, data: &Dataset) -> Option<Proposal> {
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
    })
}

/// The first steps the single-step verdict already chose (none for an
/// unexplained verdict).
pub(super) fn first_steps(base: &Level, e: &Evidence, v: &Verdict, floor: Floor) -> Vec<Proposal> {
    let (data, ranking, pairs) = (e.data, e.ranking, e.pairs);
    let mut out = Vec::new();
    match v.kind {
        VerdictKind::NoneNeeded | VerdictKind::Indistinguishable => {}
        VerdictKind::Identified => {
            let c = ranking
                .iter()
                .chain(pairs)
                .find(|c| Some(&c.effect) == v.effect.as_ref());
            if let Some(p) = c.and_then(|c| from_candidate(c, base, data, floor)) {
                if let Some(l) = v.located.first() {
                    if let Some(q) = from_located(l, &p.level, data) {
                        out.push(p);
                        out.push(q);
                        return out;
                    }
                }
                out.push(p);
            }
        }
        VerdictKind::Located => {
            if let Some(p) = v.located.first().and_then(|l| from_located(l, base, data)) {
                out.push(p);
            }
        }
        // The search over subsets decides from nothing.
        VerdictKind::Unexplained => {}
    }
    out
}

pub(super) type Steps = Vec<(SetMember, Level, Option<Located>)>;
