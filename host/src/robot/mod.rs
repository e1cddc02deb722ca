//! Models of the robot's hardware on the host: the coreless DC motor, the
//! Li-Po cell and the PWM drive, used by the controller tests and by `swimbot sim`.
//!
//! Plain `f64` SI quantities and small `Copy` structs; each model exposes
//! its derivatives or its algebraic output so a caller can couple them in
//! one integrator (see `tests/tests/controller_motor.rs`).

pub mod battery;
pub mod hall;
pub mod motor;
pub mod pwm;

pub use battery::{LiPo, LiPoParams};
pub use motor::{Motor, MotorParams, MotorRates, MotorState};
pub use pwm::PwmDrive;
