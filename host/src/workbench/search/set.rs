//! The arithmetic of a set of laws and effects ([`super`]): its members,
//! their joint fit and key `AICc + sum 2 ln M`, and the path a set is
//! listed as. What is decided about a set is in [`super`].
//!
//! References: C. M. Hurvich & C.-L. Tsai, Biometrika 76 (1989) 297 (AICc);
//! K. P. Burnham & D. R. Anderson, *Model Selection and Multimodel
//! Inference*, 2nd ed. (2002), ch. 2.

use super::level::{n_obs, step_of, Floor, Level, Steps};
use crate::data::Dataset;
use crate::effects::correction::LocatedCorrection;
use crate::effects::EffectInstance;
use crate::model::Model;
use crate::workbench::candidate::{candidates, cross_validated_mare};
use crate::workbench::compare::compare;
use crate::workbench::diagnosis::Candidate;
use crate::workbench::discovery::places::AtPlace;
use crate::workbench::discovery::{interpretation_of, Located};
use crate::workbench::fit::{fit_with, free_params_of, Estimate, FitError, FitResult};
use crate::workbench::robust::t_deviance_of;
use crate::workbench::robust::Likelihood;
use crate::workbench::score::Deviance;
use std::sync::Arc;

/// One step of the set: the effects it adds, and the law (for a located
/// step) or the catalogue name.
#[derive(Clone)]
pub(super) struct Member {
    /// What the member is, independent of its values: the catalogue name,
    /// or `place|feature|form` for a law.
    pub id: String,
    pub insts: Vec<EffectInstance>,
    pub located: Option<Located>,
    pub name: String,
    /// `2 ln M`: the charge for having chosen it among `M`.
    pub charge: f64,
    /// The place of a law (`None` for a catalogue effect).
    pub place: Option<&'static str>,
    /// A screened law not yet refitted alone: located once it is kept.
    pub pending: Option<std::sync::Arc<AtPlace>>,
}

impl Member {
    /// A catalogue effect as a member: the effects its candidate adds on
    /// top of the starting model's first `base_len`.
    pub fn catalogue(c: &Candidate, base_len: usize, charge: f64) -> Member {
        Member {
            id: c.effect.clone(),
            insts: c.model.effects[base_len..].to_vec(),
            located: None,
            name: c.effect.clone(),
            charge,
            place: None,
            pending: None,
        }
    }

    /// The parameters its effects carry (each one a free one of a set's
    /// joint fit).
    pub fn n_params(&self) -> usize {
        self.insts.iter().map(|i| i.values.len()).sum()
    }

    /// The law of a located or screened member (`None` for a catalogue
    /// effect).
    pub fn law(&self) -> Option<&Arc<LocatedCorrection>> {
        match (&self.located, &self.pending) {
            (Some(l), _) => Some(&l.correction),
            (None, Some(at)) => Some(&at.screened.correction),
            (None, None) => None,
        }
    }

    /// The member as a verdict names it: `place = formula (k=.., p=..)` at
    /// its current values, or the catalogue effect's name.
    pub fn describe(&self) -> String {
        let (Some(law), Some(inst)) = (self.law(), self.insts.first()) else {
            return self.name.clone();
        };
        let params: Vec<String> = inst
            .effect
            .params()
            .iter()
            .zip(&inst.values)
            .map(|(p, v)| format!("{}={}", p.name, crate::format::fmt_sig(*v, 4)))
            .collect();
        format!(
            "{} = {} ({})",
            law.place.name(),
            law.formula(),
            params.join(", ")
        )
    }
}

/// The id of a law: place, feature and form.
pub(super) fn law_id(c: &LocatedCorrection) -> String {
    format!(
        "{}|{}|{:?}",
        c.place.name(),
        c.feature.as_ref().map_or("-".into(), |q| q.id()),
        c.form
    )
}

/// A set of members fitted jointly on top of the starting model.
#[derive(Clone)]
pub(super) struct Joint {
    pub fit: FitResult,
    pub k: usize,
    pub at_floor: bool,
    pub key: f64,
}

/// `model0` with the effects of every member of `set` added, at the
/// members' values.
pub(super) fn model_with(model0: &Model, set: &[Member]) -> Model {
    let mut m = model0.clone();
    for inst in set.iter().flat_map(|s| &s.insts) {
        m = m.with_effect(inst.clone());
    }
    m
}

