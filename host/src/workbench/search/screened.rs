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
    /// Far above the floor (`far_above`, [`super::settings::SearchSettings`]): the beam's only screen there.
    Held,
    /// The best of each: the beam while some single is near its floor,
    /// exchange and the chosen set's neighbours (which run only near it).
    Both,
}

/// A model's response table and the laws screened on it: what the laws
/// offered on top of a set's members are read from.
pub(super) struct OnModel {
    pub(super) model: Model,
    pub(super) table: Table,
    /// Every law screened with the members held at their values.
    pub(super) held: Screen,
    /// Every law screened with the members free to first order (with
    /// [`Screens::Both`] and members to free).
    pub(super) free: Option<Screen>,
}

/// The table of `model` and its screens (`None` when the model does not
/// predict every case).
pub(super) fn screens_on(ctx: &Ctx, model: Model, screens: Screens) -> Option<OnModel> {
    let table = Table::build(&model, ctx.data).ok()?;
    let cases = ctx.s.discovery.screen_cases;
    let held = Screen::run(&table, ctx.data, cases);
    let span = match screens {
        Screens::Held => None,
        Screens::Both => Span::of(&model, ctx.model0.effects.len(), ctx.data, &table),
    };
    // Without a member to free, the two screens are one.
    let free = span.map(|span| Screen::run_free(&table, ctx.data, cases, Some(&span)));
    Some(OnModel {
        model,
        table,
        held,
        free,
    })
}

impl OnModel {
    /// The `n` best laws of each screen at places not in `taken`, by their
    /// screened AICc on top of the `k` parameters the model adds, as
    /// members: what extends a set, or replaces one of its members.
    pub(super) fn best_laws(
        &self,
        taken: &[&str],
        (k, n): (usize, usize),
        law_charge: f64,
    ) -> Vec<Member> {
        let mut out = best_by_place(&self.table, &self.held, taken, k, n, law_charge);
        if let Some(free) = &self.free {
            for m in best_by_place(&self.table, free, taken, k, n, law_charge) {
                if !out.iter().any(|o| o.id == m.id) {
                    out.push(m);
                }
            }
        }
        out
    }
}

/// [`OnModel::best_laws`] on `model`'s own table and screens.
pub(super) fn best_laws_on(
    ctx: &Ctx,
    model: &Model,
    taken: &[&str],
    (k, n): (usize, usize),
    screens: Screens,
    law_charge: f64,
) -> Vec<Member> {
    screens_on(ctx, model.clone(), screens)
        .map_or_else(Vec::new, |on| on.best_laws(taken, (k, n), law_charge))
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
