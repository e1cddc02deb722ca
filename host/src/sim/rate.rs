//! Rate control in `swimbot sim`: the chip's own rate control
//! ([`ChipControl`], `RateController` + `RateEstimator`) inside the chip's
//! main-loop pass, fed Hall edges from the simulated ring on the motor's
//! shaft ([`crate::robot::hall`]) through the pass, and a schedule of
//! set-points in place of the set-point keys. Without `--rate-hz` the
//! pass carries the host's voltage-mode controller instead (`Driver`).
//!
//! The set-point is the motor's rate (tail relative to body): that is what
//! a sensor in the body sees on the coupler. The lab-frame tail rate the
//! paper counts on video is that minus the body's counter-rotation, a
//! fixed fraction per tail in the model (printed by `sim`).

use super::script::parse_time_us;
use crate::data::limits::show;
use crate::robot::hall::{Failure, HallRing, SensorNoise};
use swimbot_shared::rate::{HallConfig, RateConfig, RateEvent, RateOutput, SensorFault};
use swimbot_shared::{BatteryStatus, ChipControl, Command, Controller, HallEdge, MotorControl};

/// A rate-controlled run: when each set-point (Hz) applies, the
/// controller's configuration, the sensor and its imperfections.
#[derive(Debug, Clone, PartialEq)]
pub struct RateRun {
    /// `(from_us, set_hz)`, sorted; before the first, no set-point.
    pub set_points: Vec<(u64, f64)>,
    pub config: RateConfig,
    pub hall: HallConfig,
    pub noise: SensorNoise,
    /// A sensor failure from a time on (s), for the fault scenarios.
    pub failure: Option<(f64, Failure)>,
}

impl RateRun {
    /// The board's controller and sensor with typical noise.
    pub fn new(set_points: Vec<(u64, f64)>) -> Self {
        RateRun {
            set_points,
            config: RateConfig::DEFAULT,
            hall: HallConfig::RING_8_POLE,
            noise: SensorNoise::TYPICAL,
            failure: None,
        }
    }

    /// `0.8` (from the start) or `0.6@0s,0.9@20s,...` (times as in scripts;
    /// a bare number is seconds). Two set-points at one time are refused:
    /// one of them would silently never apply.
    pub fn parse_schedule(text: &str) -> Result<Vec<(u64, f64)>, RateError> {
        let mut out: Vec<(u64, f64, &str)> = Vec::new();
        for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (hz, at) = item.split_once('@').unwrap_or((item, "0"));
            let bad = |problem| RateError::Item {
                item: item.to_string(),
                problem,
            };
            let at_us = parse_time_us(at.trim()).ok_or_else(|| bad(ItemProblem::Time))?;
            let hz: f64 = hz.trim().parse().map_err(|_| bad(ItemProblem::Rate))?;
            if !(hz.is_finite() && hz > 0.0) {
                return Err(bad(ItemProblem::NotPositive));
            }
            out.push((at_us, hz, item));
        }
        if out.is_empty() {
            return Err(RateError::Empty);
        }
        out.sort_by_key(|p| p.0);
        if let Some(w) = out.windows(2).find(|w| w[0].0 == w[1].0) {
            return Err(RateError::SameTime {
                first: w[0].2.to_string(),
                second: w[1].2.to_string(),
                at_s: w[0].0 as f64 * 1e-6,
            });
        }
        Ok(out.into_iter().map(|(t, hz, _)| (t, hz)).collect())
    }

    /// Refuses a set-point at or after the run's end (`max_time_s`): the
    /// controller would never be given it, and the run would not show it.
    pub fn check_reached(&self, max_time_s: f64) -> Result<(), RateError> {
        match self
            .set_points
            .iter()
            .find(|p| p.0 as f64 * 1e-6 >= max_time_s)
        {
            Some(p) => Err(RateError::NotReached {
                hz: p.1,
                at_s: p.0 as f64 * 1e-6,
                max_time_s,
            }),
            None => Ok(()),
        }
    }

    /// The set-point in force at `t_us` (Hz).
    pub fn set_hz_at(&self, t_us: u64) -> Option<f64> {
        self.set_points
            .iter()
            .take_while(|p| p.0 <= t_us)
            .last()
            .map(|p| p.1)
    }

    /// Set-points the controller cannot take (outside its allowed range).
    pub fn check(&self) -> Result<(), RateError> {
        let (lo, hi) = (self.config.min_rate_mhz, self.config.max_rate_mhz);
        match self
            .set_points
            .iter()
            .find(|p| !(f64::from(lo)..=f64::from(hi)).contains(&(p.1 * 1e3)))
        {
            Some(p) => Err(RateError::OutOfRange {
                hz: p.1,
                min_hz: f64::from(lo) / 1e3,
                max_hz: f64::from(hi) / 1e3,
            }),
            None => Ok(()),
        }
    }
}

