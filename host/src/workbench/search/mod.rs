//! The search over subsets of `diagnose`: which set of at most
//! `max_laws` laws and catalogue effects, fitted JOINTLY, explains the
//! data best?
//!
//! A greedy search takes the best first step and builds on it; on data
//! with several effects that first step takes shares of all of them, and
//! no later step can give them back. Here every set is refitted with all
//! its parameters free (the exact model, [`crate::workbench::fit`]) and
//! ranked by one key, `AICc + sum 2 ln M` over its members (`M`: the laws
//! screened, or the catalogue effects, each was chosen from):
//!
//! 1. **Singles**: every catalogue effect (already fitted by `diagnose`),
//!    the exact refits of the search on the starting model
//!    ([`super::discovery`]), and the best screened law at each place the
//!    model is sensitive to (a constant is a law with one parameter and
//!    wins its place when the data prefer it), each fitted alone.
//! 2. **Beam**: the `beam` best sets of each size (at most one set per
//!    combination of places) are extended: on the response table of the
//!    set's fitted model, the best screened law at each place not yet in
//!    the set (each member of the incumbent alone is extended too); the
//!    `extend` best of those by screened AICc, and the
//!    `catalogue_extend` best catalogue effects not in the set, are
//!    added and every parameter of the new set is refitted jointly. Sets
//!    at the noise floor are extended too: a larger set may tie them
//!    within the noise, and the verdict must say so (`rivals`).
//!    Beside them, the best single law at each of the `paired` best places
//!    is paired with each other's, from scratch: two effects at two places
//!    are each found alone in their own form, while whatever is screened on
//!    top of a first step that took shares of both is biased by it.
//! 3. **Exchange** (`exchange`, Miller's replacement algorithm): the
//!    `exchange_width` best sets of each size from two up have each
//!    member in turn replaced by the `exchange_laws` best laws screened
//!    on the model of the other members, and each set of three has each
//!    member kept while the other two are replaced together (the
//!    `exchange_laws` best laws on the kept member's model, each followed
//!    by the held screen's best law on the model of both); every new set
//!    is refitted jointly, up to `exchange_rounds` rounds, while a round
//!    lowers the best key. A set grown member by member keeps what its first member
//!    took of the effects found after it; exchange gives that back, and
//!    the pair move gives back what two members hold of each other's
//!    effects, where no single replacement lowers the key. The pair move
//!    also places two laws at the places that set the speed alone in the
//!    paper's drive (`body.D_x`, `tail.drag`, `tail.thrust`) together
//!    (`speed_pairs`): every pair of the best screened laws there is
//!    fitted jointly on each case's force balance, exactly and without a
//!    model solve, and the best few pairs join the kept member.
//!
//! Near the floor, every law screened on top of members (steps 2 and 3)
//! is screened twice, with the members held at their values and with their
//! parameters free to first order (the added-variable screen,
//! [`super::discovery::projection`]), and the best of each are offered:
//! held, members that took a share of the law's effect make the screen
//! rank first the law least like them, not the one the data want
//! (`screened::Screens` says where each screen fails).
//!
//! 4. **Choice**: the sets at the noise floor in order of their key, then
//!    (when none reaches it) the others in order of their key. The first
//!    that is **acceptable** wins. A set is acceptable when every law in it
//!    lies inside its place's physical range on every case ([`ranges`]: a
//!    drive at a tenth of its recorded rate explains nothing), every law's
//!    strength is shown by the data (its joint 95 % interval excludes the
//!    value at which the law does nothing: a near-constant law can tip a set
//!    over the floor's 95 % quantile without being there), it lowers the
//!    chi-square and the Student-t deviance ([`super::robust`]: one bad
//!    run cannot pay for it) below the starting model's by at least its
//!    charges (`sum 2k + 2 ln M`), and **every member pays for itself**:
//!    the set without it, refitted, has a key higher by more than the AICc
//!    margin (`clear_margin`, 4), and when the set is above the noise
//!    floor, dropping the member leaves at least twice what the set leaves
//!    above the floor ([`level::MIN_SHARE`]: a member that only shaves a misfit is
//!    not physics; on the paper's data, far above the floor everywhere,
//!    this is what refuses a constant external torque of -300 uN m on the
//!    body beside the body correction).
//!
//!    The set chosen is then set against every set one member away from
//!    it (each member replaced by the best law at every place the others
//!    do not hold, refitted) and the choice is made again with them: a
//!    set is claimed against all its neighbours, not only against those
//!    the beam happened to fit. Skipped, like exchange, while every set
//!    stays `far_above` times above its floor.
//!
//! When every single stays more than `far_above` times above the floor,
//! one set of each size is extended (3 laws each) and no pairs are placed
//! from scratch: a cost bound (a 200-case set about 800 times above its
//! floor took 33 s of CPU with the full beam). No set is exchanged while
//! every set stays that far above.
//!
//! When even the chosen set stays more than `far_above` times above the
//! noise floor, no set explains the data and the joint ranking only ranks
//! misfits: there the sets are **nested** instead (the best acceptable
//! single, then the best acceptable set that adds one member to it, ...),
//! each one lowering the cross-validated MARE below the one before (the
//! base model's MARE for the first).
//! On the paper's data (about 2000 times the floor) the joint ranking
//! alone prefers a drive turning at 0.11-0.14 of the recorded rate (87 %
//! slip, against a tail rate counted on video to 2 %) beside a law on the
//! body's E_x whose strength trades with it (|r| = 0.99): two members the
//! data fix only together, found because together they shave the misfit.
//!
//! When the single-step verdict already named something (a catalogue
//! effect, a located law, or both), that set is the incumbent. One member
//! at the floor is kept without a search (only a single could replace
//! it, and the single-step verdict has weighed every single); otherwise it stays
//! unless an acceptable set beats its key by the margin and reaches the
//! floor, or (the incumbent above the floor) removes at least half of what
//! the incumbent leaves above it.
//!
//! 5. **What the data cannot tell apart** (`rivals`): every other
//!    acceptable set at other places whose key is within the margin of the
//!    chosen one (at the floor when it is), the margin calibrated on data
//!    drawn from the chosen set's fit ([`calibrate`]); the verdict then
//!    lists them all ([`verdict`]).
//!
//! The chosen set is listed as levels ([`level::Found`]): its members in
//! the order the beam added them, each level the starting model with the
//! members up to it at the joint values.
//!
//! The numbers in backticks are the search's knobs, with their documented
//! defaults, in [`settings::SearchSettings`] (`DiagnoseSettings::search`):
//! they bound the cost; the key and the choice stay the same at any
//! setting.
//!
//! References: A. J. Miller, *Subset Selection in Regression*, 2nd ed.
//! (2002), ch. 3 (searches over subsets, their bias); K. P. Burnham &
//! D. R. Anderson, *Model Selection and Multimodel Inference*, 2nd ed.
//! (2002), ch. 2 (AICc); S. J. Russell & P. Norvig, *Artificial
//! Intelligence*, 3rd ed. (2010), sec. 4.1.1 (local beam search).

