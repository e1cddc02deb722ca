//! What turns the command and the battery status into a duty inside the
//! main-loop pass ([`super::MainLoop`]): a [`MotorControl`]. The chip's is
//! [`ChipControl`], rate control from the Hall edges (`rate::control`,
//! `rate::hall`); a simulation may carry another (the host's voltage mode,
//! `swimbot sim` without `--rate-hz`). The decisions around it (command
//! merge, set-point keys, when to read the cell, the monitor, the latch,
//! the LED, Hall power, dormancy) are the pass's, whichever it carries.

use super::HallEdge;
use crate::battery::BatteryStatus;
use crate::command::Command;
use crate::rate::{HallConfig, RateConfig, RateController, RateEstimator, RateOutput, SensorFault};

/// The motor's controller inside a pass.
pub trait MotorControl {
    /// A Hall edge the interrupt queued (oldest first, before `step`).
    fn hall_edge(&mut self, edge: HallEdge);
    /// One control step: the command (if one arrived) and the battery status
    /// in, the duty, state and event out.
    fn step(&mut self, now_us: u64, command: Option<Command>, battery: BatteryStatus)
        -> RateOutput;
    /// The set-point (mHz); `None` for a controller without one.
    fn set_rate(&self) -> Option<u32>;
    /// Change the set-point (a controller without one ignores it).
    fn set_rate_mhz(&mut self, set: Option<u32>);
    /// The sensor fault that stopped the motor last, if any.
    fn fault(&self) -> Option<SensorFault>;
    /// The turn-averaged rate (mHz), if measured.
    fn rate_mhz(&self) -> Option<u32>;
    /// The rotor carries the Hall ring, so its edges say whether it turns
    /// (the motor supervisor's jam check needs them). A drive without the
    /// sensor (the sim's voltage mode, a test's constant duty) says no.
    fn senses_rotor(&self) -> bool {
        true
    }
}

/// The chip's controller: rate control on the Hall ring's edges.
#[derive(Clone, Debug)]
pub struct ChipControl {
    pub controller: RateController,
    pub estimator: RateEstimator,
}

impl ChipControl {
    pub fn new(rate: RateConfig, hall: HallConfig) -> Self {
        Self {
            controller: RateController::new(rate),
            estimator: RateEstimator::new(hall),
        }
    }
}

impl MotorControl for ChipControl {
    fn hall_edge(&mut self, e: HallEdge) {
        self.estimator.edge(e.t_us, e.a, e.b);
    }

    fn step(
        &mut self,
        now_us: u64,
        command: Option<Command>,
        battery: BatteryStatus,
    ) -> RateOutput {
        self.controller
            .step(now_us, command, battery, &mut self.estimator)
    }

    fn set_rate(&self) -> Option<u32> {
        self.controller.set_rate()
    }

    fn set_rate_mhz(&mut self, set: Option<u32>) {
        self.controller.set_rate_mhz(set);
    }

    fn fault(&self) -> Option<SensorFault> {
        self.controller.fault()
    }

    fn rate_mhz(&self) -> Option<u32> {
        self.estimator.estimate().map(|r| r.rate_mhz)
    }
}
