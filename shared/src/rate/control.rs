//! The tail-rate controller: the on/off state machine, soft start and
//! interlocks of [`crate::controller::Controller`] (reused, not copied), with
//! the motor voltage chosen to hold a rate set-point instead of a fixed
//! voltage.
//!
//! Feed-forward from the motor line. Near stall (the back-EMF at 1 Hz is
//! 5 mV) the loaded motor's steady rate is linear in its mean PWM voltage,
//! `V = V_0 + s f`: `V_0` is the motor's friction `R tau_c / k` plus the
//! freewheel diode's share of each period (`V_d t_d / T`), both constants
//! of the board; the slope `s = 2 pi (R c / k + k)` grows with the tail's
//! viscous load `c`, and the tail is what the firmware cannot know. So the
//! controller keeps the configured line (`line`: the lightest load of the
//! design range, so that a start approaches from below) times a learned
//! factor `g`, and divides the voltage by the measured cell voltage for the
//! duty, so the cell's sag 4.2 -> 3.3 V does not reach the rate.
//!
//! `g` is identified, then trimmed. The plant is static on the sensor's
//! time scale (the loaded mechanical time constant is ~0.2 ms, a turn
//! ~1 s), so a window of edges at a constant voltage measures the slope:
//! `g <- g f_ref / f`. After every change of the reference this is done on
//! the first clean quarter turn (fast, a few per cent of pole-pattern
//! error) and again on the first clean whole turn (pattern-free). Then PI
//! on the relative error `e = (f_ref - f) / f_ref` of whole-turn rates
//! holds the rate against slow drifts (the cell, the oil's temperature):
//! `V = V_0 + s g f_ref (1 + k_p e)`, and on each forward edge
//! `g <- g (1 + k_i e / E)` (`E` edges a turn: `k_i` is the integral gain
//! per turn). The one-turn average lags half a turn; with `k_p = 0.5` and
//! `k_i = 1` per turn the loop's phase margin is 87 degrees and its gain
//! margin 16 (continuous approximation with the one-turn moving average;
//! `k_p < 1` keeps the proportional loop a contraction whatever the lag).
//! Clean means the window lies wholly after the last change of the
//! reference or of `g`'s identification, so the soft start and a
//! set-point step are never taken as error. Anti-windup: no integration
//! upwards while the duty is at its clamp, and `g` bounded to
//! `gain_min..=gain_max`.
//!
//! The soft start ramps the reference from 0 to the set-point over the
//! inner controller's ramp; set-point changes slew at `slew_mhz_per_s`.
//! `g` is kept across Off/On (same tail, same oil), so the second run
//! starts on the learned line.
//!
//! Fixed-point throughout (no FPU on the Cortex-M0+): rates in mHz,
//! voltages in mV, `g` and the gains in units of 1/65536.

use super::hall::{RateEstimator, SensorFault};
use super::line::{LearnedLine, LinePoint};
use crate::battery::BatteryStatus;
use crate::command::Command;
use crate::controller::{Controller, ControllerConfig, Duty, Event, MotorState};

const ONE: i64 = 1 << 16;
/// How far after the pass's clock a Hall edge's timestamp may be and still
/// count as just seen (`sensor_fault`).
const EDGE_AHEAD_MAX_US: u32 = 100_000;

/// The motor voltage against the steady rate, `V = intercept + slope f`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MotorLine {
    pub intercept_mv: u16,
    pub slope_mv_per_hz: u16,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RateConfig {
    /// On/off, soft-start length, duty clamp and run-time limit.
    pub motor: ControllerConfig,
    /// The nominal line: the first start's voltage (from below: the
    /// lightest load's slope) and the intercept until one is measured.
    pub line: MotorLine,
    /// The highest plausible intercept (mV): what the first identification
    /// assumes while the intercept is unknown, so that it lands below the
    /// set-point (`rate::line`).
    pub intercept_max_mv: u16,
    /// Proportional gain on the relative error, 1/65536 units (< 65536).
    pub kp_q16: u32,
    /// Integral gain per turn, 1/65536 units (<= 65536).
    pub ki_per_turn_q16: u32,
    /// The learned factor's bounds, 1/65536 units.
    pub gain_min_q16: u32,
    pub gain_max_q16: u32,
    /// Allowed set-points (mHz); others are clamped into this range.
    pub min_rate_mhz: u32,
    pub max_rate_mhz: u32,
    /// How fast the reference follows a set-point change once running.
    pub slew_mhz_per_s: u32,
    /// Driven past the soft start with no edge for this long: stalled.
    pub stall_us: u32,
    /// The mean motor voltage never asked beyond this (the motor's rating).
    pub max_motor_mv: u16,
}

