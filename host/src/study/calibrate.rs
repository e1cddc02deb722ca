//! Calibrating a new step on top of the study's model: its free parameters
//! fitted with the earlier steps held (or, asked, all refitted jointly);
//! a parameter the data cannot fix together with the others is fixed (an
//! earlier step's at its earlier value, the new step's at its fitted
//! value) and the rest refitted, so that every stored parameter has an
//! interval or a reason, never "±?".

use super::file::ParamRecord;
use crate::data::Dataset;
use crate::model::Model;
use crate::workbench::fit::{fit_with, free_params_of, FitResult, FreeParam};
use crate::workbench::robust::Likelihood;

/// The calibrated step.
pub struct Calibrated {
    pub model: Model,
    /// The parameters fitted in the end (what cross-validation refits).
    pub fitted: Vec<FreeParam>,
    pub params: Vec<ParamRecord>,
    pub refitted: Vec<ParamRecord>,
    pub notes: Vec<String>,
    /// A parameter was fixed because the data could not fix it.
    pub reduced: bool,
}

/// A parameter fixed because the data cannot fix it, and why.
struct Fixed {
    at: FreeParam,
    value: f64,
    reason: String,
}

/// Calibrate the last effect of `model` (just added at its defaults);
/// `first_step` is the index of the study's first step's effect (the
/// preset's effects before it are never refitted).
pub fn calibrate(
    mut model: Model,
    first_step: usize,
    refit_all: bool,
    data: &Dataset,
    likelihood: Likelihood,
) -> Result<Calibrated, String> {
    let new = model.effects.len() - 1;
    let before = model.clone();
    let scope: Vec<usize> = if refit_all {
        (first_step..=new).collect()
    } else {
        vec![new]
    };
    let mut free = free_params_of(&model, &scope);
    let n_obs: usize = data
        .cases
        .iter()
        .map(|c| c.u_mm_s.is_some() as usize + c.omega_body_hz.is_some() as usize)
        .sum();
    let mut fixed: Vec<Fixed> = Vec::new();
    let mut notes = Vec::new();
    while free.len() > n_obs {
        let f = free.pop().expect("more free parameters than none");
        fixed.push(Fixed {
            at: f,
            value: model.effects[f.effect].values[f.param],
            reason: format!(
                "the data hold {n_obs} measured quantities, too few for more free parameters; held at its default"
            ),
        });
    }
    let result =
        loop {
            if free.is_empty() {
                break None;
            }
            let r =
                fit_with(&model, data, None, &free, true, likelihood).map_err(|e| e.to_string())?;
            model = r.model.clone();
            let Some(i) = unfixable(&r, &free, new) else {
                break Some(r);
            };
            let f = free.remove(i);
            let earlier = f.effect != new;
            let value = if earlier {
                before.effects[f.effect].values[f.param]
            } else {
                model.effects[f.effect].values[f.param]
            };
            model.effects[f.effect].values[f.param] = value;
            let others: Vec<String> = r
                .estimates
                .iter()
                .filter(|e| e.ci95.is_none())
                .map(|e| format!("{}.{}", e.effect, e.name))
                .filter(|n| *n != label(&model, f))
                .collect();
            let reason =
                format!(
            "the data cannot fix it together with {} (the fit leaves {} free); held at {} {}",
            if others.is_empty() { "the other parameters".to_string() } else { others.join(", ") },
            if r.held.is_empty() { "a combination".to_string() } else { r.held.join("; ") },
            if earlier { "its earlier value" } else { "its fitted value" },
            crate::format::fmt_sig(value, 4)
        );
            notes.push(format!("{} fixed: {reason}", label(&model, f)));
            fixed.push(Fixed {
                at: f,
                value,
                reason,
            });
        };
    let params = records(&model, new, &free, result.as_ref(), &fixed);
    let refitted = if refit_all {
        (first_step..new)
            .flat_map(|e| records(&model, e, &free, result.as_ref(), &fixed))
            .filter(|p| p.status == "fitted")
            .collect()
    } else {
        Vec::new()
    };
    if refit_all {
        notes.insert(0, "earlier steps refitted jointly with this one".into());
    } else if first_step < new {
        let held: Vec<&str> = model.effects[first_step..new]
            .iter()
            .map(|e| e.name())
            .collect();
        notes.insert(
            0,
            format!("earlier steps held at their values: {}", held.join(", ")),
        );
    }
    if let Some(r) = &result {
        notes.extend(
            r.non_identifiable
                .iter()
                .map(|w| format!("strongly correlated: {w}")),
        );
        if !r.converged {
            notes.push("the optimiser did not report convergence".into());
        }
    }
    for p in params.iter().chain(&refitted).filter(|p| p.at_bound) {
        notes.push(format!(
            "{}.{} ended on its bound: the data push beyond the allowed range",
            p.effect, p.name
        ));
    }
    Ok(Calibrated {
        model,
        fitted: free,
        params,
        refitted,
        notes,
        reduced: !fixed.is_empty(),
    })
}

fn label(model: &Model, f: FreeParam) -> String {
    let e = &model.effects[f.effect];
    format!("{}.{}", e.name(), e.effect.params()[f.param].name)
}

/// The free parameter to fix when the fit leaves some without an
/// interval: an earlier step's first (the new step is what is asked
/// about), else the new step's last.
fn unfixable(r: &FitResult, free: &[FreeParam], new: usize) -> Option<usize> {
    let missing: Vec<usize> = (0..free.len())
        .filter(|&i| r.estimates.get(i).is_some_and(|e| e.ci95.is_none()))
        .collect();
    missing
        .iter()
        .copied()
        .find(|&i| free[i].effect != new)
        .or(missing.last().copied())
}

/// Every parameter of effect `e` as the study records it.
fn records(
    model: &Model,
    e: usize,
    free: &[FreeParam],
    result: Option<&FitResult>,
    fixed: &[Fixed],
) -> Vec<ParamRecord> {
    let inst = &model.effects[e];
    inst.effect
        .params()
        .iter()
        .enumerate()
        .map(|(p, spec)| {
            let at = FreeParam {
                effect: e,
                param: p,
            };
            let value = inst.values[p];
            let mut rec = ParamRecord {
                effect: inst.name().to_string(),
                name: spec.name.to_string(),
                unit: spec.unit.to_string(),
                value,
                status: "setting".into(),
                lo: None,
                hi: None,
                at_bound: false,
                reason: None,
            };
            if let Some(i) = free.iter().position(|f| *f == at) {
                let est = result.and_then(|r| r.estimates.get(i));
                rec.status = "fitted".into();
                if let Some(ci) = est.and_then(|x| x.ci95) {
                    rec.lo = Some(value - ci);
                    rec.hi = Some(value + ci);
                }
                rec.at_bound = est.is_some_and(|x| x.at_bound);
            } else if let Some(f) = fixed.iter().find(|f| f.at == at) {
                rec.status = "fixed".into();
                rec.value = f.value;
                rec.reason = Some(f.reason.clone());
            } else if spec.free {
                rec.status = "held".into();
            }
            rec
        })
        .collect()
}
