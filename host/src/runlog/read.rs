//! Reading a run log: from a saved image file, or from the robot's USB CDC
//! port (`LOG` request, `swimbot_shared::run_log::readout`), then decoded
//! ([`super::decode`]).
//!
//! The port is opened through the `serialport` crate (default features
//! off: no libudev, which only enumerates ports) rather than raw file I/O
//! on the tty: a tty opened as a file is in canonical mode with echo on,
//! so the binary log would be echoed back to the robot as requests and
//! line-edited on the way in; `serialport` puts it in raw mode, and works
//! the same on a lab's Windows (`COM3`) or macOS (`/dev/cu.usbmodem*`) host.

use super::decode::{decode_bytes, describe, RunLog};
use crate::provenance::Inputs;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use swimbot_shared::run_log::{decode, HEADER_LEN};

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
pub fn read_source(source: &Source, inputs: &Inputs) -> Result<(RunLog, Vec<u8>), LogError> {
    let bytes = read_bytes(source, inputs)?;
    let log = decode_bytes(&bytes).map_err(|e| err(source, e.to_string()))?;
    Ok((log, bytes))
}

/// A log that is the run of the power-up that read it out, as
/// [`read_source`], with the warnings to print; refused (naming the
/// source) if that power-up's run was dropped, unless `earlier`
/// ([`super::power_up::check`]).
pub fn read_current(
    source: &Source,
    earlier: bool,
    inputs: &Inputs,
) -> Result<(RunLog, Vec<u8>, Vec<String>), LogError> {
    let bytes = read_bytes(source, inputs)?;
    let image = decode(&bytes).map_err(|e| err(source, describe(&e)))?;
    let warnings = super::power_up::check(&image, earlier).map_err(|m| err(source, m))?;
    let log = decode_bytes(&bytes).map_err(|e| err(source, e.to_string()))?;
    Ok((log, bytes, warnings))
}

/// A file's bytes are recorded in `inputs`; a port's are the robot's
/// flash, no file of the user's.
fn read_bytes(source: &Source, inputs: &Inputs) -> Result<Vec<u8>, LogError> {
    match source {
        Source::File(p) => read_file(p, inputs).map_err(|e| err(source, e.to_string())),
        Source::Port(p) => read_port(p).map_err(|e| err(source, e.to_string())),
    }
}

/// The largest image the robot can hold (a 10-minute run at 10 Hz is
/// 96 kB) with a wide margin; a bigger file is not a log.
const MAX_IMAGE_BYTES: u64 = crate::input_file::cap::RUN_LOG;

/// Bounded while reading ([`crate::input_file`]): a FIFO or `/dev/zero`
/// costs at most the cap, never the machine.
fn read_file(path: &Path, inputs: &Inputs) -> Result<Vec<u8>, crate::input_file::ReadError> {
    let bytes = crate::input_file::read(
        path,
        MAX_IMAGE_BYTES,
        "a run log (a 10-minute log is about 96 kB)",
    )?;
    inputs.record(path, &bytes);
    Ok(bytes)
}

/// Silence on the port longer than this ends the read: the robot answers
/// at once, and a USB packet is never this late.
const PORT_SILENCE: Duration = Duration::from_secs(3);
/// The whole read's deadline is this plus the image's size at
/// [`PORT_MIN_BYTES_PER_S`]: a device that trickles (one byte every 2 s,
/// each within [`PORT_SILENCE`]) is dropped when it is due, not read for
/// ever. USB CDC moves about 1 MB/s; the robot sends its flash at well
/// over 100 kB/s, so an honest 96 kB log is due after 6 s and arrives in
/// a fraction of it.
const PORT_BASE_DEADLINE: Duration = Duration::from_secs(5);
const PORT_MIN_BYTES_PER_S: f64 = 100_000.0;

/// When an image of `bytes` bytes must have arrived, from `start`.
fn port_deadline(start: Instant, bytes: u64) -> Instant {
    start + PORT_BASE_DEADLINE + Duration::from_secs_f64(bytes as f64 / PORT_MIN_BYTES_PER_S)
}

/// Ask the robot for its log: `LOG\n`, then the header, then the records
/// the header announces, all before the deadline ([`port_deadline`]).
fn read_port(name: &str) -> Result<Vec<u8>, PortError> {
    let mut port = serialport::new(name, 115_200)
        .timeout(PORT_SILENCE)
        .open()
        .map_err(PortError::Open)?;
    let _ = port.clear(serialport::ClearBuffer::All);
    port.write_all(b"LOG\n")
        .and_then(|()| port.flush())
        .map_err(PortError::Request)?;
    let start = Instant::now();
    let mut timeout = |p: &mut Box<dyn serialport::SerialPort>, t: Duration| {
        let _ = p.set_timeout(t.min(PORT_SILENCE));
    };
    read_image(&mut port, start, &mut timeout)
}