mod beam;
pub mod calibrate;
mod choose;
mod exchange;
mod fitted;
pub mod joint;
mod joint_text;
pub mod level;
pub mod ranges;
mod rivals;
mod screened;
mod set;
pub mod settings;
mod speed_pairs;
pub mod stability;
pub mod verdict;

use super::diagnosis::{DiagnoseSettings, Verdict, VerdictKind};
use super::discovery::{explained_fraction, Reference};
use super::fit::FitError;
use super::robust::{t_deviance_of, Likelihood};
use super::score::Deviance;
use super::verdict::Evidence;
use crate::model::Model;
use beam::{best_of, extended, pairs_of_places, singles};
use choose::acceptable;
use fitted::{Ctx, Fitted};
use level::{first_steps, Floor, Found, Level, Steps};
use screened::Screens;
use set::{members, rebuild};
use std::collections::HashMap;
use std::sync::Mutex;

/// The starting model as a level.
fn base_level(model: &Model, e: &Evidence, lik: Likelihood) -> Result<Level, FitError> {
    let (data, base) = (e.data, e.base);
    Ok(Level {
        model: model.clone(),
        chi2: base.chi2,
        k: 0,
        mare: base.mare,
        cv_mare: base.mare,
        chi2_reduced: base.chi2_reduced,
        t_deviance: t_deviance_of(model, data)?,
        minimised: Deviance::of_model(model, data, base.chi2, lik)?.minimised,
        at_floor: base.at_noise_floor,
    })
}

