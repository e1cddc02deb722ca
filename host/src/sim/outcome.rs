//! What one run of `swimbot sim` produced ([`super::dynamics`]): the
//! sampled time series, the energy ledger, how the run ended, and the
//! means over the running time.

use super::hydro::Hydro;
use super::rate::RatePoint;
use swimbot_shared::rate::{RateEvent, SensorFault};
use swimbot_shared::{Command, Event, MotorState as State, StopReason};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    pub t_s: f64,
    pub duty: f64,
    /// Cell terminal voltage, the cycle mean (V).
    pub battery_v: f64,
    /// Cell terminal voltage in the middle of the on-pulse (V): the loaded
    /// voltage (equal to `battery_v` with the motor off or at full duty).
    pub loaded_v: f64,
    /// Mean current out of the cell (A).
    pub current_a: f64,
    /// Mean motor current (A).
    pub motor_current_a: f64,
    /// Motor rate, tail relative to body (Hz).
    pub motor_rate_hz: f64,
    /// Tail rate in the lab frame (Hz): what a camera sees.
    pub tail_rate_hz: f64,
    /// Body rate about x in the lab frame (Hz), signed: negative is
    /// counter-rotating against the tail.
    pub body_rate_hz: f64,
    pub u_mm_s: f64,
    /// Nose above the channel floor (mm).
    pub height_mm: f64,
    pub soc: f64,
    pub state: State,
}

/// Energy ledger over the run (J), see the module docs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Energy {
    pub cell_j: f64,
    pub internal_j: f64,
    pub winding_j: f64,
    pub diode_j: f64,
    pub friction_j: f64,
    pub hydro_j: f64,
    /// Work done on the robot by external loads (buoyancy), an input.
    pub external_j: f64,
    pub stored_j: f64,
}

impl Energy {
    /// Input minus everything accounted for (J).
    pub fn residual_j(&self) -> f64 {
        self.cell_j + self.external_j
            - (self.internal_j
                + self.winding_j
                + self.diode_j
                + self.friction_j
                + self.hydro_j
                + self.stored_j)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum End {
    TopReached,
    /// The controller stopped the motor and it came to rest.
    Stopped(StopReason),
    /// The rate sensor showed a fault and the controller stopped the motor.
    SensorFault(SensorFault),
    /// The script ran out and the robot is at rest (never started, or
    /// started and stopped by a command).
    Idle,
    TimeLimit,
}

#[derive(Debug, Clone)]
pub struct Outcome {
    pub tail_id: String,
    pub hydro: Hydro,
    pub samples: Vec<Sample>,
    /// The state after the last tick (also the last sample).
    pub last: Sample,
    pub events: Vec<(f64, Event)>,
    pub commands: Vec<(f64, Command)>,
    pub end: End,
    pub top_reached_s: Option<f64>,
    pub start_height_mm: f64,
    pub channel_length_mm: f64,
    /// Time in the Running state (after the soft start), and the means
    /// of U (mm/s), tail rate f and body counter-rotation (Hz) over it.
    pub running_s: f64,
    pub mean_u_mm_s: f64,
    pub mean_f_hz: f64,
    pub mean_omega_b_hz: f64,
    pub energy: Energy,
    pub ticks: u64,
    /// Rate control only: the trace every [`super::dynamics::RATE_TRACE_EVERY_US`], and the
    /// sensor faults and refused starts with their times.
    pub rate_trace: Vec<RatePoint>,
    pub rate_faults: Vec<(f64, RateEvent)>,
    /// Every battery reading the pass took: its time (us) and ADC counts.
    pub battery_readings: Vec<(u64, u16)>,
    /// The run log the robot would keep: the firmware's own recorder
    /// (`swimbot_shared::run_log::Recorder`) fed every pass.
    pub log_records: Vec<swimbot_shared::run_log::Record>,
}
