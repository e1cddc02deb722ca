//! The beam of the search over subsets (module docs of [`super`], steps
//! 1 and 2): every single fitted alone, the best sets of each size grown
//! by one screened law or catalogue effect, and the best single laws at
//! the best places paired from scratch.

use super::fitted::{fit_fresh, Ctx, Fitted};
use super::screened::{best_laws_on, pending_member, Screens};
use super::set::{law_id, Member};
use crate::workbench::discovery::places::best_at_each_place;
use crate::workbench::discovery::search::Screen;
use crate::workbench::discovery::Table;
use crate::workbench::fit::FitError;
use crate::workbench::verdict::Evidence;
use rayon::prelude::*;

/// Every single: catalogue effects, the search's exact refits, the best
/// screened law at each place; each fitted alone.
pub(super) fn singles(
    ctx: &Ctx,
    e: &Evidence,
    law_charge: f64,
    cat_charge: f64,
) -> Result<Vec<Fitted>, FitError> {
    let base_len = ctx.model0.effects.len();
    let mut lib: Vec<Member> = e
        .ranking
        .iter()
        .map(|c| Member::catalogue(c, base_len, cat_charge))
        .collect();
    if let Some(d) = e.discovery {
        for l in &d.located {
            lib.push(Member {
                id: law_id(&l.correction),
                insts: vec![l.model.effects.last().expect("a law adds one").clone()],
                located: Some(l.clone()),
                name: l.describe(),
                charge: law_charge,
                place: Some(l.place),
                pending: None,
            });
        }
    }
    let table = Table::build(ctx.model0, ctx.data)?;
    let screen = Screen::run(&table, ctx.data, ctx.s.discovery.screen_cases);
    for at in best_at_each_place(&table, &screen, 0) {
        let m = pending_member(at, law_charge);
        if !lib.iter().any(|o| o.id == m.id) {
            lib.push(m);
        }
    }
    Ok(lib
        .into_par_iter()
        .filter_map(|m| ctx.fit(vec![m]))
        .collect())
}

/// The `beam` best sets of `size` by key, one per combination of places,
/// the incumbent's always among them when it has that size; sets at the
/// floor are not extended.
pub(super) fn best_of(
    level: &[Fitted],
    size: usize,
    beam: usize,
    inc: Option<&Fitted>,
) -> Vec<Fitted> {
    // Sets at the floor are extended too: a set one member larger can tie
    // them within the margin, and the verdict must know it (`rivals`).
    let mut v: Vec<&Fitted> = level.iter().filter(|f| f.members.len() == size).collect();
    // Sets inside their places' ranges first: only they can be chosen.
    v.sort_by(|a, b| {
        (a.outside.is_some(), a.joint.key)
            .partial_cmp(&(b.outside.is_some(), b.joint.key))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    let mut seen: Vec<Vec<String>> = Vec::new();
    let mut out: Vec<Fitted> = Vec::new();
    if let Some(i) = inc.filter(|i| i.members.len() == size) {
        seen.push(i.signature());
        out.push(i.clone());
    }
    for f in v {
        if out.len() >= beam {
            break;
        }
        let sig = f.signature();
        if !seen.contains(&sig) {
            seen.push(sig);
            out.push(f.clone());
        }
    }
    out
}

/// Every pair of the best single laws at the `m` best places, refitted
/// jointly from their solo values: two effects at two places are each
/// found alone in their own form, while a first step that takes shares of
/// both would bias whatever is screened on top of it.
pub(super) fn pairs_of_places(ctx: &Ctx, all: &[Fitted], m: usize) -> Vec<Fitted> {
    let mut v: Vec<&Fitted> = all
        .iter()
        .filter(|f| f.members.len() == 1 && f.members[0].place.is_some())
        .collect();
    v.sort_by(|a, b| a.joint.key.total_cmp(&b.joint.key));
    let mut best: Vec<&Fitted> = Vec::new();
    for f in v {
        if best.len() < m
            && !best
                .iter()
                .any(|b| b.members[0].place == f.members[0].place)
        {
            best.push(f);
        }
    }
    let mut tries = Vec::new();
    for (i, a) in best.iter().enumerate() {
        for b in &best[i + 1..] {
            tries.push(vec![a.members[0].clone(), b.members[0].clone()]);
        }
    }
    tries.into_par_iter().filter_map(|t| ctx.fit(t)).collect()
}

/// Each kept set with one more member (module docs, step 2), refitted
/// jointly.
pub(super) fn extended(
    ctx: &Ctx,
    e: &Evidence,
    kept: &[Fitted],
    extend: usize,
    screens: Screens,
    law_charge: f64,
    cat_charge: f64,
) -> Vec<Fitted> {
    let base_len = ctx.model0.effects.len();
    let tries: Vec<Vec<Member>> = kept
        .par_iter()
        .flat_map(|f| {
            let mut out: Vec<Vec<Member>> = Vec::new();
            let model = &f.joint.fit.model;
            let places: Vec<&str> = f.members.iter().filter_map(|m| m.place).collect();
            for law in best_laws_on(
                ctx,
                model,
                &places,
                (f.joint.k, extend),
                screens,
                law_charge,
            ) {
                let mut m = f.members.clone();
                m.push(law);
                out.push(m);
            }
            let cats = e
                .ranking
                .iter()
                .filter(|c| !f.members.iter().any(|m| m.id == c.effect))
                .filter(|c| model.can_take(&*c.model.effects[base_len].effect))
                .take(ctx.s.search.catalogue_extend);
            for c in cats {
                let mut m = f.members.clone();
                m.push(Member::catalogue(c, base_len, cat_charge));
                out.push(m);
            }
            out
        })
        .collect();
    fit_fresh(ctx, tries, Vec::new())
}