/// A rate schedule (`--rate-hz`) the board's controller cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RateError {
    /// One comma-separated set-point, as written, and what is wrong with it.
    #[error("rate set-point `{item}`: {problem}")]
    Item { item: String, problem: ItemProblem },
    #[error("--rate-hz is empty: give a rate, e.g. 0.8")]
    Empty,
    /// Two set-points, as written, at one time.
    #[error(
        "--rate-hz: set-points `{first}` and `{second}` are both at {} s (a set-point without @ is at 0 s): \
         give each its own time, e.g. 0.6@0s,0.9@20s",
        show(*.at_s)
    )]
    SameTime {
        first: String,
        second: String,
        at_s: f64,
    },
    /// A set-point at or after the run's end.
    #[error(
        "rate set-point {} Hz at {} s is not before the run's end (--max-time-s {}): \
         it would never be reached; give a longer --max-time-s or an earlier time",
        show(*.hz),
        show(*.at_s),
        show(*.max_time_s)
    )]
    NotReached { hz: f64, at_s: f64, max_time_s: f64 },
    /// A set-point outside the controller's allowed range.
    #[error(
        "rate set-point {} Hz is outside the controller's range {min_hz}..={max_hz} Hz",
        show(*.hz)
    )]
    OutOfRange { hz: f64, min_hz: f64, max_hz: f64 },
}

/// What is wrong with one set-point of a schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ItemProblem {
    #[error(
        "the time must be a non-negative number of seconds \
         (a bare number) or with ms, s or min, e.g. 0.8@20, 0.8@500ms, 0.8@2min"
    )]
    Time,
    #[error("expected a rate in Hz, e.g. 0.8 or 0.8@10s")]
    Rate,
    #[error("the rate must be a positive number of Hz")]
    NotPositive,
}

/// One point of a rate-controlled run's trace.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RatePoint {
    pub t_s: f64,
    /// The set-point in force (0 before the first).
    pub set_hz: f64,
    /// The controller's ramped reference.
    pub reference_hz: f64,
    /// The sensor's turn-averaged rate (NaN before the first).
    pub measured_hz: f64,
    /// The true motor rate.
    pub motor_rate_hz: f64,
    pub duty: f64,
    pub battery_v: f64,
    pub running: bool,
}

/// What drives the motor inside the main-loop pass: the chip's rate
/// control ([`ChipControl`], the firmware's own) fed by the simulated Hall
/// ring, or the host's voltage mode. Either way the pass
/// (`swimbot_shared::MainLoop`) decides the rest: commands, set-point keys,
/// battery readings, cut-off, sensor faults, LED.
#[derive(Debug, Clone)]
pub(super) enum Driver {
    Voltage(Controller),
    Rate(Box<RateDriver>),
}

#[derive(Debug, Clone)]
pub(super) struct RateDriver {
    run: RateRun,
    chip: ChipControl,
    ring: HallRing,
    theta_rad: f64,
}

impl Driver {
    pub(super) fn new(voltage: Controller, rate: Option<&RateRun>) -> Driver {
        match rate {
            None => Driver::Voltage(voltage),
            Some(run) => Driver::Rate(Box::new(RateDriver {
                chip: ChipControl::new(run.config, run.hall),
                ring: match run.failure {
                    Some((at_s, f)) => {
                        HallRing::new(run.hall.edges_per_turn(), &run.noise).with_failure(at_s, f)
                    }
                    None => HallRing::new(run.hall.edges_per_turn(), &run.noise),
                },
                run: run.clone(),
                theta_rad: 0.0,
            })),
        }
    }

    /// The rotor turned by `dtheta_rad` over the tick ending at `t_us`: the
    /// sensor's edges, for the next pass to take as the interrupt's queue.
    pub(super) fn turned(&mut self, dtheta_rad: f64, t_us: u64, dt_s: f64) -> Vec<HallEdge> {
        let Driver::Rate(d) = self else {
            return Vec::new();
        };
        let (t1, th0) = (t_us as f64 * 1e-6, d.theta_rad);
        d.theta_rad += dtheta_rad;
        d.ring
            .advance(th0, d.theta_rad, t1 - dt_s, t1)
            .into_iter()
            .map(|e| HallEdge {
                t_us: e.t_us,
                a: e.a,
                b: e.b,
            })
            .collect()
    }
}