impl RateConfig {
    /// The board's motor (7 ohm, 0.8 mN m/A, 12 uN m friction: 105 mV)
    /// and drive (0.3 V Schottky conducting ~9 us of the 40 us period at
    /// 0.4-0.6 A: 70 mV), so `V_0` = 175 mV; the slope of the lightest
    /// load in the design range, 0.7 V/Hz (tails 1 and 2 in the model;
    /// the paper's observed rates give 1.9-5.1 V/Hz), with `g` up to 8x.
    /// Set-points 0.2-2 Hz. A stall is declared after 5 s without an edge:
    /// at the lowest set-point, started 8x below it, an edge takes 2.5 s.
    pub const DEFAULT: Self = Self {
        motor: ControllerConfig {
            max_duty: Duty::FULL,
            ..ControllerConfig::DEFAULT
        },
        line: MotorLine {
            intercept_mv: 175,
            slope_mv_per_hz: 700,
        },
        intercept_max_mv: 300,
        kp_q16: 1 << 15,
        ki_per_turn_q16: 1 << 16,
        gain_min_q16: 1 << 14,
        gain_max_q16: 8 << 16,
        min_rate_mhz: 200,
        max_rate_mhz: 2_000,
        slew_mhz_per_s: 1_000,
        stall_us: 5_000_000,
        max_motor_mv: 3_700,
    };
}

impl Default for RateConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// What happened in one step, for the log and the LED.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RateEvent {
    Motor(Event),
    /// The sensor shows a fault: the motor was stopped.
    Fault(SensorFault),
    /// An On arrived with no set-point selected: nothing started.
    NoSetPoint,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RateOutput {
    pub duty: Duty,
    pub state: MotorState,
    pub event: Option<RateEvent>,
    /// The (ramped, slewed) reference the motor is driven towards (mHz).
    pub reference_mhz: u32,
    /// The duty is at a limit: the set-point is out of reach.
    pub saturated: bool,
}

#[derive(Clone, Debug)]
pub struct RateController {
    motor: Controller,
    cfg: RateConfig,
    set_mhz: Option<u32>,
    ref_mhz: u32,
    line: LearnedLine,
    /// The voltage asked at the last step, and the first identification's
    /// point while a secant is pending.
    held_mv: u32,
    first_point: Option<LinePoint>,
    /// When the reference last changed (timer low word) and when the run began.
    ref_changed_us: u32,
    started_us: u64,
    last_us: u64,
    edges_seen: u32,
    /// The soft start's ramp is in progress (or ended at the last step).
    ramping: bool,
    /// Identification stages done since the reference last changed (0-2,
    /// 0-3 while the intercept is unknown).
    identified: u8,
    /// Stages to do for this reference: 3 while the intercept is unknown.
    stages: u8,
    rel_err_q16: i64,
    saturated_high: bool,
    fault: Option<SensorFault>,
}

impl RateController {
    pub const fn new(cfg: RateConfig) -> Self {
        Self {
            motor: Controller::new(cfg.motor),
            cfg,
            set_mhz: None,
            ref_mhz: 0,
            line: LearnedLine::new(&cfg),
            held_mv: 0,
            first_point: None,
            ref_changed_us: 0,
            started_us: 0,
            last_us: 0,
            edges_seen: 0,
            ramping: false,
            identified: 0,
            stages: 3,
            rel_err_q16: 0,
            saturated_high: false,
            fault: None,
        }
    }

    pub fn config(&self) -> &RateConfig {
        &self.cfg
    }

    /// Select a set-point (clamped to the allowed range), or `None` to
    /// disable: the motor then stops and On starts nothing.
    pub fn set_rate_mhz(&mut self, set: Option<u32>) {
        // `max`/`min`, not `clamp`: a config with min > max must not panic
        // (the firmware would reset), and `clamp`'s panic message alone
        // brought `u32`'s Debug formatting into the image (about 0.4 kB).
        let (lo, hi) = (self.cfg.min_rate_mhz, self.cfg.max_rate_mhz);
        self.set_mhz = set.map(|f| f.min(hi).max(lo));
    }

