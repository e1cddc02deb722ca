//! The readout protocol's device side (the table in `run_log`'s module
//! doc): request lines from the USB CDC byte stream, and the `INFO` answer.
//! A request longer than [`MAX_REQUEST`] bytes is discarded up to its
//! newline and answered as unknown, so no byte stream can overflow the
//! reader or leave it stuck.

use super::image::Header;

/// Longest request line kept (bytes before the newline).
pub const MAX_REQUEST: usize = 16;

/// A complete request.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Request {
    /// `LOG`: the log image.
    Log,
    /// `INFO`: one line about the log.
    Info,
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
            _ => Request::Unknown,
        };
        self.line.clear();
        self.overflow = false;
        Some(request)
    }
}

/// The `INFO` answer for `header`, newline included. Formatted by hand:
/// `core::fmt` would cost the firmware about 2 kB of flash for this line.
pub fn info_line(header: &Header) -> heapless::Vec<u8, 112> {
    let mut s = heapless::Vec::new();
    // The longest line (three 10-digit counts, a 5-digit period) is 100
    // bytes: every push below fits.
    let mut put = |bytes: &[u8]| {
        let _ = s.extend_from_slice(bytes);
    };
    put(b"swimbot-log v1 records=");
    put(decimal(header.record_count).as_slice());
    put(b" period_ms=");
    put(decimal(u32::from(header.sample_period_ms)).as_slice());
    put(b" dropped=");
    put(decimal(header.dropped_records).as_slice());
    put(b" foreign=");
    put(decimal(header.foreign_frames).as_slice());
    put(b" paired=");
    match header.paired_address {
        Some(a) => {
            const HEX: &[u8; 16] = b"0123456789abcdef";
            put(&[
                b'0',
                b'x',
                HEX[usize::from(a >> 4)],
                HEX[usize::from(a & 15)],
            ]);
        }
        None => put(b"none"),
    }
    put(b"\n");
    s
}

fn decimal(mut n: u32) -> heapless::Vec<u8, 10> {
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
    heapless::Vec::from_slice(&digits[i..]).unwrap_or_default()
}