/// The search (module docs) for `model` on the evidence's data.
pub fn search(
    model: &Model,
    e: &Evidence,
    v: &Verdict,
    floor: Floor,
    s: &DiagnoseSettings,
) -> Result<Found, FitError> {
    let empty = Found {
        steps: Vec::new(),
        added: 0,
        rivals: Vec::new(),
        margin: None,
    };
    if matches!(
        v.kind,
        VerdictKind::NoneNeeded | VerdictKind::Indistinguishable
    ) {
        return Ok(empty);
    }
    let base = base_level(model, e, s.likelihood)?;
    let first: Steps = first_steps(&base, e, v, floor)
        .into_iter()
        .map(|p| (p.step, p.level, p.located))
        .collect();
    let Some(d) = e.discovery else {
        return Ok(Found {
            added: 0,
            steps: first,
            rivals: Vec::new(),
            margin: None,
        });
    };
    // One member at the floor: only a single could replace it, and the
    // single-step verdict has already weighed every single (step 4).
    if first.len() == 1 && first[0].1.at_floor {
        return Ok(Found {
            added: 0,
            steps: first,
            rivals: Vec::new(),
            margin: None,
        });
    }
    let ctx = Ctx {
        model0: model,
        data: e.data,
        floor,
        s,
        base,
        cache: Mutex::new(HashMap::new()),
    };
    let law_charge = 2.0 * (d.screened.max(1) as f64).ln();
    // As the incumbent's members are charged ([`set::members`]).
    let n_cat = super::candidate::candidates(&s.catalogue, model, true).len();
    let cat_charge = 2.0 * (n_cat.max(1) as f64).ln();
    let incumbent = match first.is_empty() {
        true => None,
        false => ctx.fit(members(&s.catalogue, model, &first, d.screened)),
    };
    let mut all = singles(&ctx, e, law_charge, cat_charge)?;
    all.extend(incumbent.clone());
    // Each member of the incumbent alone is extended too: the exchange of
    // its other member is a set the beam must reach.
    let forced: Vec<Fitted> = match &incumbent {
        Some(i) if i.members.len() > 1 => i
            .members
            .iter()
            .filter_map(|m| ctx.fit(vec![m.clone()]))
            .collect(),
        _ => Vec::new(),
    };
    all.extend(forced.iter().cloned());
    let knobs = &s.search;
    // A cost bound, not a decision: when every single stays far above its
    // floor, the sets there rank misfits (the choice nests them, module
    // docs), so the beam narrows (`SearchSettings::far`).
    let far = all
        .iter()
        .filter(|f| f.members.len() == 1)
        .all(|f| ctx.is_far(f));
    let breadth = knobs.breadth_for(s.discovery.is_large(e.data.cases.len()), far);
    // A larger set never replaces an incumbent at the floor (step 4).
    let most = incumbent
        .as_ref()
        .filter(|i| i.joint.at_floor)
        .map_or(knobs.max_laws, |i| i.members.len());
    let mut level = all.clone();
    for size in 2..=most {
        let mut kept = best_of(&level, size - 1, breadth.beam, incumbent.as_ref());
        for f in forced.iter().filter(|f| f.members.len() == size - 1) {
            if !f.joint.at_floor && !kept.iter().any(|k| k.ids() == f.ids()) {
                kept.push(f.clone());
            }
        }
        let screens = if far { Screens::Held } else { Screens::Both };
        let mut next = extended(
            &ctx,
            e,
            &kept,
            breadth.extend,
            screens,
            law_charge,
            cat_charge,
        );
        if size == 2 {
            let paired = pairs_of_places(&ctx, &all, breadth.paired);
            let have: Vec<Vec<String>> = next.iter().map(Fitted::ids).collect();
            next.extend(paired.into_iter().filter(|f| !have.contains(&f.ids())));
        }
        if next.is_empty() {
            break;
        }
        all.extend(next.iter().cloned());
        level = next;
    }
    // Exchange refines sets that may explain the data: it is skipped when
    // every set so far stays far above its floor (the nested choice,
    // module docs), which also bounds its cost there.
    let near = all
        .iter()
        .any(|f| (ctx.floor)(f.joint.k).is_some_and(|fl| f.joint.fit.chi2 <= knobs.far_above * fl));
    if near {
        exchange::rounds(&ctx, &mut all, most, breadth, law_charge);
    }
    all.sort_by(|a, b| a.joint.key.total_cmp(&b.joint.key));
    let mut chosen = choose::choose(&ctx, all.clone(), incumbent.as_ref());
    // A set is chosen against every set one member away from it, not only
    // against those the beam and the exchange happened to fit.
    if let Some(c) = chosen.as_ref().filter(|_| near) {
        let seen: Vec<Vec<String>> = all.iter().map(Fitted::ids).collect();
        let next = exchange::neighbours(&ctx, c, seen, law_charge);
        if !next.is_empty() {
            all.extend(next);
            all.sort_by(|a, b| a.joint.key.total_cmp(&b.joint.key));
            chosen = choose::choose(&ctx, all.clone(), incumbent.as_ref());
        }
    }
    let Some(chosen) = chosen else {
        return Ok(empty);
    };
    let (rivals, margin) = rivals::of(&ctx, &all, &chosen);
    let margin = Some(margin);
    if incumbent.as_ref().is_some_and(|i| i.ids() == chosen.ids()) {
        return Ok(Found {
            added: 0,
            steps: first,
            rivals,
            margin,
        });
    }
    let inc_ids = incumbent.as_ref().map(Fitted::ids).unwrap_or_default();
    let added = chosen
        .members
        .iter()
        .filter(|m| !inc_ids.contains(&m.id))
        .count()
        .max(1);
    let mut found = listed(&ctx, chosen, added)?;
    found.rivals = rivals;
    found.margin = margin;
    Ok(found)
}

