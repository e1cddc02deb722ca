//! Which grown set `diagnose` states: the first set by key that explains
//! the data (at the noise floor before any above it) and in which every
//! member pays for itself, no law's strength interval spans "no effect"
//! and no law leaves its place's physical range; an incumbent is replaced
//! only by a set that beats it clearly. Far above the floor, where only
//! misfit is ranked, a larger set must be a nested extension that lowers
//! the cross-validated error (module docs of [`super`], step 4).

use super::fitted::{Ctx, Fitted};
use super::level::MIN_SHARE;
use super::set::joint;
use crate::effects::correction::Form;
use crate::workbench::discovery::explained_fraction;
use crate::workbench::robust::t_deviance_of;

/// The first acceptable set by key that may replace the incumbent; the
/// incumbent itself when it comes first (module docs, step 4). When even
/// that set stays more than `far_above` ([`super::settings::SearchSettings`]) times above the noise floor, the
/// sets are nested instead (module docs).
pub(super) fn choose(ctx: &Ctx, mut all: Vec<Fitted>, inc: Option<&Fitted>) -> Option<Fitted> {
    all.sort_by(|a, b| a.joint.key.total_cmp(&b.joint.key));
    let first = first_choice(ctx, &all, inc)?;
    let far = ctx.is_far(&first);
    if !far || inc.is_some() {
        return Some(first);
    }
    nested(ctx, &all)
}

fn first_choice(ctx: &Ctx, all: &[Fitted], inc: Option<&Fitted>) -> Option<Fitted> {
    // A set at the floor explains the data; among those the key decides
    // (an extra member is in only when it pays for itself, `acceptable`).
    let at: Vec<&Fitted> = all.iter().filter(|f| f.joint.at_floor).collect();
    if let Some(f) = pick(ctx, &at, inc) {
        return Some(f);
    }
    let above: Vec<&Fitted> = all.iter().filter(|f| !f.joint.at_floor).collect();
    pick(ctx, &above, inc).or_else(|| inc.cloned())
}

/// The first of `sets` (in key order) that is acceptable and may replace
/// the incumbent; the incumbent itself when it is met first or none may.
fn pick(ctx: &Ctx, sets: &[&Fitted], inc: Option<&Fitted>) -> Option<Fitted> {
    let margin = ctx.s.clear_margin;
    for f in sets {
        if let Some(i) = inc {
            if i.ids() == f.ids() {
                return Some(i.clone());
            }
            if i.joint.at_floor && f.members.len() > i.members.len() {
                return None;
            }
            // A smaller set only needs a lower key (a member dropped); a
            // set as large or larger must win clearly.
            let need = if f.members.len() < i.members.len() {
                0.0
            } else {
                margin
            };
            if f.joint.key + need >= i.joint.key {
                continue;
            }
            let share = explained_fraction(i.joint.fit.chi2, f.joint.fit.chi2, ctx.floor0());
            let beats = f.joint.at_floor || share.is_some_and(|x| x >= MIN_SHARE);
            if !beats {
                continue;
            }
        }
        if acceptable(ctx, f) {
            return Some((*f).clone());
        }
    }
    None
}

/// Far above the floor, every set ranks misfits: the best acceptable
/// single, then the best acceptable set that adds one member to the last,
/// while one does.
fn nested(ctx: &Ctx, all: &[Fitted]) -> Option<Fitted> {
    let mut cur: Option<Fitted> = None;
    // Far above the floor the in-sample key ranks misfits: a member must
    // also lower the cross-validated MARE, as the base model's MARE for
    // the first.
    let mut cv_cur = ctx.base.mare;
    for size in 1..=ctx.s.search.max_laws {
        let inside = |f: &&Fitted| {
            cur.as_ref()
                .is_none_or(|c| c.ids().iter().all(|id| f.ids().contains(id)))
        };
        let next = all
            .iter()
            .filter(|f| f.members.len() == size)
            .filter(inside)
            .filter(|f| acceptable(ctx, f))
            .find_map(|f| {
                let cv = cv_mare(ctx, f);
                (cv < cv_cur).then(|| (f.clone(), cv))
            });
        match next {
            Some((n, cv)) => {
                cur = Some(n);
                cv_cur = cv;
            }
            None => break,
        }
    }
    cur
}

