//! One record of the run log and its 16 bytes (layout: the table in
//! `run_log`'s module doc).

use crate::rate::SensorFault;

/// Bytes of one record.
pub const RECORD_LEN: usize = 16;

/// Rate field meaning "not measured".
const NO_RATE: u16 = u16::MAX;

/// What happened in a record's interval, one bit each. A small newtype
/// rather than the `bitflags` crate: sixteen constants and three methods
/// do not justify a dependency in the firmware.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Events(u16);

impl Events {
    pub const NONE: Self = Self(0);
    /// An On frame from the paired remote.
    pub const ON: Self = Self(1 << 0);
    /// An Off frame from the paired remote.
    pub const OFF: Self = Self(1 << 1);
    pub const STARTED: Self = Self(1 << 2);
    /// The soft start ended.
    pub const RAMP_DONE: Self = Self(1 << 3);
    pub const STOPPED_COMMAND: Self = Self(1 << 4);
    /// The 10-minute limit stopped the run.
    pub const STOPPED_MAX_RUN_TIME: Self = Self(1 << 5);
    /// The battery cut-off stopped the run.
    pub const STOPPED_LOW_BATTERY: Self = Self(1 << 6);
    /// No or an implausible battery reading stopped the run.
    pub const STOPPED_BATTERY_FAULT: Self = Self(1 << 7);
    /// On arrived while the battery forbade running.
    pub const START_REFUSED: Self = Self(1 << 8);
    /// A set-point key changed the set-point.
    pub const SET_POINT_CHANGED: Self = Self(1 << 9);
    /// On arrived with no set-point selected.
    pub const NO_SET_POINT: Self = Self(1 << 10);
    /// The cell read below the warning level.
    pub const LOW_BATTERY: Self = Self(1 << 11);
    /// The cut-off latch was set.
    pub const CUTOFF_LATCHED: Self = Self(1 << 12);
    /// A remote was paired (its address is the header's).
    pub const PAIRED: Self = Self(1 << 13);
    /// An interrupt queue (IR or Hall edges) overflowed and dropped edges.
    pub const EDGES_DROPPED: Self = Self(1 << 14);
    /// USB was connected: the motor was stopped and On is refused.
    pub const USB_CONNECTED: Self = Self(1 << 15);

    pub const fn bits(self) -> u16 {
        self.0
    }

    pub const fn from_bits(bits: u16) -> Self {
        Self(bits)
    }

    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0 && other.0 != 0
    }

    pub fn insert(&mut self, other: Self) {
        self.0 |= other.0;
    }

    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }
}

/// One sample of the run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Record {
    /// Milliseconds since power-up at the pass that took the record.
    pub t_ms: u32,
    /// The selected set-point (mHz), if any.
    pub set_point_mhz: Option<u16>,
    /// The turn-averaged measured rate (mHz), if measured.
    pub rate_mhz: Option<u16>,
    /// PWM duty in 1/10000 of the period (0..=10000).
    pub duty_per_10k: u16,
    /// The battery monitor's averaged, loaded cell voltage (0: no reading).
    pub cell_mv: u16,
    pub events: Events,
    /// The sensor fault that stopped the motor in the interval.
    pub fault: Option<SensorFault>,
    /// Frames from other remotes ignored in the interval (saturating).
    pub foreign_frames: u8,
}

/// Why 16 bytes do not make a record.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RecordError {
    /// The fault byte is not 0-6.
    FaultCode(u8),
    /// The duty is above 10000 (100 %).
    Duty(u16),
}

const fn fault_code(f: Option<SensorFault>) -> u8 {
    match f {
        None => 0,
        Some(SensorFault::Stalled) => 1,
        Some(SensorFault::Reversed) => 2,
        Some(SensorFault::Disconnected) => 3,
        Some(SensorFault::Overspeed) => 4,
        Some(SensorFault::Jammed) => 5,
        Some(SensorFault::Overheated) => 6,
    }
}

const fn fault_of(code: u8) -> Result<Option<SensorFault>, RecordError> {
    Ok(Some(match code {
        0 => return Ok(None),
        1 => SensorFault::Stalled,
        2 => SensorFault::Reversed,
        3 => SensorFault::Disconnected,
        4 => SensorFault::Overspeed,
        5 => SensorFault::Jammed,
        6 => SensorFault::Overheated,
        c => return Err(RecordError::FaultCode(c)),
    }))
}

/// The duty's 1/65536 fraction (0..=65536) in 1/10000, rounded.
pub fn duty_per_10k(raw: u32) -> u16 {
    let d = (u64::from(raw.min(1 << 16)) * 10_000 + (1 << 15)) >> 16;
    u16::try_from(d).unwrap_or(10_000)
}

/// A mHz value in the record's 16 bits: above 65.534 Hz reads as 65.534 Hz
/// (the controller's overspeed fault is at 10 Hz).
pub fn mhz_u16(mhz: u32) -> u16 {
    u16::try_from(mhz).unwrap_or(NO_RATE - 1).min(NO_RATE - 1)
}

impl Record {
    pub fn to_bytes(&self) -> [u8; RECORD_LEN] {
        let mut b = [0u8; RECORD_LEN];
        b[0..4].copy_from_slice(&self.t_ms.to_le_bytes());
        b[4..6].copy_from_slice(&self.set_point_mhz.unwrap_or(0).to_le_bytes());
        b[6..8].copy_from_slice(&self.rate_mhz.unwrap_or(NO_RATE).to_le_bytes());
        b[8..10].copy_from_slice(&self.duty_per_10k.min(10_000).to_le_bytes());
        b[10..12].copy_from_slice(&self.cell_mv.to_le_bytes());
        b[12..14].copy_from_slice(&self.events.bits().to_le_bytes());
        b[14] = fault_code(self.fault);
        b[15] = self.foreign_frames;
        b
    }

    pub fn from_bytes(b: &[u8; RECORD_LEN]) -> Result<Self, RecordError> {
        let u16_at = |i: usize| u16::from_le_bytes([b[i], b[i + 1]]);
        let duty = u16_at(8);
        if duty > 10_000 {
            return Err(RecordError::Duty(duty));
        }
        Ok(Self {
            t_ms: u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            set_point_mhz: Some(u16_at(4)).filter(|&f| f != 0),
            rate_mhz: Some(u16_at(6)).filter(|&f| f != NO_RATE),
            duty_per_10k: duty,
            cell_mv: u16_at(10),
            events: Events::from_bits(u16_at(12)),
            fault: fault_of(b[14])?,
            foreign_frames: b[15],
        })
    }
}
