//! The recorder: turns each main-loop pass's output into run-log records.
//! A record is taken on the pass that starts the motor, then on the first
//! pass at least one sample period after the previous record while the
//! motor may run (passes come every 1 ms or sooner, so a record is at most
//! one pass late and never a burst), and once more on the pass that finds
//! the motor stopped, so the stop's reason is in the log. Events between
//! records, also those while the motor is off (a set-point key, a foreign
//! remote), go into the next record.

use super::record::{duty_per_10k, mhz_u16, Events, Record};
use crate::battery::BatteryLevel;
use crate::command::Command;
use crate::controller::{Event, MotorState, StopReason};
use crate::main_loop::PassOutput;
use crate::rate::SensorFault;

/// Records from the main loop's passes.
#[derive(Clone, Debug)]
pub struct Recorder {
    period_us: u64,
    next_due_us: Option<u64>,
    pending: Events,
    fault: Option<SensorFault>,
    /// The pass's cumulative foreign-frame count at the last record.
    foreign_at_last: u32,
    foreign_now: u32,
}

impl Recorder {
    /// A record every `period_us` while the motor may run
    /// (`board::LOG_PERIOD_US` on the robot).
    pub const fn new(period_us: u32) -> Self {
        Self {
            period_us: period_us as u64,
            next_due_us: None,
            pending: Events::NONE,
            fault: None,
            foreign_at_last: 0,
            foreign_now: 0,
        }
    }

    /// An event the pass does not see (pairing, a queue overflow, USB):
    /// it goes into the next record.
    pub fn note(&mut self, events: Events) {
        self.pending.insert(events);
    }

    /// Whether records are being taken (the motor may run).
    pub fn recording(&self) -> bool {
        self.next_due_us.is_some()
    }

    /// Feed one pass taken at `now_us`; the record it completes, if any.
    pub fn observe(&mut self, now_us: u64, out: &PassOutput) -> Option<Record> {
        self.collect(out);
        let running = out.state != MotorState::Off;
        let due = match self.next_due_us {
            None => running,
            Some(_) if !running => true,
            Some(t) => now_us >= t,
        };
        if !due {
            return None;
        }
        self.next_due_us = running.then(|| now_us.saturating_add(self.period_us));
        Some(self.take(now_us, out))
    }

    fn collect(&mut self, out: &PassOutput) {
        let e = &mut self.pending;
        match out.command {
            Some(Command::On) => e.insert(Events::ON),
            Some(Command::Off) => e.insert(Events::OFF),
            None => {}
        }
        e.insert(match out.event {
            Some(Event::Started) => Events::STARTED,
            Some(Event::RampDone) => Events::RAMP_DONE,
            Some(Event::Stopped(StopReason::Command)) => Events::STOPPED_COMMAND,
            Some(Event::Stopped(StopReason::MaxRunTime)) => Events::STOPPED_MAX_RUN_TIME,
            Some(Event::Stopped(StopReason::LowBattery)) => Events::STOPPED_LOW_BATTERY,
            Some(Event::Stopped(StopReason::BatteryFault)) => Events::STOPPED_BATTERY_FAULT,
            Some(Event::StartRefused(_)) => Events::START_REFUSED,
            None => Events::NONE,
        });
        if out.set_point_changed.is_some() {
            e.insert(Events::SET_POINT_CHANGED);
        }
        if out.refused_no_set_point {
            e.insert(Events::NO_SET_POINT);
        }
        if out.sample.is_some() && out.battery.level == BatteryLevel::Low {
            e.insert(Events::LOW_BATTERY);
        }
        if out.latch_changed == Some(true) {
            e.insert(Events::CUTOFF_LATCHED);
        }
        if out.fault.is_some() {
            self.fault = out.fault;
        }
        self.foreign_now = out.foreign_frames;
    }

    fn take(&mut self, now_us: u64, out: &PassOutput) -> Record {
        let foreign = self.foreign_now.wrapping_sub(self.foreign_at_last);
        self.foreign_at_last = self.foreign_now;
        let record = Record {
            // Wraps after 49.7 days of power-up: far beyond any run.
            t_ms: (now_us / 1_000) as u32,
            set_point_mhz: out.set_point_mhz.map(mhz_u16),
            rate_mhz: out.rate_mhz.map(mhz_u16),
            duty_per_10k: duty_per_10k(out.duty.raw()),
            cell_mv: out.battery.mv,
            events: self.pending,
            fault: self.fault.take(),
            foreign_frames: u8::try_from(foreign).unwrap_or(u8::MAX),
        };
        self.pending = Events::NONE;
        record
    }
}
