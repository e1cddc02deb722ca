//! The feasible experiments: what the rig can run, each field's range
//! taken from the dataset's `[rig]` block ([`crate::data::rig`]) or, where
//! the block is silent, from the dataset itself (the smallest and largest
//! value it records: the range the lab has shown it can run), and the
//! tubes it has (stated, or the diameters the cases used).

use crate::data::rig::RigLimits;
use crate::data::{Case, Dataset};

/// A field's feasible range and where it came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    pub lo: f64,
    pub hi: f64,
    /// Stated in `[rig]` (else: the dataset's own range).
    pub stated: bool,
}

impl Range {
    /// `n` evenly spaced values from `lo` to `hi` (one when they agree).
    pub fn grid(&self, n: usize) -> Vec<f64> {
        if self.hi <= self.lo || n < 2 {
            return vec![self.lo];
        }
        (0..n)
            .map(|i| self.lo + (self.hi - self.lo) * i as f64 / (n - 1) as f64)
            .collect()
    }

    pub fn contains(&self, x: f64) -> bool {
        x >= self.lo * (1.0 - 1e-12) && x <= self.hi * (1.0 + 1e-12)
    }

    fn words(&self, unit: &str) -> String {
        let src = if self.stated { "stated" } else { "the data's" };
        format!(
            "{}-{} {unit} ({src})",
            crate::format::fmt_sig(self.lo, 3),
            crate::format::fmt_sig(self.hi, 3)
        )
    }
}

/// What the rig can run (module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Rig {
    pub frequency_hz: Range,
    pub amplitude_mm: Range,
    pub wavelength_mm: Range,
    pub tail_length_mm: Range,
    /// The tubes' inner diameters.
    pub tubes_mm: Vec<f64>,
    pub tubes_stated: bool,
}

/// A field of a case that a new experiment may change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Field {
    Frequency,
    Amplitude,
    Wavelength,
    TailLength,
    Tube,
}

impl Field {
    pub const ALL: [Field; 5] = [
        Field::Frequency,
        Field::Amplitude,
        Field::Wavelength,
        Field::TailLength,
        Field::Tube,
    ];

    /// The dataset key.
    pub fn key(self) -> &'static str {
        match self {
            Field::Frequency => "frequency_hz",
            Field::Amplitude => "amplitude_mm",
            Field::Wavelength => "wavelength_mm",
            Field::TailLength => "tail_length_mm",
            Field::Tube => "channel_diameter_mm",
        }
    }

    pub fn get(self, c: &Case) -> f64 {
        match self {
            Field::Frequency => c.frequency_hz,
            Field::Amplitude => c.amplitude_mm,
            Field::Wavelength => c.wavelength_mm,
            Field::TailLength => c.tail_length_mm,
            Field::Tube => c.channel_diameter_mm,
        }
    }

    pub fn set(self, c: &mut Case, x: f64) {
        match self {
            Field::Frequency => c.frequency_hz = x,
            Field::Amplitude => c.amplitude_mm = x,
            Field::Wavelength => c.wavelength_mm = x,
            Field::TailLength => c.tail_length_mm = x,
            Field::Tube => c.channel_diameter_mm = x,
        }
    }
}

fn range_of(data: &Dataset, field: Field, stated: Option<(f64, f64)>) -> Range {
    match stated {
        Some((lo, hi)) => Range {
            lo,
            hi,
            stated: true,
        },
        None => {
            let v = data.cases.iter().map(|c| field.get(c));
            Range {
                lo: v.clone().fold(f64::INFINITY, f64::min),
                hi: v.fold(f64::NEG_INFINITY, f64::max),
                stated: false,
            }
        }
    }
}

/// Most tubes a suggestion lists one by one (8); more are given by their
/// count and span.
const MOST_TUBES_LISTED: usize = 8;

impl Rig {
    /// The rig of `data` (module docs).
    pub fn of(data: &Dataset) -> Rig {
        let r: &RigLimits = &data.rig;
        let (tubes_mm, tubes_stated) = match &r.channel_diameter_mm {
            Some(t) => (t.clone(), true),
            None => {
                let mut t: Vec<f64> = data.cases.iter().map(|c| c.channel_diameter_mm).collect();
                t.sort_by(f64::total_cmp);
                t.dedup();
                (t, false)
            }
        };
        Rig {
            frequency_hz: range_of(data, Field::Frequency, r.frequency_hz),
            amplitude_mm: range_of(data, Field::Amplitude, r.amplitude_mm),
            wavelength_mm: range_of(data, Field::Wavelength, r.wavelength_mm),
            tail_length_mm: range_of(data, Field::TailLength, r.tail_length_mm),
            tubes_mm,
            tubes_stated,
        }
    }

    /// The values `field` may take in a new experiment.
    pub fn values(&self, field: Field, grid: usize) -> Vec<f64> {
        match field {
            Field::Frequency => self.frequency_hz.grid(grid),
            Field::Amplitude => self.amplitude_mm.grid(grid),
            Field::Wavelength => self.wavelength_mm.grid(grid),
            Field::TailLength => self.tail_length_mm.grid(grid),
            Field::Tube => self.tubes_mm.clone(),
        }
    }

    /// Whether a case's changeable fields all lie inside the rig.
    pub fn admits(&self, c: &Case) -> bool {
        self.frequency_hz.contains(c.frequency_hz)
            && self.amplitude_mm.contains(c.amplitude_mm)
            && self.wavelength_mm.contains(c.wavelength_mm)
            && self.tail_length_mm.contains(c.tail_length_mm)
            && self
                .tubes_mm
                .iter()
                .any(|d| (d - c.channel_diameter_mm).abs() <= 1e-9 * d)
    }

    /// The ranges in words, for a suggestion's sentence.
    pub fn describe(&self) -> String {
        let mut sorted = self.tubes_mm.clone();
        sorted.sort_by(f64::total_cmp);
        let mut tubes: Vec<String> = sorted
            .iter()
            .map(|d| crate::format::fmt_sig(*d, 3))
            .collect();
        tubes.dedup();
        // A design with a tube per case lists dozens: their span says it.
        let tubes = match tubes.len() > MOST_TUBES_LISTED {
            true => format!(
                "{} between {} and {}",
                sorted.len(),
                tubes[0],
                tubes[tubes.len() - 1]
            ),
            false => tubes.join(", "),
        };
        format!(
            "rates {}, amplitudes {}, wavelengths {}, tail lengths {}, tubes {} mm ({})",
            self.frequency_hz.words("Hz"),
            self.amplitude_mm.words("mm"),
            self.wavelength_mm.words("mm"),
            self.tail_length_mm.words("mm"),
            tubes,
            if self.tubes_stated {
                "stated"
            } else {
                "the data's"
            }
        )
    }
}

/// Whether the tail and body fit the tube and the helix is well posed
/// (the dataset parser's geometry rules, and the data limits).
pub fn feasible(c: &Case) -> bool {
    c.wavelength_mm > c.wire_diameter_mm
        && c.amplitude_mm + 0.5 * c.wire_diameter_mm < 0.5 * c.channel_diameter_mm
        && c.body_diameter_mm < c.channel_diameter_mm
        && crate::data::limits::check_case(c).is_ok()
}
