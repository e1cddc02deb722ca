//! The models a plan separates, from a diagnosis:
//!
//! - **Separate**: the rival sets the data cannot tell apart
//!   ([`crate::workbench::diagnosis::Verdict::sets`], each at its joint
//!   fit), else the catalogue effects named indistinguishable (each at its
//!   fit in the ranking). Every pair of them is to be separated.
//!   Else, when the verdict names one catalogue effect, the effects ranked
//!   within [`NEAR_AICC`] of the best: by Burnham & Anderson's scale
//!   (Model Selection and Multimodel Inference, 2nd ed., 2002, sec.
//!   2.6.9) a model 4-7 AICc behind has considerably less support but is
//!   not ruled out, and beyond 10 essentially none. A verdict that names
//!   one of two such models is the one experiment most worth testing.
//! - **Sharpen**: no rivals, but a fitted law or effect: for each of its
//!   parameters with a 95 % interval, the model at the interval's two ends
//!   (`value +- ci95 / 2` each, the others held) is a pair. Their distance
//!   at a run is the present interval's width in that run's standard
//!   errors: where a measurement narrows the parameter most (a c-optimal
//!   design read as discrimination).
//! - **Nothing**: neither; no plan is needed.

use crate::model::Model;
use crate::workbench::diagnosis::{Candidate, Diagnosis};
use crate::workbench::fit::Estimate;

/// One model to separate from the others.
#[derive(Debug, Clone)]
pub struct Rival {
    /// How the verdict names it (`set 2: ...`, `kappa = lo end`).
    pub name: String,
    pub model: Model,
}

/// What the plan is for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Goal {
    Separate,
    Sharpen,
    Nothing,
}

/// The models, and the pairs (indices) to separate.
#[derive(Debug, Clone)]
pub struct Rivals {
    pub goal: Goal,
    /// What the models are, in words (the terminal's heading).
    pub why: &'static str,
    pub models: Vec<Rival>,
    pub pairs: Vec<(usize, usize)>,
}

fn all_pairs(n: usize) -> Vec<(usize, usize)> {
    (0..n)
        .flat_map(|i| (i + 1..n).map(move |j| (i, j)))
        .collect()
}

fn candidate_named<'a>(d: &'a Diagnosis, name: &str) -> Option<&'a Candidate> {
    d.ranking.iter().chain(&d.pairs).find(|c| c.effect == name)
}

/// The model with estimate `e` moved to `value`, within its bounds.
fn with_value(model: &Model, e: &Estimate, value: f64) -> Option<Model> {
    let mut m = model.clone();
    let inst = m.effects.iter_mut().rev().find(|i| i.name() == e.effect)?;
    let specs = inst.effect.params();
    let k = specs.iter().position(|p| p.name == e.name)?;
    inst.values[k] = value.clamp(specs[k].min, specs[k].max);
    Some(m)
}

fn sharpen(model: &Model, estimates: &[Estimate]) -> Rivals {
    let mut models = Vec::new();
    let mut pairs = Vec::new();
    for e in estimates {
        let Some(ci) = e.ci95.filter(|c| c.is_finite() && *c > 0.0) else {
            continue;
        };
        let (Some(lo), Some(hi)) = (
            with_value(model, e, e.value - 0.5 * ci),
            with_value(model, e, e.value + 0.5 * ci),
        ) else {
            continue;
        };
        pairs.push((models.len(), models.len() + 1));
        for (end, m) in [("low", lo), ("high", hi)] {
            models.push(Rival {
                name: format!("{}.{} at its interval's {end} end", e.effect, e.name),
                model: m,
            });
        }
    }
    Rivals {
        goal: if pairs.is_empty() {
            Goal::Nothing
        } else {
            Goal::Sharpen
        },
        why: "the fitted law's intervals to sharpen (each parameter's two ends)",
        models,
        pairs,
    }
}

/// The largest AICc behind the best at which a ranked effect is still a
/// rival to test (module docs).
pub const NEAR_AICC: f64 = 10.0;

/// The ranked effects within [`NEAR_AICC`] of the best, each named with
/// its distance, when the verdict names the best.
fn near_rivals(d: &Diagnosis) -> Vec<Rival> {
    let best = d.ranking.first();
    let named = best.is_some_and(|b| d.verdict.effect.as_deref() == Some(b.effect.as_str()));
    let Some(best_aicc) = best.and_then(|b| b.score.aicc).filter(|_| named) else {
        return Vec::new();
    };
    d.ranking
        .iter()
        .filter_map(|c| Some((c, c.score.aicc? - best_aicc)))
        .filter(|(_, delta)| delta.is_finite() && *delta <= NEAR_AICC)
        .map(|(c, delta)| Rival {
            name: format!("{} (AICc +{delta:.1})", c.effect),
            model: c.model.clone(),
        })
        .collect()
}

/// The models a plan for `d` separates (module docs).
pub fn rivals_of(d: &Diagnosis) -> Rivals {
    let v = &d.verdict;
    let sets: Vec<Rival> = v
        .sets
        .iter()
        .enumerate()
        .filter_map(|(i, s)| {
            Some(Rival {
                name: format!("set {}: {}", i + 1, s.members.join(" + ")),
                model: s.model.clone()?,
            })
        })
        .collect();
    let ties: Vec<Rival> = v
        .indistinguishable
        .iter()
        .filter_map(|n| {
            Some(Rival {
                name: n.clone(),
                model: candidate_named(d, n)?.model.clone(),
            })
        })
        .collect();
    let whys = [
        "the rival sets the data cannot tell apart",
        "the effects the data cannot tell apart",
        "the verdict's effect and the effects within 10 AICc of it, which the data do not rule out",
    ];
    for (models, why) in [sets, ties, near_rivals(d)].into_iter().zip(whys) {
        if models.len() >= 2 {
            return Rivals {
                goal: Goal::Separate,
                why,
                pairs: all_pairs(models.len()),
                models,
            };
        }
    }
    if let Some(l) = v.located.first() {
        return sharpen(&l.model, &l.params);
    }
    if let Some(c) = v.effect.as_deref().and_then(|n| candidate_named(d, n)) {
        return sharpen(&c.model, &c.params);
    }
    Rivals {
        goal: Goal::Nothing,
        why: "nothing to separate or sharpen",
        models: Vec::new(),
        pairs: Vec::new(),
    }
}
