//! The run log: what the robot did, at 10 Hz for a whole
//! 10-minute run, kept in flash and read out over USB after the run, so the
//! tail's rate becomes a measured input of a dataset (`swimbot log` on the
//! host) instead of a count from 30 fps video.
//!
//! - [`record`]: one 16-byte record: time, set-point, measured rate, duty,
//!   cell voltage, the events and the sensor fault of the interval, and the
//!   frames from other remotes ignored in it;
//! - [`recorder`]: turns the main-loop pass's output ([`crate::PassOutput`])
//!   into records, one every [`board::LOG_PERIOD_US`](crate::board) while the
//!   motor may run, plus one closing record when it stops;
//! - [`image`]: the log image (32-byte header + records), `encode` and a
//!   total `decode` (any bytes give a log or a typed [`DecodeError`]);
//! - [`readout`]: the request/answer protocol over USB CDC;
//! - [`power_up`]: what a readout says about the power-up it is read in
//!   (whose records, and whether this power-up's run was dropped);
//! - [`store`]: the log's slots in flash: which slot a power-up writes,
//!   which it erases (only while the motor is off), what a readout holds.
//!
//! # The log image (version 2, all integers little-endian)
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 4 | magic `SWLG` |
//! | 4 | 2 | version = 2 (1: the same layout, dropped count 0 in a log of an earlier power-up) |
//! | 6 | 2 | header length = 32 |
//! | 8 | 2 | record length = 16 |
//! | 10 | 2 | sample period, ms (100: 10 Hz) |
//! | 12 | 4 | record count N |
//! | 16 | 4 | records this power-up took and did not keep (its log slot was full or not yet erased), also in a log of an earlier power-up: records there and none kept = this power-up's run was dropped |
//! | 20 | 4 | frames from other remotes ignored since power-up; in a log of an earlier power-up, the sum of its records' counts |
//! | 24 | 2 | paired remote's NEC address (0x0000-0x00FF), 0xFFFF = unpaired |
//! | 26 | 2 | flags: bit 0 closed (the motor was off when the image was made: always, since USB holds it off), bit 1 recovered (the log of an earlier power-up, rebuilt from flash) |
//! | 28 | 4 | CRC-32 (ISO-HDLC, as zlib's `crc32`) of bytes 0-27 followed by the N records |
//! | 32 | 16 N | records |
//!
//! A record (16 bytes):
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 4 | time, ms since power-up (the pass that took the record) |
//! | 4 | 2 | set-point, mHz (0 = none selected) |
//! | 6 | 2 | measured rate, mHz, turn-averaged (0xFFFF = not measured) |
//! | 8 | 2 | PWM duty, 1/10000 of the period (0-10000) |
//! | 10 | 2 | cell voltage, mV (the battery monitor's loaded average; 0 = no reading) |
//! | 12 | 2 | events since the previous record ([`Events`] bits) |
//! | 14 | 1 | sensor fault that stopped the motor in the interval: 0 none, 1 stalled, 2 reversed, 3 disconnected, 4 overspeed |
//! | 15 | 1 | frames from other remotes ignored in the interval (saturates at 255) |
//!
//! # Readout over USB CDC
//!
//! The robot enumerates as a CDC-ACM serial port (USB VID 0x16C0 / PID
//! 0x27DD, product "swimbot run log") whenever VBUS is present; while it is,
//! the motor is off and On is refused. The host sends one ASCII request
//! line ending in `\n` (a `\r` before it is ignored; at most
//! [`readout::MAX_REQUEST`] bytes); the device answers:
//!
//! | request | answer |
//! |---|---|
//! | `LOG` | the log image of the last run, exactly `32 + 16 N` bytes (binary; N from the header). With no run recorded: a valid image with N = 0 |
//! | `INFO` | one line: `swimbot-log v2 records=N period_ms=100 dropped=D foreign=F paired=0xAA log=L this_run=R` (or `paired=none`), then the robot's status (`status::Status`): `fw=0.1.0 commit=C battery_mv=M battery=B rate_mhz=X set_mhz=S fault=F trips=T lockout=yes|no pairing=P`, then `\n`. `L`: whose records `LOG` sends, `this` (this power-up's), `earlier` (an earlier power-up's) or `none`; `R`: what became of this power-up's records, `none` (the motor did not run), `kept`, `partly-dropped` or `dropped` (none kept: `LOG` holds no record of this power-up) |
//! | `BOOTSEL` | `OK BOOTSEL\n`, then the chip reboots into the ROM's USB bootloader (the RPI-RP2 drive: `cargo xtask flash`); only with the motor off and its gate low, else `ERR motor on\n` and nothing happens |
//! | anything else | `ERR unknown request\n` |
//!
//! The host reads the 32-byte header first, takes N from it, then reads the
//! records and checks the CRC with [`decode`].
//!
//! References: CRC-32/ISO-HDLC as catalogued by G. Cook, *Catalogue of
//! parametrised CRC algorithms* (reveng.sourceforge.io/crc-catalogue);
//! USB CDC 1.2, ACM subclass (usb.org).

pub mod image;
pub mod power_up;
pub mod readout;
pub mod record;
pub mod recorder;
pub mod status;
pub mod store;
#[cfg(test)]
mod tests;

pub use image::{
    decode, encode, DecodeError, EncodeError, Header, ImageDigest, LogImage, HEADER_LEN,
};
pub use power_up::{LogOf, ThisRun};
pub use readout::{Request, RequestReader};
pub use record::{Events, Record, RECORD_LEN};
pub use recorder::Recorder;
pub use store::{LogFlash, LogStore, ReadoutImage, StoreLayout};
