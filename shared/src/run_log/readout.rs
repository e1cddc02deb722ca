//! The readout protocol's device side (the table in `run_log`'s module
//! doc): request lines from the USB CDC byte stream, and the `INFO` answer.
//! A request longer than [`MAX_REQUEST`] bytes is discarded up to its
//! newline and answered as unknown, so no byte stream can overflow the
//! reader or leave it stuck.

use super::image::Header;
use core::fmt::Write;

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

/// The `INFO` answer for `header`, newline included.
pub fn info_line(header: &Header) -> heapless::String<112> {
    let mut s = heapless::String::new();
    // The longest line (three 10-digit counts, a 5-digit period) is 100 bytes.
    let _ = write!(
        s,
        "swimbot-log v1 records={} period_ms={} dropped={} foreign={} paired=",
        header.record_count, header.sample_period_ms, header.dropped_records, header.foreign_frames
    );
    let _ = match header.paired_address {
        Some(a) => writeln!(s, "{a:#04x}"),
        None => writeln!(s, "none"),
    };
    s
}
