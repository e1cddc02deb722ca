//! What the data fix in a found set of two steps or more: the
//! steps' parameters refitted jointly, the pairs of parameters of
//! different steps that trade against each other, the places that carry
//! two laws, and the parameters whose interval spans no effect. The set is
//! still a set that fits; these say which of its parts the data fix only
//! together. How they are worded is in [`crate::workbench::verdict::text`].
//!
//! - **Traded**: two parameters of different steps whose correlation in
//!   the joint fit exceeds [`TRADE_CORRELATION`] in magnitude, or that
//!   span a combination the data leave free (a null direction of
//!   `J^T W J`, [`crate::workbench::fit::uncertainty`]; no correlation is defined, it
//!   is reported as `null`). The data fix a combination of the two, not
//!   each: moving one and refitting the other costs almost nothing.
//! - **Shared place**: two located laws at one place (in different
//!   features) are one place whose multiplier is the product of the two
//!   laws (a load: their sum), or at places the axial model cannot tell
//!   apart ([`crate::workbench::discovery::interpret::equivalents`]).
//! - **No effect within the interval**: a located law's strength `k`
//!   whose 95 % interval in the joint fit contains the value at which the
//!   law does nothing (1 for a constant multiplier, 0 for `1 + k x`,
//!   `1 + k x^p` and for every load). A law `k x` or `k x^p` on a
//!   multiplier has no such value.
//!
//! The joint fit starts from the path's values (one start), with every
//! parameter the steps added free, by the likelihood of the enclosing
//! diagnosis ([`crate::workbench::fit::fit_with`]).
//!
//! References: D. A. Belsley, E. Kuh & R. E. Welsch, *Regression
//! Diagnostics* (1980), ch. 3 (collinearity; a variance inflation factor
//! `1/(1 - r^2)` above 10, `|r|` above 0.95 for a pair, is the usual
//! mark of a combination fixed rather than its parts).

use super::level::Found;
use crate::data::Dataset;
use crate::effects::correction::Form;
use crate::effects::place::Place;
use crate::workbench::discovery::interpret::equivalents;
use crate::workbench::fit::{fit_with, free_params_of, FitError, FitResult, FreeParam};
use crate::workbench::robust::Likelihood;
use serde::Serialize;

/// `|r|` above which two parameters of different steps trade (0.95): the
/// threshold `fit` uses for its own pairs ([`crate::workbench::fit::uncertainty`]), a
/// variance inflation factor `1/(1 - r^2)` of 10.3 (module docs).
pub const TRADE_CORRELATION: f64 = 0.95;

/// One parameter of a step of the set, at the joint fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepParam {
    /// The step's number in `verdict.steps`, from 1.
    pub step: usize,
    /// The law's place, or the catalogue effect's name.
    pub of: String,
    pub param: String,
    pub value: f64,
    /// 95 % half-width in the joint fit; `None` when not identifiable.
    pub ci95: Option<f64>,
}

/// Two parameters of different steps that the data fix only together.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Traded {
    pub params: [StepParam; 2],
    /// Their correlation in the joint fit; `None` for a combination the
    /// data leave free (no correlation is defined there).
    pub correlation: Option<f64>,
}

/// Located laws of different steps at one place, or at places the axial
/// model cannot tell apart.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SharedPlace {
    pub places: [&'static str; 2],
    pub steps: [usize; 2],
    /// `same` (one place), or the equivalent's `reciprocal`/`opposite`.
    pub relation: &'static str,
    /// At one place: `product` (multipliers) or `sum` (loads).
    pub combined: Option<&'static str>,
}

/// What the joint fit of a found set fixes only together (module docs).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct JointReading {
    pub traded: Vec<Traded>,
    pub shared_places: Vec<SharedPlace>,
    /// Located laws' strengths whose 95 % interval contains no effect.
    pub no_effect_within: Vec<StepParam>,
}

