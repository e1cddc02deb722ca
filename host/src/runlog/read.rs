//! Reading a run log: from a saved image file, or from the robot's USB CDC
//! port (`LOG` request, `swimbot_shared::run_log::readout`), then decoded
//! by the firmware's own [`decode`]: the host reads exactly the bytes the
//! firmware writes, with the same checks.
//!
//! The port is opened through the `serialport` crate (default features
//! off: no libudev, which only enumerates ports) rather than raw file I/O
//! on the tty: a tty opened as a file is in canonical mode with echo on,
//! so the binary log would be echoed back to the robot as requests and
//! line-edited on the way in; `serialport` puts it in raw mode, and works
//! the same on a lab's Windows (`COM3`) or macOS (`/dev/cu.usbmodem*`) host.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::time::Duration;
use swimbot_shared::run_log::image::{OLDEST_VERSION, VERSION};
use swimbot_shared::run_log::{decode, DecodeError, Header, Record, HEADER_LEN};

/// A decoded log: its header and records, in time order as recorded.
#[derive(Debug, Clone, PartialEq)]
pub struct RunLog {
    pub header: Header,
    pub records: Vec<Record>,
}

/// Where the log comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    File(PathBuf),
    Port(String),
}

impl Source {
    /// A serial device (`/dev/tty*`, `/dev/cu.*`, `COMn`, or any character
    /// device) is a port; anything else a saved file.
    pub fn of(arg: &str) -> Source {
        let com = arg
            .strip_prefix("COM")
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()));
        if com || arg.starts_with("/dev/tty") || arg.starts_with("/dev/cu.") || is_char_device(arg)
        {
            Source::Port(arg.to_string())
        } else {
            Source::File(PathBuf::from(arg))
        }
    }

    pub fn name(&self) -> String {
        match self {
            Source::File(p) => p.display().to_string(),
            Source::Port(p) => p.clone(),
        }
    }
}

#[cfg(unix)]
fn is_char_device(path: &str) -> bool {
    use std::os::unix::fs::FileTypeExt;
    std::fs::metadata(path).is_ok_and(|m| m.file_type().is_char_device())
}

#[cfg(not(unix))]
fn is_char_device(_: &str) -> bool {
    false
}

/// Why no log was read: the source and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{source_name}: {message}")]
pub struct LogError {
    pub source_name: String,
    pub message: String,
}

fn err(source: &Source, message: impl Into<String>) -> LogError {
    LogError {
        source_name: source.name(),
        message: message.into(),
    }
}

/// Read and decode a log; also its raw bytes (to be saved when read from
/// the port: the robot keeps only the last run).
pub fn read_source(source: &Source) -> Result<(RunLog, Vec<u8>), LogError> {
    let bytes = read_bytes(source)?;
    let log = decode_bytes(&bytes).map_err(|m| err(source, m))?;
    Ok((log, bytes))
}

/// A log that is the run of the power-up that read it out, as
/// [`read_source`], with the warnings to print; refused (naming the
/// source) if that power-up's run was dropped, unless `earlier`
/// ([`super::power_up::check`]).
pub fn read_current(
    source: &Source,
    earlier: bool,
) -> Result<(RunLog, Vec<u8>, Vec<String>), LogError> {
    let bytes = read_bytes(source)?;
    let image = decode(&bytes).map_err(|e| err(source, describe(&e)))?;
    let warnings = super::power_up::check(&image, earlier).map_err(|m| err(source, m))?;
    let log = decode_bytes(&bytes).map_err(|m| err(source, m))?;
    Ok((log, bytes, warnings))
}

fn read_bytes(source: &Source) -> Result<Vec<u8>, LogError> {
    match source {
        Source::File(p) => read_file(p).map_err(|m| err(source, m)),
        Source::Port(p) => read_port(p).map_err(|m| err(source, m)),
    }
}

/// The largest image the robot can hold (a 10-minute run at 10 Hz is
/// 96 kB) with a wide margin; a bigger file is not a log.
const MAX_IMAGE_BYTES: u64 = 16 << 20;

fn read_file(path: &Path) -> Result<Vec<u8>, String> {
    let len = std::fs::metadata(path)
        .map_err(|e| format!("cannot read the log file: {e}"))?
        .len();
    if len > MAX_IMAGE_BYTES {
        return Err(format!(
            "{len} bytes: not a run log (a 10-minute log is about 96 kB)"
        ));
    }
    let bytes = std::fs::read(path).map_err(|e| format!("cannot read the log file: {e}"))?;
    crate::provenance::record_input(path, &bytes);
    Ok(bytes)
}

