//! Which set-points the robot can hold: the motor's steady rate at full
//! drive against the tail's load is an upper bound the rate controller
//! cannot pass, whatever the set-point range allows. The robot (motor,
//! cell, the model's load) knows it; the plan asks through [`Reach`], so
//! that the planner does not depend on the whole-robot simulation.

use crate::data::Case;
use crate::model::Model;

/// The fraction of the motor's full-drive rate a set-point may use: the
/// controller needs headroom for the cell's sag over a run.
pub const HEADROOM: f64 = 0.9;

/// The robot's largest steady motor rate (tail relative to body, Hz) in a
/// run `case` under `model`'s load; `None` when it cannot be computed.
pub trait Reach: Sync {
    fn max_rate_hz(&self, model: &Model, case: &Case) -> Option<f64>;
}

/// No limit known: every set-point in the controller's range is taken.
pub struct Unlimited;

impl Reach for Unlimited {
    fn max_rate_hz(&self, _: &Model, _: &Case) -> Option<f64> {
        Some(f64::INFINITY)
    }
}
