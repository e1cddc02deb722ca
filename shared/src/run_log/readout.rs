//! The readout protocol's device side (the table in `run_log`'s module
//! doc): request lines from the USB CDC byte stream, and the `INFO` answer.
//! A request longer than [`MAX_REQUEST`] bytes is discarded up to its
//! newline and answered as unknown, so no byte stream can overflow the
//! reader or leave it stuck.

use super::image::{Header, VERSION};
use super::power_up::{LogOf, ThisRun};

/// Longest request line kept (bytes before the newline).
pub const MAX_REQUEST: usize = 16;

/// A complete request.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Request {
    /// `LOG`: the log image.
    Log,
    /// `INFO`: one line about the log and the robot (`status`).
    Info,
    /// `BOOTSEL`: reboot into the ROM's USB bootloader (`status::bootsel`).
    Bootsel,
    /// Anything else: `ERR unknown request`.
    Unknown,
}

/// The answer to [`Request::Unknown`].
pub const UNKNOWN_ANSWER: &[u8] = b"ERR unknown request\n";

/// Collects request lines from received bytes.
#[derive(Clone, Debug, Default)]
pub struct RequestReader {
    line: heapless::Vec<u8, MAX_REQUEST>,
    overflow: bool,
}

impl RequestReader {
    pub const fn new() -> Self {
        Self {
            line: heapless::Vec::new(),
            overflow: false,
        }
    }

    /// Feed one received byte; the request it completes, if any.
    pub fn push(&mut self, byte: u8) -> Option<Request> {
        if byte != b'\n' {
            if self.line.push(byte).is_err() {
                self.overflow = true;
            }
            return None;
        }
        let line = self.line.strip_suffix(b"\r").unwrap_or(&self.line);
        let request = match (self.overflow, line) {
            (false, b"LOG") => Request::Log,
            (false, b"INFO") => Request::Info,
            (false, b"BOOTSEL") => Request::Bootsel,
            _ => Request::Unknown,
        };
        self.line.clear();
        self.overflow = false;
        Some(request)
    }
}

/// Capacity of an answer [`Line`].
pub const LINE_MAX: usize = 320;

/// An answer line of at most [`LINE_MAX`] bytes. Filled with
/// `copy_from_slice`: heapless's `extend_from_slice` copies byte by byte
/// through `Clone`, which cost the firmware about 0.3 kB of flash.
#[derive(Clone, Debug)]
pub struct Line {
    bytes: [u8; LINE_MAX],
    len: usize,
}

impl Line {
    pub const fn new() -> Self {
        Self {
            bytes: [0; LINE_MAX],
            len: 0,
        }
    }

    /// A line holding `bytes` (empty if they do not fit).
    pub fn from_bytes(bytes: &[u8]) -> Self {
        let mut line = Self::new();
        line.put(bytes);
        line
    }

    pub fn as_slice(&self) -> &[u8] {
        &self.bytes[..self.len]
    }

    /// Append `bytes` whole, or nothing if they do not fit.
    pub(super) fn put(&mut self, bytes: &[u8]) {
        let Some(to) = self.bytes.get_mut(self.len..self.len + bytes.len()) else {
            return;
        };
        to.copy_from_slice(bytes);
        self.len += bytes.len();
    }

    /// Append `n` in decimal.
    pub(super) fn put_decimal(&mut self, mut n: u32) {
        let mut digits = [0u8; 10];
        let mut i = digits.len();
        loop {
            i -= 1;
            digits[i] = b'0' + (n % 10) as u8;
            n /= 10;
            if n == 0 {
                break;
            }
        }
        self.put(&digits[i..]);
    }
}

impl Default for Line {
    fn default() -> Self {
        Self::new()
    }
}

impl core::ops::Deref for Line {
    type Target = [u8];

    fn deref(&self) -> &[u8] {
        self.as_slice()
    }
}

/// The `INFO` answer for `header` and the robot's `status` (the robot's
/// own fields after the log's; `None`: the log's only), newline included. Formatted by hand: `core::fmt` would cost the firmware about
/// 2 kB of flash for this line.
pub fn info_line(header: &Header, status: Option<&super::status::Status>) -> Line {
    let mut s = Line::new();
    // The log's part is at most 133 bytes (three 10-digit counts, a 5-digit
    // period, `log=this this_run=partly-dropped`), the status's at most 171
    // (`Status::put`): every put fits in LINE_MAX.
    s.put(b"swimbot-log v");
    s.put_decimal(u32::from(VERSION));
    s.put(b" records=");
    s.put_decimal(header.record_count);
    s.put(b" period_ms=");
    s.put_decimal(u32::from(header.sample_period_ms));
    s.put(b" dropped=");
    s.put_decimal(header.dropped_records);
    s.put(b" foreign=");
    s.put_decimal(header.foreign_frames);
    s.put(b" paired=");
    match header.paired_address {
        Some(a) => {
            const HEX: &[u8; 16] = b"0123456789abcdef";
            s.put(&[
                b'0',
                b'x',
                HEX[usize::from(a >> 4)],
                HEX[usize::from(a & 15)],
            ]);
        }
        None => s.put(b"none"),
    }
    s.put(b" log=");
    s.put(LogOf::of(header).word());
    s.put(b" this_run=");
    if let Some(run) = ThisRun::of(header, VERSION) {
        s.put(run.word());
    }
    if let Some(status) = status {
        status.put(&mut s);
    }
    s.put(b"\n");
    s
}
