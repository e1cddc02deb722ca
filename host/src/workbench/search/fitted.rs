//! A set of laws and catalogue effects with its joint fit, and the
//! context every set is fitted and judged in: the starting model, the
//! data, the noise floor and a cache of the joint fits made so far.

use super::level::{n_obs, Floor, Level};
use super::ranges;
use super::set::{joint, with_values, Joint, Member};
use crate::data::Dataset;
use crate::model::Model;
use crate::workbench::diagnosis::DiagnoseSettings;
use rayon::prelude::*;
use std::collections::HashMap;
use std::sync::Mutex;

/// A set with its joint fit; members carry the joint values.
#[derive(Clone)]
pub(super) struct Fitted {
    pub(super) members: Vec<Member>,
    pub(super) joint: Joint,
    /// Why a member's fitted law lies outside what its place allows
    /// ([`ranges`]); `None` when every member is inside.
    pub(super) outside: Option<String>,
}

impl Fitted {
    pub(super) fn ids(&self) -> Vec<String> {
        sorted_ids(&self.members)
    }

    /// The places (and catalogue names) of the set: one beam entry each.
    pub(super) fn signature(&self) -> Vec<String> {
        let mut v: Vec<String> = self
            .members
            .iter()
            .map(|m| m.place.map_or_else(|| m.id.clone(), str::to_string))
            .collect();
        v.sort();
        v
    }
}

/// The first member whose law, at its fitted values, puts its place
/// outside what the place's physics allows, in words ([`ranges`]).
pub(super) fn outside_range(members: &[Member], data: &Dataset) -> Option<String> {
    members.iter().find_map(|m| {
        let law = m.law()?;
        let values = &m.insts.first()?.values;
        let (case, v, (lo, hi)) = ranges::outside(law, values, data)?;
        Some(format!(
            "{} is {} on case {case}, outside {lo} .. {hi}",
            law.place.name(),
            crate::format::fmt_sig(v, 3)
        ))
    })
}

pub(super) fn sorted_ids(members: &[Member]) -> Vec<String> {
    let mut v: Vec<String> = members.iter().map(|m| m.id.clone()).collect();
    v.sort();
    v
}

/// Each member's id with the bits of its start values, sorted by id.
type FitKey = Vec<(String, Vec<u64>)>;

/// A joint fit's identity: the members' ids with the bits of the values
/// it starts from. The fit is a local descent, so a set reached again
/// from other values may end elsewhere; keyed by ids alone, the cache
/// would hand back whichever start a parallel task reached first, and the
/// verdict would depend on thread timing.
fn fit_key(members: &[Member]) -> FitKey {
    let mut v: FitKey = members
        .iter()
        .map(|m| {
            let start = m.insts.iter().flat_map(|i| &i.values);
            (m.id.clone(), start.map(|x| x.to_bits()).collect())
        })
        .collect();
    v.sort();
    v
}

/// What every set is judged on, and the joint fits made so far.
pub(super) struct Ctx<'a> {
    pub(super) model0: &'a Model,
    pub(super) data: &'a Dataset,
    pub(super) floor: Floor<'a>,
    pub(super) s: &'a DiagnoseSettings,
    pub(super) base: Level,
    pub(super) cache: Mutex<HashMap<FitKey, Option<Fitted>>>,
}

impl Ctx<'_> {
    /// The set refitted jointly (once per set and start, [`fit_key`]);
    /// `None` when its fit fails (one set fewer, not an error).
    pub(super) fn fit(&self, members: Vec<Member>) -> Option<Fitted> {
        let key = fit_key(&members);
        if let Some(f) = self.cache.lock().expect("no panic holds it").get(&key) {
            return f.clone();
        }
        let out = joint(
            self.model0,
            &members,
            self.data,
            self.floor,
            self.s.likelihood,
        )
        .ok()
        .map(|j| {
            let members = with_values(&members, self.model0, &j);
            let outside = outside_range(&members, self.data);
            Fitted {
                members,
                joint: j,
                outside,
            }
        });
        self.cache
            .lock()
            .expect("no panic holds it")
            .insert(key, out.clone());
        out
    }

    pub(super) fn base_key(&self) -> f64 {
        self.base
            .deviance()
            .aicc(n_obs(self.data), 0)
            .unwrap_or(f64::INFINITY)
    }

    pub(super) fn floor0(&self) -> Option<f64> {
        (self.floor)(0)
    }
}

/// The sets of `tries` not met before (by their members' ids; none of
/// `seen`), each refitted jointly.
pub(super) fn fit_fresh(
    ctx: &Ctx,
    tries: Vec<Vec<Member>>,
    mut seen: Vec<Vec<String>>,
) -> Vec<Fitted> {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::EffectInstance;

    fn member(id: &str, values: &[f64]) -> Member {
        let effect = crate::effects::by_name("buoyancy").expect("a catalogue effect");
        Member {
            id: id.to_string(),
            insts: vec![EffectInstance {
                effect: effect.into(),
                values: values.to_vec(),
            }],
            located: None,
            name: id.to_string(),
            charge: 0.0,
            place: None,
            pending: None,
        }
    }

    /// One set reached from two starts is two fits: a shared entry would
    /// hand either caller the other's local optimum, whichever finished
    /// first.
    #[test]
    fn a_set_from_another_start_is_another_fit() {
        let a = [member("a", &[1.0]), member("b", &[2.0])];
        let b = [member("a", &[1.0]), member("b", &[2.0 + 1e-12])];
        assert_ne!(fit_key(&a), fit_key(&b));
        assert_eq!(sorted_ids(&a), sorted_ids(&b));
    }

    /// The order members were added in is not part of the fit.
    #[test]
    fn the_order_of_members_is_not_part_of_the_key() {
        let a = [member("a", &[1.0]), member("b", &[2.0])];
        let b = [member("b", &[2.0]), member("a", &[1.0])];
        assert_eq!(fit_key(&a), fit_key(&b));
    }
}