/// The image from `port`: header, then the announced records; the whole
/// read ends by [`port_deadline`]. `set_timeout` bounds each read by the
/// time left.
fn read_image<R: Read>(
    port: &mut R,
    start: Instant,
    set_timeout: &mut dyn FnMut(&mut R, Duration),
) -> Result<Vec<u8>, PortError> {
    let mut bytes = vec![0u8; HEADER_LEN];
    read_exact_by(
        port,
        &mut bytes,
        port_deadline(start, HEADER_LEN as u64),
        set_timeout,
    )
    .map_err(PortError::NoHeader)?;
    let count = u32::from_le_bytes([bytes[12], bytes[13], bytes[14], bytes[15]]) as u64;
    let total = HEADER_LEN as u64 + count.saturating_mul(16);
    if &bytes[..4] != b"SWLG" || total > MAX_IMAGE_BYTES {
        // Decoding says what is wrong (magic, version, lengths).
        return Ok(bytes);
    }
    let mut rest = vec![0u8; (total as usize) - HEADER_LEN];
    let deadline = port_deadline(start, total);
    read_exact_by(port, &mut rest, deadline, set_timeout).map_err(|why| PortError::Stopped {
        records: count,
        why,
    })?;
    bytes.extend_from_slice(&rest);
    Ok(bytes)
}

/// `read_exact` that gives up at `deadline` however the bytes trickle in.
fn read_exact_by<R: Read>(
    r: &mut R,
    buf: &mut [u8],
    deadline: Instant,
    set_timeout: &mut dyn FnMut(&mut R, Duration),
) -> Result<(), ShortRead> {
    let mut filled = 0;
    let wanted = buf.len();
    while filled < wanted {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            return Err(ShortRead::Deadline { filled, wanted });
        }
        set_timeout(r, left);
        match r.read(&mut buf[filled..]) {
            Ok(0) => return Err(ShortRead::Closed { filled, wanted }),
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(ShortRead::Io(e)),
        }
    }
    Ok(())
}

/// Why the robot's port gave no log.
#[derive(Debug, thiserror::Error)]
pub enum PortError {
    #[error("cannot open the robot's port: {0}")]
    Open(serialport::Error),
    #[error("cannot send the LOG request: {0}")]
    Request(std::io::Error),
    #[error("no log header from the robot: {0}")]
    NoHeader(ShortRead),
    /// The header announced `records` records; fewer bytes followed.
    #[error("the robot sent the header of {records} records, then stopped: {why}")]
    Stopped { records: u64, why: ShortRead },
}

/// Fewer bytes than wanted from the port: how many, and why it stopped.
#[derive(Debug, thiserror::Error)]
pub enum ShortRead {
    #[error(
        "{filled} of {wanted} bytes arrived before the read's deadline; the port is too slow or not the robot"
    )]
    Deadline { filled: usize, wanted: usize },
    #[error("the port closed after {filled} of {wanted} bytes")]
    Closed { filled: usize, wanted: usize },
    #[error("{0}")]
    Io(std::io::Error),
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A device that sends one byte per read, `delay` apart.
    struct Trickle {
        delay: Duration,
        next: u8,
    }

    impl Read for Trickle {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            std::thread::sleep(self.delay);
            buf[0] = self.next;
            self.next = self.next.wrapping_add(1);
            Ok(1)
        }
    }

    #[test]
    fn a_trickling_port_is_dropped_at_the_deadline() {
        let mut port = Trickle {
            delay: Duration::from_millis(20),
            next: 0,
        };
        // Started long ago: the deadline has nearly passed.
        let start = Instant::now() - PORT_BASE_DEADLINE + Duration::from_millis(100);
        let t = Instant::now();
        let e = read_image(&mut port, start, &mut |_, _| {})
            .unwrap_err()
            .to_string();
        assert!(e.contains("before the read's deadline"), "{e}");
        assert!(t.elapsed() < Duration::from_secs(2), "{:?}", t.elapsed());
        // The time left is what each read may wait.
        let mut waits = Vec::new();
        let mut port = Trickle {
            delay: Duration::ZERO,
            next: 0,
        };
        let _ = read_exact_by(
            &mut port,
            &mut [0u8; 3],
            Instant::now() + Duration::from_secs(1),
            &mut |_, t| waits.push(t),
        );
        assert_eq!(waits.len(), 3);
        assert!(
            waits.iter().all(|w| *w <= Duration::from_secs(1)),
            "{waits:?}"
        );
    }

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
        let e = read_source(&Source::Port("/dev/ttyACM-none".into()), &Inputs::new()).unwrap_err();
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
        let got = read_source(&Source::Port(name), &Inputs::new());
        done.send(()).unwrap();
        assert_eq!(&served.join().unwrap(), b"LOG\n");
        let (log, bytes) = got.expect("the log");
        assert_eq!(bytes, image);
        assert_eq!(log.records.len(), 1);
        assert_eq!(log.records[0].rate_mhz, Some(799));
        drop(keep);
    }
}