    pub fn set_rate(&self) -> Option<u32> {
        self.set_mhz
    }

    /// The learned line factor `g` (1/65536 units).
    pub fn gain_q16(&self) -> u32 {
        self.line.gain_q16
    }

    /// The motor line's intercept in use (mV), and whether it was measured.
    pub fn intercept_mv(&self) -> (u32, bool) {
        (self.line.intercept_mv, self.line.intercept_known)
    }

    /// The last sensor fault that stopped the motor (cleared by the next On).
    pub fn fault(&self) -> Option<SensorFault> {
        self.fault
    }

    /// One control step, every main-loop pass after the edge queue has been
    /// drained into `rate`.
    pub fn step(
        &mut self,
        now_us: u64,
        command: Option<Command>,
        battery: BatteryStatus,
        rate: &mut RateEstimator,
    ) -> RateOutput {
        let was_off = self.motor.state() == MotorState::Off;
        let (mut command, mut event) = (command, None);
        if command == Some(Command::On) && self.set_mhz.is_none() {
            command = None;
            event = Some(RateEvent::NoSetPoint);
        }
        if self.set_mhz.is_none() && !was_off {
            command = Some(Command::Off);
        }
        let sensor = if was_off {
            None
        } else {
            self.sensor_fault(now_us, rate)
        };
        if sensor.is_some() {
            command = Some(Command::Off);
        }
        let out = self.motor.step(now_us, command, battery);
        if let Some(f) = sensor {
            self.fault = Some(f);
            event = Some(RateEvent::Fault(f));
        } else if let Some(e) = out.event {
            event = Some(RateEvent::Motor(e));
        }
        if out.event == Some(Event::Started) {
            self.start(now_us, rate);
        }
        let duty = match (out.state, self.set_mhz) {
            (MotorState::Off, _) | (_, None) => {
                self.ref_mhz = 0;
                Duty::ZERO
            }
            (state, Some(set)) => {
                self.follow(now_us, state, set);
                self.update(now_us, rate);
                self.duty(battery)
            }
        };
        // After `follow`, which slews by the time since the last step.
        self.last_us = now_us;
        RateOutput {
            duty,
            state: out.state,
            event,
            reference_mhz: self.ref_mhz,
            saturated: duty != Duty::ZERO && self.saturated_high,
        }
    }

    fn start(&mut self, now_us: u64, rate: &mut RateEstimator) {
        rate.restart();
        self.fault = None;
        self.started_us = now_us;
        self.ref_mhz = 0;
        self.ramping = true;
        self.ref_changed_us = now_us as u32;
        self.edges_seen = rate.forward_edges();
        self.rel_err_q16 = 0;
    }

    fn sensor_fault(&self, now_us: u64, rate: &RateEstimator) -> Option<SensorFault> {
        if let Some(f) = rate.fault() {
            return Some(f);
        }
        if self.motor.state() != MotorState::Running {
            return None;
        }
        // Silence counts from the later of the last edge and the ramp's end.
        let ramp_end = self
            .started_us
            .saturating_add(u64::from(self.cfg.motor.ramp_us));
        let since_ramp = now_us.saturating_sub(ramp_end);
        // An edge stamped after `now_us` (its interrupt came between the
        // pass's timer read and the queue's drain, or in a flash stall) is
        // fresh, where the wrapped difference would call it 71 minutes old:
        // a stall. Up to 100 ms ahead counts as fresh; an edge really 71.6
        // minutes old reads as fresh for those 100 ms only.
        let since_edge = rate.last_edge_us().map_or(u64::MAX, |t| {
            let ahead_us = t.wrapping_sub(now_us as u32);
            if ahead_us <= EDGE_AHEAD_MAX_US {
                0
            } else {
                u64::from((now_us as u32).wrapping_sub(t))
            }
        });
        let quiet_from = since_ramp.min(since_edge);
        (quiet_from > u64::from(self.cfg.stall_us)).then_some(SensorFault::Stalled)
    }

