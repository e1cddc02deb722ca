//! A run log as a time series in SI-ish units (s, Hz, V), with the events
//! worded, and what a simulation needs to replay it: the set-points in
//! force and the On/Off commands, in time.

use super::RunLog;
use swimbot_shared::run_log::{Events, Record};

/// One record, converted.
#[derive(Debug, Clone, PartialEq)]
pub struct LogPoint {
    pub t_s: f64,
    /// The selected set-point (Hz), if any.
    pub set_hz: Option<f64>,
    /// The turn-averaged measured rate (Hz), if measured.
    pub rate_hz: Option<f64>,
    /// PWM duty, 0-1.
    pub duty: f64,
    /// The cell's loaded voltage (V), if read.
    pub cell_v: Option<f64>,
    /// What happened in the interval, worded (empty: nothing).
    pub events: Vec<&'static str>,
}

impl LogPoint {
    fn of(r: &Record) -> LogPoint {
        LogPoint {
            t_s: f64::from(r.t_ms) * 1e-3,
            set_hz: r.set_point_mhz.map(|f| f64::from(f) * 1e-3),
            rate_hz: r.rate_mhz.map(|f| f64::from(f) * 1e-3),
            duty: f64::from(r.duty_per_10k) * 1e-4,
            cell_v: (r.cell_mv > 0).then(|| f64::from(r.cell_mv) * 1e-3),
            events: words(r),
        }
    }

    /// The motor is driven in this record.
    pub fn running(&self) -> bool {
        self.duty > 0.0
    }
}

/// Event bits and their words, as the figure and the summary show them.
const EVENT_WORDS: [(Events, &str); 16] = [
    (Events::ON, "On"),
    (Events::OFF, "Off"),
    (Events::STARTED, "started"),
    (Events::RAMP_DONE, "ramp done"),
    (Events::STOPPED_COMMAND, "stopped (Off)"),
    (Events::STOPPED_MAX_RUN_TIME, "stopped (run-time limit)"),
    (Events::STOPPED_LOW_BATTERY, "stopped (low battery)"),
    (Events::STOPPED_BATTERY_FAULT, "stopped (battery fault)"),
    (Events::START_REFUSED, "start refused"),
    (Events::SET_POINT_CHANGED, "set-point key"),
    (Events::NO_SET_POINT, "On without set-point"),
    (Events::LOW_BATTERY, "battery low"),
    (Events::CUTOFF_LATCHED, "cut-off latched"),
    (Events::PAIRED, "remote paired"),
    (Events::EDGES_DROPPED, "edges dropped"),
    (Events::USB_CONNECTED, "USB connected"),
];

fn words(r: &Record) -> Vec<&'static str> {
    let mut out: Vec<&'static str> = EVENT_WORDS
        .iter()
        .filter(|(bit, _)| r.events.contains(*bit))
        .map(|&(_, w)| w)
        .collect();
    if let Some(f) = r.fault {
        out.push(match f {
            swimbot_shared::rate::SensorFault::Stalled => "fault: stalled",
            swimbot_shared::rate::SensorFault::Reversed => "fault: reversed",
            swimbot_shared::rate::SensorFault::Disconnected => "fault: sensor disconnected",
            swimbot_shared::rate::SensorFault::Overspeed => "fault: overspeed",
            swimbot_shared::rate::SensorFault::Jammed => "fault: jammed (supervisor)",
            swimbot_shared::rate::SensorFault::Overheated => "fault: overheated (supervisor)",
        });
    }
    out
}

/// The whole log as points.
#[derive(Debug, Clone, PartialEq)]
pub struct Trace {
    pub points: Vec<LogPoint>,
    /// Records taken but not kept by the robot (its slot was full).
    pub dropped_records: u32,
    pub sample_period_s: f64,
}

impl Trace {
    pub fn of(log: &RunLog) -> Trace {
        Trace {
            points: log.records.iter().map(LogPoint::of).collect(),
            dropped_records: log.header.dropped_records,
            sample_period_s: f64::from(log.header.sample_period_ms) * 1e-3,
        }
    }

    /// The set-points as a schedule `(from_us, Hz)`: each change, at the
    /// record that first shows it.
    pub fn set_points(&self) -> Vec<(u64, f64)> {
        let mut out: Vec<(u64, f64)> = Vec::new();
        for p in &self.points {
            let Some(f) = p.set_hz else { continue };
            if out.last().is_none_or(|&(_, last)| last != f) {
                let at_us = if out.is_empty() {
                    0
                } else {
                    (p.t_s * 1e6).round() as u64
                };
                out.push((at_us, f));
            }
        }
        out
    }

    /// The remote's On and Off commands (time in s, true for On) as the
    /// robot decoded them.
    pub fn commands(&self) -> Vec<(f64, bool)> {
        let mut out = Vec::new();
        for p in &self.points {
            if p.events.contains(&"On") {
                out.push((p.t_s, true));
            }
            if p.events.contains(&"Off") {
                out.push((p.t_s, false));
            }
        }
        out
    }
}
