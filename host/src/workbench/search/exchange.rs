//! Exchange (Miller's replacement algorithm) on the best sets of the beam:
//! each member in turn is dropped, the laws are screened on the response
//! table of the model of the others at their joint values, and the best
//! few laws at places the others do not hold take its place; every new
//! set is refitted jointly. A set of the beam is grown member by member,
//! so a member chosen early keeps what it took of effects found later;
//! exchange lets it go once the others are in.
//!
//! Two members can hold parts of each other's effects so that replacing
//! either alone raises the key (on a drawn three-effect design, a tail
//! drag in the wire's gap beside a body drag in `D_body / gap`, where the
//! library's best pair is the tail drag in the helix's gap beside the body
//! drag in the body's gap ratio: 70 lower in key, and neither move alone
//! reaches it);
//! the pair move keeps one member and replaces the other two together.
//! The same single replacement at every place, not only the best few,
//! gives the chosen set's neighbours ([`neighbours`]).
//!
//! References: A. J. Miller, *Subset Selection in Regression*, 2nd ed.
//! (2002), ch. 3 (sequential replacement, and replacing more than one
//! variable at a time).

use super::beam::best_of;
use super::fitted::{fit_fresh, Ctx, Fitted};
use super::screened::{screens_on, OnModel, Screens};
use super::set::{model_with, Member};
use super::settings::Breadth;
use super::speed_pairs::speed_pairs;
use rayon::prelude::*;

/// Up to `exchange_rounds` rounds of exchange
/// ([`super::settings::SearchSettings`]) on the breadth's `exchange_width`
/// best sets of each size from 2 to `most` in `all` (one per combination
/// of places), each member replaced by its `exchange_laws` best laws
/// screened on the model of the others; new sets join `all`. The rounds stop when one finds no set
/// with a lower key than every set before it.
pub(super) fn rounds(
    ctx: &Ctx,
    all: &mut Vec<Fitted>,
    most: usize,
    breadth: Breadth,
    law_charge: f64,
) {
    let (width, laws) = (breadth.exchange_width, breadth.exchange_laws);
    for _ in 0..ctx.s.search.exchange_rounds {
        let best: Vec<Fitted> = (2..=most)
            .flat_map(|size| best_of(all, size, width, None))
            .collect();
        let lowest = |v: &[Fitted]| v.iter().map(|f| f.joint.key).fold(f64::INFINITY, f64::min);
        let before = lowest(all);
        let have: Vec<Vec<String>> = all.iter().map(Fitted::ids).collect();
        let new = exchanged(ctx, &best, have, laws, law_charge);
        let improved = lowest(&new) < before;
        all.extend(new);
        if !improved {
            break;
        }
    }
}

/// Every set one exchange away from one of `sets` and not in `seen`
/// (member ids): each member replaced by the `per_member` best laws
/// screened on the model of the others.
fn exchanged(
    ctx: &Ctx,
    sets: &[Fitted],
    seen: Vec<Vec<String>>,
    per_member: usize,
    law_charge: f64,
) -> Vec<Fitted> {
    let tries: Vec<Vec<Member>> = sets
        .par_iter()
        .flat_map(|f| {
            let singles = (0..f.members.len())
                .into_par_iter()
                .flat_map(|i| replacements(ctx, f, i, per_member, law_charge));
            // A pair move keeps one member: it needs three.
            let kept = if f.members.len() > 2 {
                f.members.len()
            } else {
                0
            };
            let pairs = (0..kept)
                .into_par_iter()
                .flat_map(|i| pair_replacements(ctx, f, i, per_member, law_charge));
            singles.chain(pairs).collect::<Vec<_>>()
        })
        .collect();
    fit_fresh(ctx, tries, seen)
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
    laws_on(ctx, &others, per_member, law_charge)
        .into_iter()
        .map(|law| {
            let mut m = others.clone();
            m.push(law);
            m
        })
        .collect()
}

/// The sets that keep member `keep` of `f` and replace the other two
/// together: the `per_member` best laws screened on the kept member's
/// model, each followed by the best law screened on the model of both.
fn pair_replacements(
    ctx: &Ctx,
    f: &Fitted,
    keep: usize,
    per_member: usize,
    law_charge: f64,
) -> Vec<Vec<Member>> {
    let kept = vec![f.members[keep].clone()];
    let Some((on, taken, k)) = on_members(ctx, &kept, Screens::Both) else {
        return Vec::new();
    };
    let screened = on
        .best_laws(&taken, (k, per_member), law_charge)
        .into_par_iter()
        .filter_map(|a| {
            let mut two = kept.clone();
            two.push(a);
            let b = completion(ctx, &two, law_charge)?;
            two.push(b);
            Some(two)
        });
    let on_the_speed = speed_pairs(ctx, &kept, &on, law_charge)
        .into_par_iter()
        .map(|pair| kept.iter().cloned().chain(pair).collect());
    screened.chain(on_the_speed).collect()
}

/// The `n` best laws (of each screen) on the model of `members` at their
/// values, at places they do not hold.
fn laws_on(ctx: &Ctx, members: &[Member], n: usize, law_charge: f64) -> Vec<Member> {
    laws_screened(ctx, members, n, Screens::Both, law_charge)
}

/// The one law that completes a pair move: the best of the held screen
/// on the model of `members`, the freed screen's only when the held one
/// offers none. The held screen's best comes first among both screens'
/// laws, so the freed screen is not run to be set aside.
fn completion(ctx: &Ctx, members: &[Member], law_charge: f64) -> Option<Member> {
    let first = |screens| {
        laws_screened(ctx, members, 1, screens, law_charge)
            .into_iter()
            .next()
    };
    first(Screens::Held).or_else(|| first(Screens::Both))
}

fn laws_screened(
    ctx: &Ctx,
    members: &[Member],
    n: usize,
    screens: Screens,
    law_charge: f64,
) -> Vec<Member> {
    on_members(ctx, members, screens).map_or_else(Vec::new, |(on, taken, k)| {
        on.best_laws(&taken, (k, n), law_charge)
    })
}

/// The screens on the model of `members` at their values, with the places
/// they hold and the parameters they add.
fn on_members<'m>(
    ctx: &Ctx,
    members: &'m [Member],
    screens: Screens,
) -> Option<(OnModel, Vec<&'m str>, usize)> {
    let on = screens_on(ctx, model_with(ctx.model0, members), screens)?;
    let taken = members.iter().filter_map(|m| m.place).collect();
    let k = members.iter().map(Member::n_params).sum();
    Some((on, taken, k))
}

/// Every set one member away from `f`: each member replaced by the best
/// law at every place the others do not hold, refitted jointly (sets in
/// `seen` skipped). A set is claimed against all its neighbours, not only
/// against those the beam happened to fit.
pub(super) fn neighbours(
    ctx: &Ctx,
    f: &Fitted,
    seen: Vec<Vec<String>>,
    law_charge: f64,
) -> Vec<Fitted> {
    let tries: Vec<Vec<Member>> = (0..f.members.len())
        .into_par_iter()
        .flat_map(|i| replacements(ctx, f, i, usize::MAX, law_charge))
        .collect();
    fit_fresh(ctx, tries, seen)
}