impl JointReading {
    pub fn is_empty(&self) -> bool {
        self.traded.is_empty() && self.shared_places.is_empty() && self.no_effect_within.is_empty()
    }
}

/// The reading of `path` on `data`; `None` for a path of fewer than two
/// steps (a single law's own fit says what it fixes).
pub fn joint_reading(
    path: &Found,
    data: &Dataset,
    lik: Likelihood,
) -> Result<Option<JointReading>, FitError> {
    let (Some(first), Some(last)) = (path.steps.first(), path.steps.last()) else {
        return Ok(None);
    };
    if path.steps.len() < 2 {
        return Ok(None);
    }
    let model = &last.1.model;
    let n0 = first.0.on_top_of.len();
    let free = free_params_of(model, &(n0..model.effects.len()).collect::<Vec<_>>());
    // Step `i` added the effects from its `on_top_of` to its level's end.
    let step_of_effect = |e: usize| {
        path.steps
            .iter()
            .position(|(s, l, _)| (s.on_top_of.len()..l.model.effects.len()).contains(&e))
    };
    // Every effect beyond the starting model was added by a step; a path
    // that says otherwise is not read rather than read wrong.
    let Some(steps) = free
        .iter()
        .map(|f| step_of_effect(f.effect))
        .collect::<Option<Vec<usize>>>()
    else {
        return Ok(None);
    };
    let joint = fit_with(model, data, None, &free, false, lik)?;
    let params: Vec<StepParam> = joint
        .estimates
        .iter()
        .zip(&steps)
        .zip(&free)
        .map(|((e, &s), f)| StepParam {
            step: s + 1,
            of: path.steps[s]
                .2
                .as_ref()
                .map_or_else(|| path.steps[s].0.name.clone(), |l| l.place.to_string()),
            param: model.effects[f.effect].effect.params()[f.param]
                .name
                .to_string(),
            value: e.value,
            ci95: e.ci95,
        })
        .collect();
    let laws: Vec<(usize, Place)> = path
        .steps
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.2.as_ref().map(|l| (i + 1, l.correction.place)))
        .collect();
    let strengths = strength_nulls(&free, &steps, path);
    Ok(Some(JointReading {
        traded: traded(&params, &correlations(&joint, &free, data)),
        shared_places: shared_places(&laws),
        no_effect_within: no_effect_within(&params, &strengths),
    }))
}

/// The joint fit's correlations: its matrix; or, when the data leave a
/// combination free (the fit then gives none), those of the covariance on
/// the constrained subspace ([`crate::workbench::fit::uncertainty::inverse`], the
/// information `J^T J` of the normalised residuals), with `None` for the
/// pairs within a free combination (no correlation is defined there) and
/// for every pair when the information has no usable inverse at all.
fn correlations(joint: &FitResult, free: &[FreeParam], data: &Dataset) -> Vec<Vec<Option<f64>>> {
    let k = free.len();
    if let Some(r) = &joint.correlation {
        return r
            .iter()
            .map(|row| row.iter().map(|&x| Some(x)).collect())
            .collect();
    }
    let cases: Vec<&crate::data::Case> = data.cases.iter().collect();
    let Some(inv) =
        crate::workbench::fit::uncertainty::physical_jacobian(&joint.model, free, &cases)
            .and_then(|j| crate::workbench::fit::uncertainty::inverse(&(j.transpose() * &j)))
    else {
        return vec![vec![None; k]; k];
    };
    let c = &inv.cov;
    let mut out: Vec<Vec<Option<f64>>> = (0..k)
        .map(|i| {
            (0..k)
                .map(|j| Some(c[(i, j)] / (c[(i, i)] * c[(j, j)]).sqrt()).filter(|r| r.is_finite()))
                .collect()
        })
        .collect();
    for combo in &inv.held {
        for &(a, _) in combo {
            for &(b, _) in combo {
                out[a][b] = None;
            }
        }
    }
    out
}

