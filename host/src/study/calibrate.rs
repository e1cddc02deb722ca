//! Calibrating a new step on top of the study's model: its free parameters
//! fitted with the earlier steps held (or, asked, all refitted jointly);
//! a parameter the data cannot fix together with the others is fixed (an
//! earlier step's at its earlier value, the new step's at its fitted
//! value) and the rest refitted, so that every stored parameter has an
//! interval or a reason, never "±?".

use super::file::{ParamRecord, ProfileRecord};
use crate::data::Dataset;
use crate::format::fmt_sig;
use crate::model::Model;
use crate::workbench::fit::profile::profile_of;
use crate::workbench::fit::{fit_with, free_params_of, FitError, FitResult, FreeParam};
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
) -> Result<Calibrated, FitError> {
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
            let r = fit_with(&model, data, None, &free, true, likelihood)?;
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
            fmt_sig(value, 4)
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

/// Store the profile-likelihood interval of each fitted parameter of the
/// new (last) effect of `c`, beside its covariance interval: profiled
/// within the fit `c` kept (every parameter it frees refitted at each
/// trial value), by the code and rule `diagnose` uses
/// ([`crate::workbench::fit::profile`]). A profile whose refit fails
/// leaves the covariance's intervals, and a note says so.
pub fn profile_new(c: &mut Calibrated, data: &Dataset, likelihood: Likelihood) {
    let new = c.model.effects.len() - 1;
    let which: Vec<usize> = (0..c.fitted.len())
        .filter(|&i| c.fitted[i].effect == new)
        .collect();
    if which.is_empty() {
        return;
    }
    let intervals = match profile_of(&c.model, data, &c.fitted, &which, likelihood) {
        Ok((_, intervals)) => intervals,
        Err(e) => {
            c.notes.push(format!(
                "the profile likelihood could not be computed ({e}): the intervals are the covariance's"
            ));
            return;
        }
    };
    for (&i, p) in which.iter().zip(&intervals) {
        let Some(rec) = c.params.get_mut(c.fitted[i].param) else {
            continue;
        };
        // A profile is of the optimum it starts from; one whose refit
        // found another (its interval not holding the stored value) says
        // nothing of the stored value's interval.
        let holds = p.low.is_none_or(|l| l <= rec.value) && p.high.is_none_or(|h| rec.value <= h);
        if rec.standard_uncertainty.is_none() {
            continue;
        } else if holds {
            rec.profile = Some(ProfileRecord::of(p));
        } else {
            c.notes.push(format!(
                "{}.{}: the profile likelihood's refit left the fitted value ({} .. {} against {}): its interval is the covariance's",
                rec.effect,
                rec.name,
                p.low.map_or("open".into(), |x| fmt_sig(x, 4)),
                p.high.map_or("open".into(), |x| fmt_sig(x, 4)),
                fmt_sig(rec.value, 4)
            ));
        }
    }
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
                standard_uncertainty: None,
                at_bound: false,
                reason: None,
                profile: None,
            };
            if let Some(i) = free.iter().position(|f| *f == at) {
                let est = result.and_then(|r| r.estimates.get(i));
                rec.status = "fitted".into();
                if let Some(ci) = est.and_then(|x| x.ci95) {
                    let (lo, hi, cut) = interval_in_range(value, ci, spec.min, spec.max);
                    rec.lo = Some(lo);
                    rec.hi = Some(hi);
                    rec.reason = cut;
                    rec.standard_uncertainty = Some(ci.abs() / crate::workbench::fit::report::Z95);
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

/// The 95 % interval `value +- ci` within the parameter's range
/// `[min, max]`, and, when it was cut, why. A linearised interval knows
/// nothing of the range: through a drag factor's lower bound it would
/// report a negative drag, which no data allow. Cut at the bound, the end
/// says only that the data do not bound the parameter on that side
/// (M. Mandelkern, Stat. Sci. 17 (2002) 149, intervals for bounded
/// parameters).
fn interval_in_range(value: f64, ci: f64, min: f64, max: f64) -> (f64, f64, Option<String>) {
    let (lo, hi) = (value - ci, value + ci);
    let cut = (lo < min || hi > max).then(|| {
        format!(
            "the linearised 95 % interval {} .. {} is cut at the parameter's range {} .. {}: the data do not bound it on that side",
            fmt_sig(lo, 4),
            fmt_sig(hi, 4),
            fmt_sig(min, 4),
            fmt_sig(max, 4)
        )
    });
    (lo.max(min), hi.min(max), cut)
}

#[cfg(test)]
mod interval_tests {
    use super::interval_in_range;

    #[test]
    fn an_interval_through_a_bound_ends_at_it_and_says_so() {
        // The paper data's body-correction translation: 25.72 +- 52.64.
        let (lo, hi, why) = interval_in_range(25.72, 52.64, 0.01, 100.0);
        assert_eq!((lo, hi), (0.01, 78.36));
        let why = why.expect("cut");
        assert!(why.contains("-26.92") && why.contains("0.01"), "{why}");
        let (lo, hi, why) = interval_in_range(2.638, 0.265, 0.01, 100.0);
        assert!((lo - 2.373).abs() < 1e-12 && (hi - 2.903).abs() < 1e-12);
        assert_eq!(why, None, "inside the range: nothing cut");
    }
}
