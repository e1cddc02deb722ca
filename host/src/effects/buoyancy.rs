//! Net buoyancy in a vertical channel. The robot is trimmed to be neutrally
//! buoyant with a cork; any residual mismatch is a constant force along
//! the channel axis, independent of the tail rate, so it breaks the
//! proportionality of U to f that every viscous effect keeps.
//!
//! Reference: Archimedes; the paper, section II.A (neutral buoyancy).

use super::{Effect, ParamSpec};
use crate::data::Case;
use crate::physics::solve::ForceBalance;
use std::borrow::Cow;

pub struct Buoyancy;

const PARAMS: &[ParamSpec] = &[ParamSpec {
    name: Cow::Borrowed("net_force_mn"),
    unit: Cow::Borrowed("mN"),
    default: 0.1,
    min: -20.0,
    max: 20.0,
    free: true,
    doc: Cow::Borrowed(
        "buoyancy minus weight along the swimming direction (up); 0.1 mN is a 10 mg trim error",
    ),
}];

impl Effect for Buoyancy {
    fn name(&self) -> &'static str {
        "buoyancy"
    }
    fn statement(&self) -> &'static str {
        "residual buoyancy minus weight along a vertical channel: a constant axial force, U no longer proportional to f"
    }
    fn reference(&self) -> &'static str {
        "paper section II.A (neutral-buoyancy trim)"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn applies_to(&self, case: &Case, _p: &[f64]) -> bool {
        case.orientation == crate::data::Orientation::Vertical
    }
    fn applicability(&self) -> &'static str {
        "vertical channels"
    }
    fn balance(&self, p: &[f64], _case: &Case, fb: &mut ForceBalance) {
        fb.load[0] += p[0] * 1e-3;
    }
}