pub(super) fn joint(
    model0: &Model,
    set: &[Member],
    data: &Dataset,
    floor: Floor,
    lik: Likelihood,
) -> Result<Joint, FitError> {
    let m = model_with(model0, set);
    let added: Vec<usize> = (model0.effects.len()..m.effects.len()).collect();
    let free = free_params_of(&m, &added);
    let fit = fit_with(&m, data, None, &free, false, lik)?;
    let k = free.len();
    let at_floor = floor(k).is_some_and(|f| fit.chi2 <= f);
    let charges: f64 = set.iter().map(|s| s.charge).sum();
    let key = Deviance::of_fit(&fit)
        .aicc(n_obs(data), k)
        .unwrap_or(f64::INFINITY)
        + charges;
    Ok(Joint {
        fit,
        k,
        at_floor,
        key,
    })
}

/// The members with the values of a joint fit.
pub(super) fn with_values(set: &[Member], model0: &Model, j: &Joint) -> Vec<Member> {
    let mut at = model0.effects.len();
    set.iter()
        .map(|s| {
            let mut s = s.clone();
            for inst in &mut s.insts {
                *inst = j.fit.model.effects[at].clone();
                at += 1;
            }
            s
        })
        .collect()
}

pub(super) fn members(
    catalogue: &crate::effects::Catalogue,
    model0: &Model,
    path: &Steps,
    laws: usize,
) -> Vec<Member> {
    let n_cat = candidates(catalogue, model0, true).len().max(1) as f64;
    let mut prev = model0.effects.len();
    path.iter()
        .map(|(step, level, located)| {
            let insts = level.model.effects[prev..].to_vec();
            prev = level.model.effects.len();
            Member {
                id: match located {
                    Some(l) => law_id(&l.correction),
                    None => step.name.clone(),
                },
                place: located.as_ref().map(|l| l.place),
                pending: None,
                insts,
                located: located.clone(),
                name: step.name.clone(),
                charge: match located {
                    Some(_) => 2.0 * (laws.max(1) as f64).ln(),
                    None => 2.0 * n_cat.ln(),
                },
            }
        })
        .collect()
}

/// The path of a backfitted set: each step's level is the starting model
/// with the steps up to it at the joint values, scored as it stands
/// (cross-validated by refitting all their parameters on each fold).
pub(super) fn rebuild(
    model0: &Model,
    data: &Dataset,
    set: &[Member],
    estimates: &[Estimate],
    floor: Floor,
    lik: Likelihood,
) -> Result<Steps, FitError> {
    let n = n_obs(data);
    let mut estimates = estimates.iter();
    let mut prev = Level {
        model: model0.clone(),
        chi2: f64::INFINITY,
        k: 0,
        mare: f64::INFINITY,
        cv_mare: f64::INFINITY,
        chi2_reduced: None,
        t_deviance: f64::INFINITY,
        minimised: None,
        at_floor: false,
    };
    let mut out: Steps = Vec::new();
    for m in set {
        let mut model = prev.model.clone();
        for inst in &m.insts {
            model = model.with_effect(inst.clone());
        }
        let added: Vec<usize> = (model0.effects.len()..model.effects.len()).collect();
        let free = free_params_of(&model, &added);
        let k = free.len();
        let cmp = compare(&model, data, k)?;
        let level = Level {
            cv_mare: cross_validated_mare(&model, data, &free, lik),
            chi2: cmp.summary.chi2,
            k,
            mare: cmp.summary.mare,
            chi2_reduced: cmp.summary.chi2_reduced,
            t_deviance: t_deviance_of(&model, data)?,
            minimised: Deviance::of_model(&model, data, cmp.summary.chi2, lik)?.minimised,
            at_floor: floor(k).is_some_and(|f| cmp.summary.chi2 <= f),
            model,
        };
        let own: Vec<Estimate> = estimates.by_ref().take(k - prev.k).cloned().collect();
        let located = m.located.as_ref().map(|l| restate(l, &level, own, data, n));
        let (kind, name) = match &located {
            Some(l) => ("located", l.describe()),
            None => ("catalogue", m.name.clone()),
        };
        out.push((
            step_of(kind, name, &prev, &level, n),
            level.clone(),
            located,
        ));
        prev = level;
    }
    Ok(out)
}

/// A law restated at its backfitted values and level.
pub(super) fn restate(
    l: &Located,
    level: &Level,
    own: Vec<Estimate>,
    data: &Dataset,
    n: usize,
) -> Located {
    let values = &level
        .model
        .effects
        .last()
        .expect("a law adds one effect")
        .values;
    let mut out = l.clone();
    out.params = own;
    out.score.mare = level.mare;
    out.score.cv_mare = level.cv_mare;
    out.score.chi2 = level.chi2;
    out.score.chi2_reduced = level.chi2_reduced;
    out.score.deviance = level.minimised;
    out.score.aicc = level.deviance().aicc(n, level.k);
    out.score.at_noise_floor = level.at_floor;
    out.t_deviance = level.t_deviance;
    out.interpretation = interpretation_of(&l.correction, values, data);
    out.model = level.model.clone();
    out
}
