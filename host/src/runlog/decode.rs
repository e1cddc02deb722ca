//! What the bytes of a run log say, checked: the firmware's own
//! [`decode`] (the host reads exactly the bytes the firmware writes, with
//! the same checks), then a time that runs one way without a jump, and
//! what is wrong in the words a lab needs ([`LogContentError`]).

use swimbot_shared::run_log::image::{OLDEST_VERSION, VERSION};
use swimbot_shared::run_log::{decode, DecodeError, Header, Record, HEADER_LEN};

/// A decoded log: its header and records, in time order as recorded.
#[derive(Debug, Clone, PartialEq)]
pub struct RunLog {
    pub header: Header,
    pub records: Vec<Record>,
}

/// Why the bytes are no run log of one run; the source is named by the
/// reader ([`super::read::LogError`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LogContentError {
    /// The firmware's decoder refused the image.
    #[error("{}", describe(.0))]
    Image(DecodeError),
    #[error("the log is empty: no record (was the motor started since power-up?)")]
    Empty,
    /// Record `later` (1-based) is earlier than record `earlier`.
    #[error(
        "record {later} (t = {later_s:.3} s) is earlier than record {earlier} (t = {earlier_s:.3} s): time runs backwards, so this is not one run as the robot records it (two logs joined?)"
    )]
    TimeRunsBackwards {
        earlier: usize,
        later: usize,
        earlier_s: f64,
        later_s: f64,
    },
    /// Record `later` comes longer after record `earlier` than the robot
    /// ever waits while the motor runs.
    #[error(
        "record {later} (t = {later_s:.3} s) comes {gap_s:.3} s after record {earlier}: the robot records every {period_ms} ms while the motor runs, so a gap over {max_gap_s:.0} s is no real log (a damaged clock?)"
    )]
    TimeJumps {
        earlier: usize,
        later: usize,
        later_s: f64,
        gap_s: f64,
        period_ms: u32,
        max_gap_s: f64,
    },
}

/// Decode an image; what is wrong is a [`LogContentError`].
pub fn decode_bytes(bytes: &[u8]) -> Result<RunLog, LogContentError> {
    let image = decode(bytes).map_err(LogContentError::Image)?;
    if image.is_empty() {
        return Err(LogContentError::Empty);
    }
    let records: Vec<Record> = image.records().collect();
    check_time(&records, u32::from(image.header.sample_period_ms))?;
    Ok(RunLog {
        header: image.header,
        records,
    })
}

/// The longest plausible gap between two records while the motor runs,
/// in sample periods and at least in ms: the recorder takes a record one
/// period after the last (a main-loop pass, every 1 ms or sooner, is at
/// most one pass late), so even a main loop held up by a flash erase
/// stays far inside it. Between runs of one power-up (the motor stopped,
/// then started again) any gap is real.
const MAX_GAP_PERIODS: u64 = 100;
const MAX_GAP_MS: u64 = 60_000;

/// The motor runs from record `a` to record `b`: `a` is no stop and `b`
/// no start.
fn runs_across(a: &Record, b: &Record) -> bool {
    use swimbot_shared::run_log::Events;
    let stopped = [
        Events::STOPPED_COMMAND,
        Events::STOPPED_MAX_RUN_TIME,
        Events::STOPPED_LOW_BATTERY,
        Events::STOPPED_BATTERY_FAULT,
        Events::USB_CONNECTED,
    ]
    .iter()
    .any(|&e| a.events.contains(e));
    let started = [Events::STARTED, Events::ON]
        .iter()
        .any(|&e| b.events.contains(e));
    a.duty_per_10k > 0 && !stopped && !started
}

/// A CRC-valid image can still hold a time that runs backwards (two logs
/// concatenated) or jumps by days (a corrupted clock): steady windows
/// would count turns twice or span the jump. Refused, naming the record.
fn check_time(records: &[Record], period_ms: u32) -> Result<(), LogContentError> {
    let max_gap = (u64::from(period_ms) * MAX_GAP_PERIODS).max(MAX_GAP_MS);
    for (i, w) in records.windows(2).enumerate() {
        let (a, b) = (u64::from(w[0].t_ms), u64::from(w[1].t_ms));
        let (earlier, later) = (i + 1, i + 2);
        if b < a {
            return Err(LogContentError::TimeRunsBackwards {
                earlier,
                later,
                earlier_s: a as f64 * 1e-3,
                later_s: b as f64 * 1e-3,
            });
        }
        if b - a > max_gap && runs_across(&w[0], &w[1]) {
            return Err(LogContentError::TimeJumps {
                earlier,
                later,
                later_s: b as f64 * 1e-3,
                gap_s: (b - a) as f64 * 1e-3,
                period_ms,
                max_gap_s: max_gap as f64 * 1e-3,
            });
        }
    }
    Ok(())
}

/// A decode error in the words a lab needs.
pub fn describe(e: &DecodeError) -> String {
    match *e {
        DecodeError::TooShort { len } => {
            format!("{len} bytes: too short for a run log (its header alone is {HEADER_LEN} bytes)")
        }
        DecodeError::BadMagic(m) => {
            format!("not a swimbot run log: it starts with {m:02x?}, a log with \"SWLG\"")
        }
        DecodeError::UnsupportedVersion(v) => format!(
            "log format version {v}: this swimbot reads versions {OLDEST_VERSION}-{VERSION}"
        ),
        DecodeError::BadLengths {
            header_len,
            record_len,
        } => format!(
            "header and record lengths {header_len} and {record_len}: the log format has 32 and 16"
        ),
        DecodeError::ZeroPeriod => "the header's sample period is 0 ms".into(),
        DecodeError::BadAddress(a) => format!("the header's paired address {a:#06x} is not 0-255"),
        DecodeError::Truncated { expected, got } => {
            format!("truncated: the header announces {expected} bytes, the log has {got}")
        }
        DecodeError::TrailingBytes { expected, got } => format!(
            "{got} bytes where the header announces {expected}: bytes after the last record"
        ),
        DecodeError::Crc { stored, computed } => format!(
            "bad CRC (stored {stored:#010x}, computed {computed:#010x}): the log is damaged"
        ),
        DecodeError::Record { index, error } => {
            format!("record {index} is malformed: {error:?}")
        }
    }
}