/// Ask the robot for its log: `LOG\n`, then the header, then the records
/// the header announces.
fn read_port(name: &str) -> Result<Vec<u8>, String> {
    let mut port = serialport::new(name, 115_200)
        .timeout(Duration::from_secs(3))
        .open()
        .map_err(|e| format!("cannot open the robot's port: {e}"))?;
    let _ = port.clear(serialport::ClearBuffer::All);
    port.write_all(b"LOG\n")
        .and_then(|()| port.flush())
        .map_err(|e| format!("cannot send the LOG request: {e}"))?;
    let mut bytes = vec![0u8; HEADER_LEN];
    port.read_exact(&mut bytes)
        .map_err(|e| format!("no log header from the robot: {e}"))?;
    let count = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]) as u64;
    let total = HEADER_LEN as u64 + count.saturating_mul(16);
    if &bytes[..4] != b"SWLG" || total > MAX_IMAGE_BYTES {
        // Decoding says what is wrong (magic, version, lengths).
        return Ok(bytes);
    }
    let mut rest = vec![0u8; (total as usize) - HEADER_LEN];
    port.read_exact(&mut rest)
        .map_err(|e| format!("the robot sent the header of {count} records, then stopped: {e}"))?;
    bytes.extend_from_slice(&rest);
    Ok(bytes)
}

/// Decode an image, with what is wrong said in words.
pub fn decode_bytes(bytes: &[u8]) -> Result<RunLog, String> {
    let image = decode(bytes).map_err(|e| describe(&e))?;
    if image.is_empty() {
        return Err("the log is empty: no record (was the motor started since power-up?)".into());
    }
    Ok(RunLog {
        header: image.header,
        records: image.records().collect(),
    })
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ports_and_files_are_told_apart_by_name() {
        for port in ["/dev/ttyACM0", "COM3", "/dev/cu.usbmodem1101", "/dev/null"] {
            assert!(matches!(Source::of(port), Source::Port(_)), "{port}");
        }
        for file in ["run.swlog", "COM", "COMX", "logs/COM3.bin"] {
            assert!(matches!(Source::of(file), Source::File(_)), "{file}");
        }
    }

    #[test]
    fn an_absent_port_is_an_error_naming_it() {
        let e = read_source(&Source::Port("/dev/ttyACM-none".into())).unwrap_err();
        assert_eq!(e.source_name, "/dev/ttyACM-none");
        assert!(e.message.contains("cannot open"), "{e}");
    }
}

/// The port's path end to end against a pseudo-terminal standing in for
/// the robot's CDC port: the request goes out, the image comes back whole.
#[cfg(all(test, unix))]
mod port_tests {
    use super::*;
    use serialport::SerialPort;

    #[test]
    fn the_log_request_is_answered_through_a_pseudo_terminal() {
        let (mut robot, host) = serialport::TTYPort::pair().expect("a pseudo-terminal");
        let name = host.name().expect("the host side's name");
        // Held open without the port's lock (a pty whose last slave closes
        // hangs up), so that `read_source` opens it by name as a user would.
        let keep = std::fs::File::open(&name).unwrap();
        drop(host);
        let image = crate::sim::replay::log_image(&[swimbot_shared::run_log::Record {
            t_ms: 1_000,
            set_point_mhz: Some(800),
            rate_mhz: Some(799),
            duty_per_10k: 3_000,
            cell_mv: 3_900,
            events: swimbot_shared::run_log::Events::ON,
            fault: None,
            foreign_frames: 0,
        }])
        .unwrap();
        let answer = image.clone();
        let (done, host_done) = std::sync::mpsc::channel::<()>();
        let served = std::thread::spawn(move || {
            robot.set_timeout(Duration::from_secs(5)).unwrap();
            let mut req = [0u8; 4];
            robot.read_exact(&mut req).unwrap();
            robot.write_all(&answer).unwrap();
            robot.flush().unwrap();
            // Held until the host has read: a closed pty hangs up first.
            let _ = host_done.recv_timeout(Duration::from_secs(30));
            req
        });
        let got = read_source(&Source::Port(name));
        done.send(()).unwrap();
        assert_eq!(&served.join().unwrap(), b"LOG\n");
        let (log, bytes) = got.expect("the log");
        assert_eq!(bytes, image);
        assert_eq!(log.records.len(), 1);
        assert_eq!(log.records[0].rate_mhz, Some(799));
        drop(keep);
    }
}
