//! The laws screened on top of a set's fitted model: what extends a set
//! in the beam, replaces a member in exchange, or makes a neighbour of
//! the chosen set. Each is the best screened law at its place, pending
//! its joint refit.

use super::fitted::Ctx;
use super::set::{law_id, Member};
use crate::effects::EffectInstance;
use crate::model::Model;
use crate::workbench::discovery::aicc;
use crate::workbench::discovery::places::{best_at_each_place, AtPlace};
use crate::workbench::discovery::projection::Span;
use crate::workbench::discovery::search::Screen;
use crate::workbench::discovery::Table;
use std::sync::Arc;

/// Which screens offer the laws tried on top of members
/// ([`best_laws_on`]). Both approximate the joint refit of a law with the
/// members: one holds the members at their values, the other frees them to
/// first order ([`Span`], the added-variable screen). Held, members that
/// took a share of the law's effect hide it; freed, the linearisation fails
/// where adding the law moves the members far: on the paper's data, about
/// 2000 times above its floor, the freed screen's best companion of the
/// body correction is an external load torque of -300 uN m that the choice
/// refuses, the held screen's a law on the body's E_x that it accepts.
///
/// Near the floor both are offered: on two drawn two-effect truths
/// (integration tests, seeds 205 and the stagewise pair) exchange with
/// the freed screen alone split the oil over two tail places, and no
/// acceptable pair reached the floor.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Screens {
    /// Far above the floor ([`super::FAR_ABOVE`]): the beam's only screen there.
    Held,
    /// The best of each: the beam while some single is near its floor,
    /// exchange and the chosen set's neighbours (which run only near it).
    Both,
}

/// The `n` best laws screened on `model` at places not in `taken` (of
/// each of the `screens`), by their screened AICc on top of the `k`
/// parameters `model` adds, as members: what extends a set, or replaces
/// one of its members.
pub(super) fn best_laws_on(
    ctx: &Ctx,
    model: &Model,
    taken: &[&str],
    (k, n): (usize, usize),
    screens: Screens,
    law_charge: f64,
) -> Vec<Member> {
    let Ok(table) = Table::build(model, ctx.data) else {
        return Vec::new();
    };
    let cases = ctx.s.discovery.screen_cases;
    let held = Screen::run(&table, ctx.data, cases);
    let mut out = best_by_place(&table, &held, taken, k, n, law_charge);
    let span = match screens {
        Screens::Held => None,
        Screens::Both => Span::of(model, ctx.model0.effects.len(), ctx.data, &table),
    };
    // Without a member to free, the two screens are one.
    if let Some(span) = span {
        let free = Screen::run_free(&table, ctx.data, cases, Some(&span));
        for m in best_by_place(&table, &free, taken, k, n, law_charge) {
            if !out.iter().any(|o| o.id == m.id) {
                out.push(m);
            }
        }
    }
    out
}

/// The `n` best laws of one screen at places not in `taken` (one per
/// place), by screened AICc on top of `k` parameters.
pub(super) fn best_by_place(
    table: &Table,
    screen: &Screen,
    taken: &[&str],
    k: usize,
    n: usize,
    law_charge: f64,
) -> Vec<Member> {
    let n_sub = screen.sub.len();
    let mut ats = best_at_each_place(table, screen, k);
    ats.retain(|a| !taken.contains(&a.place.name()));
    let key = |a: &AtPlace| {
        aicc(a.screened.chi2, n_sub, k + a.screened.params.len()).unwrap_or(f64::INFINITY)
    };
    ats.sort_by(|a, b| key(a).total_cmp(&key(b)));
    ats.into_iter()
        .take(n)
        .map(|at| pending_member(at, law_charge))
        .collect()
}

pub(super) fn pending_member(at: AtPlace, charge: f64) -> Member {
    let c = at.screened.correction.clone();
    Member {
        id: law_id(&c),
        insts: vec![EffectInstance {
            effect: c.clone().into(),
            values: at.screened.params.clone(),
        }],
        located: None,
        name: c.formula(),
        charge,
        place: Some(c.place.name()),
        pending: Some(Arc::new(at)),
    }
}