/// The chosen set as a path: each screened law located (refitted alone on
/// top of the members before it, for its finding's reading), then every
/// level at the joint values.
fn listed(ctx: &Ctx, chosen: Fitted, added: usize) -> Result<Found, FitError> {
    let mut members = chosen.members.clone();
    let mut prefix = ctx.model0.clone();
    let mut prev_chi2 = ctx.base.chi2;
    let mut k = 0;
    for m in &mut members {
        if let (None, Some(at)) = (&m.located, &m.pending) {
            let reference = Reference {
                chi2: prev_chi2,
                k,
                floor: ctx.floor,
                likelihood: ctx.s.likelihood,
            };
            let l = at.locate(&prefix, ctx.data, &reference)?;
            m.name = l.describe();
            m.located = Some(l);
        }
        for inst in &m.insts {
            prefix = prefix.with_effect(inst.clone());
            k += inst.effect.params().len();
        }
        prev_chi2 = super::compare::compare(&prefix, ctx.data, k)?.summary.chi2;
    }
    let mut steps = rebuild(
        ctx.model0,
        ctx.data,
        &members,
        &chosen.joint.fit.estimates,
        ctx.floor,
        ctx.s.likelihood,
    )?;
    let floor0 = ctx.floor0();
    let mut prev = ctx.base.chi2;
    for (step, level, located) in &mut steps {
        step.explained_fraction = explained_fraction(prev, level.chi2, floor0);
        if let Some(l) = located {
            l.on_top_of = step.on_top_of.clone();
        }
        prev = level.chi2;
    }
    Ok(Found {
        steps,
        added,
        rivals: Vec::new(),
        margin: None,
    })
}