/// The set's cross-validated MARE: every parameter it adds refitted on
/// each fold ([`crate::workbench::candidate::cross_validated_mare`]).
fn cv_mare(ctx: &Ctx, f: &Fitted) -> f64 {
    let model = &f.joint.fit.model;
    let added: Vec<usize> = (ctx.model0.effects.len()..model.effects.len()).collect();
    let free = crate::workbench::fit::free_params_of(model, &added);
    crate::workbench::candidate::cross_validated_mare(model, ctx.data, &free, ctx.s.likelihood)
}

/// Whether a law's strength, in the set's joint fit, has a 95 % interval
/// that contains the value at which the law does nothing, or no interval
/// at all: the data do not show that member, however it moves the key (a near-constant law at the
/// floor can tip a set over its 95 % quantile without being there).
fn strength_spans_no_effect(f: &Fitted) -> bool {
    let mut at = 0;
    f.members.iter().any(|m| {
        let first = at;
        at += m
            .insts
            .iter()
            .map(|i| i.free_indices().len())
            .sum::<usize>();
        let Some(law) = m.law() else {
            return false;
        };
        // A strength whose interval cannot be computed (the fit leaves it
        // free) is not shown either.
        let within = |i: usize, n: f64| {
            f.joint
                .fit
                .estimates
                .get(first + i)
                .is_some_and(|e| e.ci95.is_none_or(|ci| (e.value - n).abs() <= ci))
        };
        match super::joint::no_effect_value(law.form, law.place.is_additive()) {
            Some(n) => within(0, n),
            // `k x^p` does nothing at k = 1 and p = 0 together.
            None if law.form == Form::PowerLaw => within(0, 1.0) && within(1, 0.0),
            None => false,
        }
    })
}

/// Whether the set beats the starting model by its charges on both
/// deviances, and every member pays for itself (module docs).
pub(super) fn acceptable(ctx: &Ctx, f: &Fitted) -> bool {
    if f.outside.is_some() || strength_spans_no_effect(f) {
        return false;
    }
    let cost: f64 = f
        .members
        .iter()
        .map(|m| 2.0 * m.n_params() as f64 + m.charge)
        .sum();
    let Ok(t) = t_deviance_of(&f.joint.fit.model, ctx.data) else {
        return false;
    };
    if ctx.base.chi2 - f.joint.fit.chi2 < cost || ctx.base.t_deviance - t < cost {
        return false;
    }
    (0..f.members.len()).all(|i| {
        let mut others = f.members.clone();
        others.remove(i);
        let (key, chi2) = if others.is_empty() {
            (ctx.base_key(), ctx.base.chi2)
        } else {
            // The others refitted from the set's own values as well as
            // from wherever they were fitted before: a joint fit can stop
            // in a worse minimum, and a member must not pay for that.
            let warm = joint(ctx.model0, &others, ctx.data, ctx.floor, ctx.s.likelihood).ok();
            let cached = ctx.fit(others);
            let best = [warm, cached.map(|c| c.joint)]
                .into_iter()
                .flatten()
                .min_by(|a, b| a.key.total_cmp(&b.key));
            match best {
                Some(o) => (o.key, o.fit.chi2),
                None => return false,
            }
        };
        let pays = key - f.joint.key > ctx.s.clear_margin;
        let share = explained_fraction(chi2, f.joint.fit.chi2, ctx.floor0());
        pays && (f.joint.at_floor || share.is_some_and(|x| x >= MIN_SHARE))
    })
}
