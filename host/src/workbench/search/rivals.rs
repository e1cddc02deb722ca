//! The sets the data cannot tell apart: a model confidence set around the
//! found set of [`super::search`]. Reaching the noise floor is not placing
//! the truth: on drawn three-effect truths the search reached the floor on
//! eight designs of ten, yet a set with one law at a wrong place tied the
//! true set within the noise on every one. A verdict that names one set
//! there claims a certainty the data do not give.
//!
//! A **rival** of the found set is every other set the search fitted that
//! - has its key (`AICc + sum 2 ln M`) within the margin of the found
//!   set's, either side: the margin calibrated on the data's own design
//!   ([`super::calibrate`]: how far a wrong set beats the set that made
//!   the data, 95 % of the time), never below the AICc margin
//!   (`clear_margin`, 4);
//! - is at the noise floor when the found set is;
//! - lies inside its places' physical ranges and is acceptable as the found
//!   set is (every member pays for itself, [`super::acceptable`]);
//! - has other places (a set that differs only in a law's form or feature
//!   at the same places is the same finding, worded by the parsimony rule).
//!
//! One set per combination of places (the best key) is kept. When the found
//! set stays more than `far_above` ([`super::settings::SearchSettings`]) times above the floor, sets only
//! rank misfits and none is stated as a rival.
//!
//! References: K. P. Burnham & D. R. Anderson, *Model Selection and
//! Multimodel Inference*, 2nd ed. (2002), ch. 2 (models within a few AICc
//! units have substantial support); P. R. Hansen, A. Lunde & J. M. Nason,
//! Econometrica 79 (2011) 453 (the model confidence set).

use super::acceptable;
use super::calibrate::{self, Margin};
use super::fitted::{Ctx, Fitted};
use super::level::Rival;

/// The rivals of `chosen` among `all` (sorted by key), best key first,
/// and the margin they were judged by.
pub(super) fn of(ctx: &Ctx, all: &[Fitted], chosen: &Fitted) -> (Vec<Rival>, Margin) {
    let fixed = Margin {
        value: ctx.s.clear_margin,
        calibrated: None,
    };
    let far = ctx.is_far(chosen);
    if far {
        return (Vec::new(), fixed);
    }
    let could_be = |f: &Fitted| {
        (!chosen.joint.at_floor || f.joint.at_floor) && f.outside.is_none() && acceptable(ctx, f)
    };
    let candidates = calibrate::candidates(all, chosen, could_be);
    let margin = calibrate::margin(ctx, &candidates);
    let out = candidates[1..]
        .iter()
        .filter(|f| (f.joint.key - chosen.joint.key).abs() <= margin.value)
        .map(|f| Rival {
            members: f.members.iter().map(|m| m.describe()).collect(),
            places: f.signature(),
            key_difference: f.joint.key - chosen.joint.key,
            at_floor: f.joint.at_floor,
            model: f.joint.fit.model.clone(),
        })
        .collect();
    (out, margin)
}
