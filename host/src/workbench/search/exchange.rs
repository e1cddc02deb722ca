//! Exchange (Miller's replacement algorithm) on the best sets of the beam:
//! each member in turn is dropped, the laws are screened on the response
//! table of the model of the others at their joint values, and the best
//! few laws at places the others do not hold take its place; every new
//! set is refitted jointly. A set of the beam is grown member by member,
//! so a member chosen early keeps what it took of effects found later;
//! exchange lets it go once the others are in.
//!
//! References: A. J. Miller, *Subset Selection in Regression*, 2nd ed.
//! (2002), ch. 3 (sequential replacement).

use super::set::Member;
use super::sorted_ids;
use super::{best_of, pending_member, Ctx, Fitted, EXCHANGE_ROUNDS};
use crate::workbench::discovery::places::best_at_each_place;
use crate::workbench::discovery::search::Screen;
use crate::workbench::discovery::{aicc, Table};
use rayon::prelude::*;

/// Up to [`EXCHANGE_ROUNDS`] rounds of exchange on the `width` best sets
/// of each size from 2 to `most` in `all` (one per combination of places),
/// each member replaced by the `laws` best laws screened on the model of
/// the others; new sets join `all`. The rounds stop when one finds no set
/// with a lower key than every set before it.
pub(super) fn rounds(
    ctx: &Ctx,
    all: &mut Vec<Fitted>,
    most: usize,
    width: usize,
    laws: usize,
    law_charge: f64,
) {
    for _ in 0..EXCHANGE_ROUNDS {
        let best: Vec<Fitted> = (2..=most)
            .flat_map(|size| best_of(all, size, width, None))
            .collect();
        let lowest = |v: &[Fitted]| v.iter().map(|f| f.joint.key).fold(f64::INFINITY, f64::min);
        let before = lowest(all);
        let have: Vec<Vec<String>> = all.iter().map(Fitted::ids).collect();
        let new: Vec<Fitted> = exchanged(ctx, &best, laws, law_charge)
            .into_iter()
            .filter(|f| !have.contains(&f.ids()))
            .collect();
        let improved = lowest(&new) < before;
        all.extend(new);
        if !improved {
            break;
        }
    }
}

/// Every set one exchange away from one of `sets`: each member replaced
/// by the `per_member` best laws screened on the model of the others.
fn exchanged(ctx: &Ctx, sets: &[Fitted], per_member: usize, law_charge: f64) -> Vec<Fitted> {
    let tries: Vec<Vec<Member>> = sets
        .par_iter()
        .flat_map(|f| {
            (0..f.members.len())
                .into_par_iter()
                .flat_map(|i| replacements(ctx, f, i, per_member, law_charge))
                .collect::<Vec<_>>()
        })
        .collect();
    let mut seen: Vec<Vec<String>> = sets.iter().map(Fitted::ids).collect();
    let fresh: Vec<Vec<Member>> = tries
        .into_iter()
        .filter(|m| {
            let ids = sorted_ids(m);
            let new = !seen.contains(&ids);
            seen.push(ids);
            new
        })
        .collect();
    fresh.into_par_iter().filter_map(|m| ctx.fit(m)).collect()
}

/// The sets that replace member `i` of `f`.
fn replacements(
    ctx: &Ctx,
    f: &Fitted,
    i: usize,
    per_member: usize,
    law_charge: f64,
) -> Vec<Vec<Member>> {
    let mut others = f.members.clone();
    others.remove(i);
    let mut model = ctx.model0.clone();
    for inst in others.iter().flat_map(|m| &m.insts) {
        model = model.with_effect(inst.clone());
    }
    let k: usize = others
        .iter()
        .flat_map(|m| &m.insts)
        .map(|x| x.values.len())
        .sum();
    let Ok(table) = Table::build(&model, ctx.data) else {
        return Vec::new();
    };
    let screen = Screen::run(&table, ctx.data, ctx.s.discovery.screen_cases);
    let n = screen.sub.len();
    let taken: Vec<&str> = others.iter().filter_map(|m| m.place).collect();
    let mut ats = best_at_each_place(&table, &screen, k);
    ats.retain(|a| !taken.contains(&a.place.name()));
    let key = |a: &crate::workbench::discovery::places::AtPlace| {
        aicc(a.screened.chi2, n, k + a.screened.params.len()).unwrap_or(f64::INFINITY)
    };
    ats.sort_by(|a, b| key(a).total_cmp(&key(b)));
    ats.into_iter()
        .take(per_member)
        .map(|at| {
            let mut m = others.clone();
            m.push(pending_member(at, law_charge));
            m
        })
        .collect()
}
