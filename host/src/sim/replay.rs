//! A run log and a simulation, both ways: the log's set-points and remote
//! commands as a simulation's schedule and script (`swimbot sim
//! --set-points-from LOG`, to predict the logged run with the model's tail
//! load), and a simulated run's records as a log image (`--write-log`),
//! written by the firmware's own recorder and encoder, which `swimbot log`
//! reads like the robot's.

use super::rate::RateRun;
use super::script::{Item, Script, Send};
use crate::runlog::{RunLog, Trace};
use swimbot_shared::run_log::{encode, Header, Record, HEADER_LEN, RECORD_LEN};
use swimbot_shared::KeyMap;

/// The logged run as a simulation's script and set-point schedule. The
/// log holds the times the robot decoded On and Off; the script sends each
/// frame that much earlier, so the simulated robot decodes it at the same
/// time. Other stops (low battery, run-time limit, a fault) are the
/// simulation's own to reach or not.
pub fn replay(trace: &Trace, keys: &KeyMap) -> Result<(Script, RateRun), ReplayError> {
    let commands = trace.commands();
    if !commands.iter().any(|c| c.1) {
        return Err(ReplayError::NoOnCommand);
    }
    let set_points = trace.set_points();
    if set_points.is_empty() {
        return Err(ReplayError::NoSetPoint);
    }
    // The frame's length: from its first edge to its last, after which
    // the pass decodes it.
    let on = Script::on_at_zero();
    let frame_us = on.edges(keys).last().map_or(0, |e| e.1);
    let items = commands
        .iter()
        .map(|&(t_s, is_on)| Item {
            at_us: ((t_s * 1e6).round() as u64).saturating_sub(frame_us),
            send: if is_on { Send::On } else { Send::Off },
        })
        .collect();
    Ok((Script { items }, RateRun::new(set_points)))
}

/// A log with nothing to replay.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ReplayError {
    #[error("the log holds no On command: there is no run to replay")]
    NoOnCommand,
    #[error("the log holds no set-point: the motor never ran rate-controlled")]
    NoSetPoint,
}

/// Simulated records the firmware's log format cannot hold (the shared
/// crate's `EncodeError`, shown as the firmware names it).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0:?}")]
pub struct ImageError(pub swimbot_shared::run_log::image::EncodeError);

/// The header of a simulated log: the board's period, closed, unpaired,
/// nothing dropped, no foreign remote.
fn header(records: &[Record]) -> Header {
    Header {
        sample_period_ms: (swimbot_shared::board::LOG_PERIOD_US / 1_000) as u16,
        record_count: u32::try_from(records.len()).unwrap_or(u32::MAX),
        dropped_records: 0,
        foreign_frames: 0,
        paired_address: None,
        flags: swimbot_shared::run_log::image::FLAG_CLOSED,
    }
}

/// A simulated run as the robot would log it.
pub fn log_trace(records: &[Record]) -> Trace {
    Trace::of(&RunLog {
        header: header(records),
        records: records.to_vec(),
    })
}

/// The log image of simulated records.
pub fn log_image(records: &[Record]) -> Result<Vec<u8>, ImageError> {
    let header = header(records);
    let mut out = vec![0u8; HEADER_LEN + RECORD_LEN * records.len()];
    let n = encode(&header, records, &mut out).map_err(ImageError)?;
    out.truncate(n);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runlog::LogPoint;
    use crate::sim::{default_robot, simulate_with, Options};
    use swimbot_shared::Event;

    fn point(t_s: f64, set: f64, events: Vec<&'static str>) -> LogPoint {
        LogPoint {
            t_s,
            set_hz: Some(set),
            rate_hz: None,
            duty: 0.3,
            cell_v: Some(3.9),
            events,
        }
    }

    #[test]
    fn the_replayed_robot_decodes_the_commands_when_the_logged_one_did() {
        let trace = Trace {
            points: vec![
                point(1.0, 0.8, vec!["On", "started"]),
                point(1.1, 0.8, vec![]),
                point(2.0, 1.2, vec![]),
                point(3.0, 1.2, vec!["Off", "stopped (Off)"]),
            ],
            dropped_records: 0,
            sample_period_s: 0.1,
        };
        let robot = default_robot();
        let (script, run) = replay(&trace, &robot.keys).unwrap();
        assert_eq!(run.set_points, vec![(0, 0.8), (2_000_000, 1.2)]);
        let opts = Options {
            tail: 2,
            max_time_s: 4.0,
            stop_at_top: false,
            ..Options::default()
        };
        let o = simulate_with(&robot, &script, &opts, Some(&run)).unwrap();
        let started = o.events.iter().find(|e| e.1 == Event::Started).unwrap().0;
        let stopped = o
            .events
            .iter()
            .find(|e| matches!(e.1, Event::Stopped(_)))
            .unwrap()
            .0;
        // One 1 ms pass of slack: the frame's last edge, then the pass.
        assert!((started - 1.0).abs() <= 0.0015, "{started}");
        assert!((stopped - 3.0).abs() <= 0.0015, "{stopped}");
    }

    #[test]
    fn a_log_without_a_run_cannot_be_replayed() {
        let trace = Trace {
            points: vec![point(1.0, 0.8, vec![])],
            dropped_records: 0,
            sample_period_s: 0.1,
        };
        let e = replay(&trace, &default_robot().keys)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no On"), "{e}");
    }

    #[test]
    fn the_log_band_is_the_step_responses_band() {
        assert_eq!(
            crate::runlog::STEADY_BAND,
            super::super::step_response::SETTLE_BAND
        );
    }
}
