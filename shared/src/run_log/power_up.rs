//! What a readout says about the power-up it is read in (image version
//! 2): whose records the image holds ([`LogOf`]) and what
//! became of the records this power-up took ([`ThisRun`]). Without it a
//! power-up whose run was dropped (its slot not yet erased, or full) read
//! out an earlier power-up's log with `dropped=0`, and a lab took a
//! previous run's trace for today's.
//!
//! Both follow from the header alone: the records are an earlier
//! power-up's when `FLAG_RECOVERED` is set, and from version 2 on the
//! dropped count is always this power-up's (in version 1 it was 0 in an
//! earlier power-up's log, so a version-1 image cannot say whether the
//! run of the power-up that made it was lost).

use super::image::{Header, FLAG_RECOVERED, VERSION};

/// Whose records an image holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LogOf {
    /// The power-up the image was made in.
    ThisPowerUp,
    /// An earlier power-up's, rebuilt from flash.
    EarlierPowerUp,
    /// No records at all.
    Nothing,
}

/// What became of the records the power-up making the image took.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ThisRun {
    /// None taken: the motor did not run since power-up.
    NoRun,
    /// Every record taken is in the image.
    Kept,
    /// Some are in the image, `dropped` more were not kept.
    PartlyDropped { dropped: u32 },
    /// Records were taken and none kept (no erased slot, or the flash
    /// refused them): any records in the image are an earlier power-up's.
    Dropped { dropped: u32 },
}

impl LogOf {
    pub fn of(header: &Header) -> Self {
        if header.flags & FLAG_RECOVERED != 0 {
            LogOf::EarlierPowerUp
        } else if header.record_count == 0 {
            LogOf::Nothing
        } else {
            LogOf::ThisPowerUp
        }
    }

    /// The `INFO` line's word for it.
    pub fn word(self) -> &'static [u8] {
        match self {
            LogOf::ThisPowerUp => b"this",
            LogOf::EarlierPowerUp => b"earlier",
            LogOf::Nothing => b"none",
        }
    }
}

impl ThisRun {
    /// For a header of `version`; `None` when a version-1 image holds an
    /// earlier power-up's log (its dropped count is then 0 by definition).
    pub fn of(header: &Header, version: u16) -> Option<Self> {
        let own = LogOf::of(header) == LogOf::ThisPowerUp;
        if version < VERSION && !own {
            return None;
        }
        let dropped = header.dropped_records;
        Some(match (own, dropped) {
            (true, 0) => ThisRun::Kept,
            (true, _) => ThisRun::PartlyDropped { dropped },
            (false, 0) => ThisRun::NoRun,
            (false, _) => ThisRun::Dropped { dropped },
        })
    }

    /// The `INFO` line's word for it.
    pub fn word(self) -> &'static [u8] {
        match self {
            ThisRun::NoRun => b"none",
            ThisRun::Kept => b"kept",
            ThisRun::PartlyDropped { .. } => b"partly-dropped",
            ThisRun::Dropped { .. } => b"dropped",
        }
    }
}