/// In rate mode the run's schedule of set-points stands in for the
/// set-point keys; in voltage mode there is no set-point, no sensor.
impl MotorControl for Driver {
    fn hall_edge(&mut self, edge: HallEdge) {
        if let Driver::Rate(d) = self {
            d.chip.hall_edge(edge);
        }
    }

    fn step(&mut self, t_us: u64, command: Option<Command>, battery: BatteryStatus) -> RateOutput {
        let d = match self {
            Driver::Voltage(c) => {
                let o = c.step(t_us, command, battery);
                return RateOutput {
                    duty: o.duty,
                    state: o.state,
                    event: o.event.map(RateEvent::Motor),
                    reference_mhz: 0,
                    saturated: false,
                };
            }
            Driver::Rate(d) => d,
        };
        let set = d.run.set_hz_at(t_us).map(|f| (f * 1e3).round() as u32);
        d.chip.set_rate_mhz(set);
        d.chip.step(t_us, command, battery)
    }

    fn set_rate(&self) -> Option<u32> {
        match self {
            Driver::Rate(d) => d.chip.set_rate(),
            Driver::Voltage(_) => None,
        }
    }

    fn set_rate_mhz(&mut self, set: Option<u32>) {
        if let Driver::Rate(d) = self {
            d.chip.set_rate_mhz(set);
        }
    }

    fn fault(&self) -> Option<SensorFault> {
        match self {
            Driver::Rate(d) => d.chip.fault(),
            Driver::Voltage(_) => None,
        }
    }

    fn rate_mhz(&self) -> Option<u32> {
        match self {
            Driver::Rate(d) => d.chip.rate_mhz(),
            Driver::Voltage(_) => None,
        }
    }

    fn senses_rotor(&self) -> bool {
        matches!(self, Driver::Rate(_))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn schedules_parse_and_bad_ones_say_why() {
        assert_eq!(RateRun::parse_schedule("0.8"), Ok(vec![(0, 0.8)]));
        assert_eq!(
            RateRun::parse_schedule("0.9@20s, 0.6@0s"),
            Ok(vec![(0, 0.6), (20_000_000, 0.9)])
        );
        for bad in ["", "fast", "-1", "0.8@later", "NaN"] {
            let e = RateRun::parse_schedule(bad).unwrap_err().to_string();
            assert!(e.contains("rate") || e.contains("--rate-hz"), "{bad}: {e}");
        }
        let run = RateRun::new(vec![(0, 0.6), (5_000_000, 0.9)]);
        assert_eq!(run.set_hz_at(4_999_999), Some(0.6));
        assert_eq!(run.set_hz_at(5_000_000), Some(0.9));
        assert!(run.check().is_ok());
        assert!(RateRun::new(vec![(0, 5.0)]).check().is_err());
    }

    #[test]
    fn equal_times_and_set_points_past_the_end_are_refused() {
        for (bad, a, b) in [
            ("0.8,0.9", "0.8", "0.9"),
            ("0.6@20s, 0.9@20000ms", "0.6@20s", "0.9@20000ms"),
        ] {
            let e = RateRun::parse_schedule(bad).unwrap_err().to_string();
            assert!(
                e.contains(&format!("`{a}`")) && e.contains(&format!("`{b}`")),
                "{e}"
            );
        }
        // A bare time is seconds, as the message says.
        assert_eq!(
            RateRun::parse_schedule("0.6@0,0.9@20"),
            Ok(vec![(0, 0.6), (20_000_000, 0.9)])
        );
        let run = RateRun::new(vec![(0, 0.6), (20_000_000, 0.9)]);
        assert!(run.check_reached(20.001).is_ok());
        let e = run.check_reached(20.0).unwrap_err().to_string();
        assert!(
            e.contains("0.9 Hz at 20 s") && e.contains("--max-time-s 20"),
            "{e}"
        );
        let e = RateRun::new(vec![(0, 1e300)])
            .check()
            .unwrap_err()
            .to_string();
        assert!(e.contains("1e300 Hz") && e.len() < 200, "{e}");
    }
}
