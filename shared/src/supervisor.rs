//! The motor supervisor: a second, independent guard between whatever
//! controller chose the duty and the PWM. It keeps its own state and reads
//! only the duty, the cell voltage and the raw Hall edges, so a controller
//! that misjudges the motor (a wrong line, an integrator wound up against a
//! jammed tail) cannot cook it. Three limits:
//!
//! - **Voltage ceiling.** The mean motor voltage `duty V_cell` never
//!   exceeds the motor's rated voltage: the duty is cut to
//!   `V_rated / V_cell`.
//! - **Jam.** Driven hard (mean voltage at or above `jam.drive_min_mv`)
//!   for `jam.window_us` while the rotor moved fewer than
//!   `jam.min_steps` quadrature steps: a jammed or nearly jammed tail.
//!   The motor stops ([`SensorFault::Jammed`]); a new On retries.
//! - **Heat.** The `I^2 t` estimate of the winding's and the driver's
//!   rise (`thermal`) past its limit stops the motor
//!   ([`SensorFault::Overheated`]); On is refused until the winding has
//!   cooled below the restart rise.
//!
//! The supervisor only ever lowers the duty: it cannot start the motor.

use crate::controller::Duty;
use crate::main_loop::HallEdge;
use crate::rate::SensorFault;

pub mod thermal;
pub use thermal::{Heating, ThermalConfig, ThermalNode};

/// When the supervisor calls a rotor jammed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct JamConfig {
    /// Mean motor voltage that moves any healthy tail clearly (mV).
    pub drive_min_mv: u32,
    /// How long the drive must stay at or above it with too little motion.
    pub window_us: u32,
    /// The fewest quadrature steps a turning rotor makes in the window.
    pub min_steps: u32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SupervisorConfig {
    /// The motor's rated voltage: the mean voltage's ceiling (mV).
    pub max_motor_mv: u32,
    pub jam: JamConfig,
    pub thermal: ThermalConfig,
    /// After this many trips (jams, overheating) since power-up every
    /// start is refused until the next power-up: a tail that keeps
    /// jamming, or a motor that keeps overheating, is not retried for ever
    /// (as the Crazyflie's supervisor locks out after repeated faults).
    pub lockout_trips: u16,
}

/// What the supervisor made of one step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Verdict {
    /// The duty to apply: at most the one asked for.
    pub duty: Duty,
    /// The motor must stop now for this reason (reported once).
    pub trip: Option<SensorFault>,
}

/// Motion is sampled this often into the jam window.
const SAMPLE_US: u64 = 250_000;
/// The heat network advances this often (its fastest time constant, the
/// winding's, is 2.5 s).
const HEAT_STEP_US: u64 = 100_000;
/// Samples kept: the window (at most 4 s) in 250 ms steps, plus one.
const RING: usize = 17;
const _: () = assert!(RING >= 2);

#[derive(Clone, Debug)]
pub struct Supervisor {
    cfg: SupervisorConfig,
    heat: Heating,
    last_us: Option<u64>,
    /// Net quadrature steps and the last (A, B) state.
    position: i32,
    quadrant: Option<u8>,
    /// Positions sampled every `SAMPLE_US` while driven hard.
    ring: [i32; RING],
    samples: usize,
    next_sample_us: u64,
    /// The fault that stopped the motor last (shown until the next start).
    fault: Option<SensorFault>,
    /// Overheated: On is refused until the winding has cooled.
    cooling: bool,
    /// Trips since power-up.
    trips: u16,
    /// The duty applied since the last check, and the cell it drew from.
    applied_q16: u32,
    applied_cell_mv: u32,
    /// `duty V_cell^2 dt` summed since the heat was last advanced, and
    /// the time it spans: the heat advances every `HEAT_STEP_US` on the
    /// mean (one division per step, not several per pass).
    heat_sum: u64,
    heat_sum_us: u64,
    /// The ceiling's duty for the last cell voltage seen.
    ceiling: (u32, Duty),
}

/// Gray-code index of a quadrature state.
fn quadrant(a: bool, b: bool) -> u8 {
    match (a, b) {
        (false, false) => 0,
        (false, true) => 1,
        (true, true) => 2,
        (true, false) => 3,
    }
}

impl Supervisor {
    pub const fn new(cfg: SupervisorConfig) -> Self {
        Self {
            cfg,
            heat: Heating {
                winding_uk: 0,
                housing_uk: 0,
                driver_uk: 0,
            },
            last_us: None,
            position: 0,
            quadrant: None,
            ring: [0; RING],
            samples: 0,
            next_sample_us: 0,
            fault: None,
            cooling: false,
            trips: 0,
            applied_q16: 0,
            applied_cell_mv: 0,
            heat_sum: 0,
            heat_sum_us: 0,
            ceiling: (0, Duty::ZERO),
        }
    }

    pub fn config(&self) -> &SupervisorConfig {
        &self.cfg
    }

    pub fn heating(&self) -> Heating {
        self.heat
    }

