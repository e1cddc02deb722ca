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

/// What every set is judged on, and the joint fits made so far.
pub(super) struct Ctx<'a> {
    pub(super) model0: &'a Model,
    pub(super) data: &'a Dataset,
    pub(super) floor: Floor<'a>,
    pub(super) s: &'a DiagnoseSettings,
    pub(super) base: Level,
    pub(super) cache: Mutex<HashMap<Vec<String>, Option<Fitted>>>,
}

impl Ctx<'_> {
    /// The set refitted jointly (once per set of ids: a set met again is
    /// the fit made first, which the choice also reads as "wherever the
    /// members were fitted before"); `None` when its fit fails (one set
    /// fewer, not an error). Each parallel batch of fits holds distinct
    /// sets (the singles, the pairs from scratch, [`fit_fresh`]), so what
    /// is cached first does not depend on thread timing.
    pub(super) fn fit(&self, members: Vec<Member>) -> Option<Fitted> {
        let key = sorted_ids(&members);
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

    /// Whether the set stays farther above its noise floor than the
    /// search's `far_above` ([`super::settings::SearchSettings::is_far`]).
    pub(super) fn is_far(&self, f: &Fitted) -> bool {
        self.s
            .search
            .is_far(f.joint.fit.chi2, (self.floor)(f.joint.k))
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
