//! `swimbot sim`: the whole robot in time. A robot description
//! ([`robot`]) and a remote-control script ([`script`]) drive the
//! firmware's own main-loop pass (`swimbot_shared::MainLoop`), the host's
//! motor, PWM and cell models and
//! the swimmer model (eq. 11 with the motor between body and tail,
//! [`hydro`]) through [`dynamics`]; [`output`] writes the time series,
//! plot and summary, and [`calibrate`] fits one motor to all observed tail
//! rates (a check of the paper's constant-torque assumption).

pub mod calibrate;
pub mod drive;
pub mod dynamics;
pub mod figure;
pub mod hydro;
pub mod lab;
pub mod log_overlay;
pub mod motor_profile;
pub mod outcome;
pub mod output;
#[cfg(test)]
mod pass_tests;
pub mod rate;
pub mod rate_figure;
mod raw;
pub mod reach;
pub mod replay;
pub mod robot;
mod robot_file;
mod robot_limits;
pub mod script;
pub mod step_response;

pub use dynamics::{
    simulate, simulate_with, BatteryReading, End, Energy, Options, Outcome, Sample,
};
pub use rate::{RatePoint, RateRun};
pub use robot::{default_robot, Robot, RobotError};
pub use script::Script;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    #[error(transparent)]
    Robot(#[from] RobotError),
    #[error(transparent)]
    Hydro(#[from] hydro::HydroError),
    #[error(transparent)]
    Script(#[from] script::ScriptError),
    #[error("{0}")]
    Input(String),
}