    /// The fault that stopped the motor last, until the next start.
    pub fn fault(&self) -> Option<SensorFault> {
        self.fault
    }

    /// A start must wait: the motor overheated and has not cooled yet, or
    /// the trips since power-up reached the lock-out.
    pub fn refuses_start(&self) -> bool {
        self.cooling || self.locked_out()
    }

    /// Trips since power-up.
    pub fn trips(&self) -> u16 {
        self.trips
    }

    /// Every start is refused until the next power-up.
    pub fn locked_out(&self) -> bool {
        self.cfg.lockout_trips > 0 && self.trips >= self.cfg.lockout_trips
    }

    /// The motor started: the last fault is no longer shown.
    pub fn started(&mut self) {
        self.fault = None;
        self.samples = 0;
    }

    /// A raw Hall edge: both levels, as the interrupt read them.
    pub fn hall_edge(&mut self, e: HallEdge) {
        let q = quadrant(e.a, e.b);
        if let Some(prev) = self.quadrant {
            // One step forward or back; two (a skipped state) says nothing.
            match q.wrapping_sub(prev) & 3 {
                1 => self.position = self.position.wrapping_add(1),
                3 => self.position = self.position.wrapping_sub(1),
                _ => {}
            }
        }
        self.quadrant = Some(q);
    }

    /// The duty the controller chose for the interval from `now_us` on,
    /// with the cell at `cell_mv`: the duty to apply and whether to stop.
    /// `senses_rotor`: Hall edges come from this rotor (without them the
    /// jam check is off; the ceiling and the heat hold).
    pub fn check(&mut self, now_us: u64, asked: Duty, cell_mv: u32, senses_rotor: bool) -> Verdict {
        let dt = self.last_us.map_or(0, |t| now_us.saturating_sub(t));
        self.last_us = Some(now_us);
        self.heat_of_interval(dt);
        if self.cooling && self.heat.may_restart(&self.cfg.thermal) {
            self.cooling = false;
        }
        if self.ceiling.0 != cell_mv {
            self.ceiling = (cell_mv, Duty::from_ratio(self.cfg.max_motor_mv, cell_mv));
        }
        let duty = asked.min(self.ceiling.1);
        let trip = if duty == Duty::ZERO {
            self.samples = 0;
            None
        } else if self.heat.overheated(&self.cfg.thermal) {
            self.cooling = true;
            Some(SensorFault::Overheated)
        } else if senses_rotor && self.jammed(now_us, duty, cell_mv) {
            Some(SensorFault::Jammed)
        } else {
            None
        };
        let duty = if trip.is_some() { Duty::ZERO } else { duty };
        if trip.is_some() {
            self.fault = trip;
            self.samples = 0;
            self.trips = self.trips.saturating_add(1);
        }
        self.applied_q16 = duty.raw();
        self.applied_cell_mv = cell_mv;
        Verdict { duty, trip }
    }

    /// The heat of the interval that just ended, at the duty it had.
    fn heat_of_interval(&mut self, dt_us: u64) {
        if dt_us > HEAT_STEP_US {
            // A long gap (DORMANT, a late pass): the sum so far, then the
            // gap at its own duty.
            self.flush_heat();
            self.heat.advance(
                &self.cfg.thermal,
                dt_us,
                self.applied_q16,
                self.applied_cell_mv,
            );
            return;
        }
        let v2 = thermal::duty_v2(self.applied_q16, self.applied_cell_mv);
        self.heat_sum = self.heat_sum.saturating_add(v2 * dt_us);
        self.heat_sum_us += dt_us;
        if self.heat_sum_us >= HEAT_STEP_US {
            self.flush_heat();
        }
    }

    fn flush_heat(&mut self) {
        if let Some(mean) = self.heat_sum.checked_div(self.heat_sum_us) {
            self.heat
                .advance_mean(&self.cfg.thermal, self.heat_sum_us, mean);
        }
        self.heat_sum = 0;
        self.heat_sum_us = 0;
    }

    /// Driven hard for the whole window with too little motion.
    fn jammed(&mut self, now_us: u64, duty: Duty, cell_mv: u32) -> bool {
        let drive_mv = (u64::from(duty.raw()) * u64::from(cell_mv)) >> 16;
        if drive_mv < u64::from(self.cfg.jam.drive_min_mv) {
            self.samples = 0;
            return false;
        }
        if self.samples > 0 && now_us < self.next_sample_us {
            return false;
        }
        self.next_sample_us = now_us.saturating_add(SAMPLE_US);
        self.ring.copy_within(0..RING - 1, 1);
        self.ring[0] = self.position;
        self.samples = (self.samples + 1).min(RING);
        let span = (u64::from(self.cfg.jam.window_us) / SAMPLE_US).clamp(1, RING as u64 - 1);
        let span = span as usize;
        if self.samples <= span {
            return false;
        }
        let moved = self.ring[0].wrapping_sub(self.ring[span]).unsigned_abs();
        moved < self.cfg.jam.min_steps
    }
}

#[cfg(test)]
mod tests;