    /// The soft start and the slew towards the set-point.
    fn follow(&mut self, now_us: u64, state: MotorState, set: u32) {
        let before = self.ref_mhz;
        // The step that ends the ramp still takes its end value, the set-point.
        let ramping = self.ramping;
        self.ramping = state == MotorState::Ramping;
        self.ref_mhz = if ramping || self.ramping {
            let ramp = u64::from(self.cfg.motor.ramp_us).max(1);
            let t = now_us.saturating_sub(self.started_us).min(ramp);
            u32::try_from(u64::from(set) * t / ramp).unwrap_or(set)
        } else {
            let dt = now_us.saturating_sub(self.last_us).min(1_000_000);
            let max_step = u64::from(self.cfg.slew_mhz_per_s) * dt / 1_000_000;
            let max_step = u32::try_from(max_step.max(1)).unwrap_or(u32::MAX);
            if set > before {
                before.saturating_add(max_step).min(set)
            } else {
                before.saturating_sub(max_step).max(set)
            }
        };
        if self.ref_mhz != before || state == MotorState::Ramping {
            self.ref_changed_us = now_us as u32;
            self.identified = 0;
            self.stages = if self.line.intercept_known { 2 } else { 3 };
        }
    }

    /// Line identification, then PI, on every new rate whose window lies
    /// wholly after the last change of the reference or of the line.
    fn update(&mut self, now_us: u64, rate: &RateEstimator) {
        let seen = rate.forward_edges();
        let new_edges = seen.wrapping_sub(self.edges_seen);
        self.edges_seen = seen;
        let Some(r) = rate.estimate() else { return };
        let clean = (r.since_us.wrapping_sub(self.ref_changed_us) as i32) >= 0;
        if !clean {
            self.rel_err_q16 = 0;
        }
        if new_edges == 0 || !clean || self.ref_mhz == 0 || r.rate_mhz == 0 {
            return;
        }
        let edges = rate.config().edges_per_turn();
        let quarter = usize::from(r.intervals) * 4 >= edges;
        // While the intercept is unknown: a quarter turn on the pessimistic
        // line, a quarter turn for the secant, then a whole turn.
        let stages = self.stages;
        let due = match (self.identified, stages) {
            (0, _) | (1, 3) => quarter,
            (1, 2) | (2, 3) => r.whole_turn,
            _ => false,
        };
        if due {
            self.identify(now_us, r.rate_mhz, stages);
            return;
        }
        if self.identified < stages || !r.whole_turn {
            return;
        }
        let reference = i64::from(self.ref_mhz);
        let e = ((reference - i64::from(r.rate_mhz)) * ONE / reference).clamp(-ONE, ONE);
        self.rel_err_q16 = e;
        // Anti-windup: the duty cannot rise further.
        if e > 0 && self.saturated_high {
            return;
        }
        let steps = i64::from(new_edges.min(32));
        self.line.integrate(&self.cfg, e, steps, edges as i64);
    }

    /// One identification stage on a clean window at the held voltage: the
    /// plant is static, so the window is a point of the motor line.
    fn identify(&mut self, now_us: u64, rate_mhz: u32, stages: u8) {
        let at = LinePoint {
            mv: self.held_mv,
            rate_mhz,
        };
        match (self.identified, self.first_point.take()) {
            (0, _) if stages == 3 => {
                self.line.one_point(&self.cfg, at, self.ref_mhz);
                self.first_point = Some(at);
            }
            (1, Some(a)) => {
                if !self.line.secant(&self.cfg, a, at) {
                    self.line.one_point(&self.cfg, at, self.ref_mhz);
                }
            }
            _ => self.line.one_point(&self.cfg, at, self.ref_mhz),
        }
        self.identified += 1;
        self.ref_changed_us = now_us as u32;
        self.rel_err_q16 = 0;
    }

    /// Motor voltage from the line, the learned factor and the P term, as a
    /// duty of the measured cell voltage.
    fn duty(&mut self, battery: BatteryStatus) -> Duty {
        let p = ONE + i64::from(self.cfg.kp_q16) * self.rel_err_q16 / ONE;
        let asked = self.line.voltage_mv(&self.cfg, self.ref_mhz, p);
        let mv = asked.min(u32::from(self.cfg.max_motor_mv));
        self.held_mv = mv;
        let raw = Duty::from_ratio(mv, u32::from(battery.mv));
        let duty = raw.min(self.cfg.motor.max_duty);
        self.saturated_high = (raw >= self.cfg.motor.max_duty || asked > mv) && mv > 0;
        duty
    }
}