/// Pairs of parameters of different steps with `|r| >` [`TRADE_CORRELATION`]
/// or in a free combination (`None`).
pub fn traded(params: &[StepParam], r: &[Vec<Option<f64>>]) -> Vec<Traded> {
    let mut out = Vec::new();
    for (i, a) in params.iter().enumerate() {
        for (j, b) in params.iter().enumerate().skip(i + 1) {
            if a.step == b.step {
                continue;
            }
            let rij = r[i][j];
            if rij.is_none_or(|x| x.abs() > TRADE_CORRELATION) {
                out.push(Traded {
                    params: [a.clone(), b.clone()],
                    correlation: rij,
                });
            }
        }
    }
    out
}

/// The traded pairs joined into groups that share a parameter (a set whose
/// resistances all scale together trades every pair of its strengths:
/// one combination, said once), each with its parameters in step order
/// and its pairs.
pub fn traded_groups(traded: &[Traded]) -> Vec<(Vec<StepParam>, Vec<&Traded>)> {
    let mut groups: Vec<(Vec<StepParam>, Vec<&Traded>)> = Vec::new();
    for t in traded {
        let touching: Vec<usize> = (0..groups.len())
            .filter(|&g| groups[g].0.iter().any(|p| t.params.contains(p)))
            .collect();
        let mut merged = (t.params.to_vec(), vec![t]);
        for &g in touching.iter().rev() {
            let (ps, ts) = groups.remove(g);
            merged.0.extend(ps);
            merged.1.extend(ts);
        }
        merged
            .0
            .sort_by(|a, b| (a.step, &a.param).cmp(&(b.step, &b.param)));
        merged.0.dedup();
        groups.push(merged);
    }
    groups
}

/// Located laws (step number, place) at one place or at equivalent places.
pub fn shared_places(laws: &[(usize, Place)]) -> Vec<SharedPlace> {
    let mut out = Vec::new();
    for (i, &(sa, a)) in laws.iter().enumerate() {
        for &(sb, b) in &laws[i + 1..] {
            let relation = if a == b {
                Some("same")
            } else {
                equivalents(a)
                    .iter()
                    .find(|e| e.place == b.name())
                    .map(|e| e.relation)
            };
            let Some(relation) = relation else { continue };
            let additive = a.is_additive();
            out.push(SharedPlace {
                places: [a.name(), b.name()],
                steps: [sa, sb],
                relation,
                combined: (relation == "same").then_some(if additive { "sum" } else { "product" }),
            });
        }
    }
    out
}

/// The value of a located law's strength `k` at which it does nothing
/// (module docs), per free parameter; `None` for every other parameter.
fn strength_nulls(free: &[FreeParam], steps: &[usize], path: &Found) -> Vec<Option<f64>> {
    free.iter()
        .zip(steps)
        .map(|(f, &s)| {
            let l = path.steps[s].2.as_ref().filter(|_| f.param == 0)?;
            no_effect_value(l.correction.form, l.correction.place.is_additive())
        })
        .collect()
}

/// The strength at which a law of `form` does nothing.
pub fn no_effect_value(form: Form, additive: bool) -> Option<f64> {
    match (form, additive) {
        (_, true) | (Form::Linear | Form::Power, false) => Some(0.0),
        (Form::Constant, false) => Some(1.0),
        (Form::Proportional | Form::PowerLaw, false) => None,
        (Form::Affine, false) => None,
    }
}

/// Parameters whose 95 % interval contains their no-effect value.
pub fn no_effect_within(params: &[StepParam], nulls: &[Option<f64>]) -> Vec<StepParam> {
    params
        .iter()
        .zip(nulls)
        .filter(|(p, n)| {
            n.zip(p.ci95)
                .is_some_and(|(n, ci)| (p.value - n).abs() <= ci)
        })
        .map(|(p, _)| p.clone())
        .collect()
}
