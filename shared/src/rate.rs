//! Tail-rate sensing and control: the paper's
//! limitation is that "the actuation frequency f is not a controlled
//! parameter"; with the rate measured on board and held at a set-point it
//! becomes one.
//!
//! - [`hall`]: the rate from timestamped quadrature Hall edges, averaged
//!   over whole turns, with the sensor faults (reversed, one channel lost,
//!   overspeed);
//! - [`control`]: feed-forward from the motor line and the measured cell
//!   voltage plus PI with anti-windup, around the on/off state machine of
//!   [`crate::controller`], with the stall fault.
//!
//! The firmware feeds [`RateEstimator::edge`] from an interrupt-and-queue
//! pair like the IR receiver's and calls [`RateController::step`] every
//! pass; the host simulation (`swimbot sim --rate-hz`) runs the same code
//! against the simulated motor, tail and cell. Sensor choice, numbers and
//! wiring: `docs/rate-sensing.md`.
//!
//! References: the paper (`shared/seed/in-channel-vertical-swimming.md`,
//! Table I motor and tails, Table II observed rates); K. J. Astrom and
//! T. Hagglund, *Advanced PID Control* (ISA, 2006), ch. 3 (anti-windup by
//! conditional integration) and ch. 4 (set-point weighting and ramps).

pub mod control;
pub mod hall;
pub mod line;
#[cfg(test)]
mod props;

pub use control::{MotorLine, RateConfig, RateController, RateEvent, RateOutput};
pub use hall::{HallConfig, RateEstimate, RateEstimator, SensorFault, MAX_EDGES_PER_TURN};
