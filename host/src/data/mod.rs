//! Datasets: the robot's setup and, per case, a tail geometry, its observed
//! tail rate and (optionally) the measured swimming speed and body rotation
//! rate with confidence intervals. The format is TOML or CSV, documented
//! in `docs/data-format.md`; the paper's Tables I, II and IV ship built in.

pub mod body_inputs;
pub mod csv_columns;
mod csv_dialect;
mod csv_header;
mod csv_read;
mod csv_write;
pub mod feature;
mod limit_check;
pub mod limits;
mod load;
pub mod model_quantities;
mod parse;
mod profile;
pub mod quantities;
pub mod recorded;
mod resolve;
pub mod rig;
pub mod uncertainty;
mod write;

pub use csv_dialect::ReadOptions;
pub use feature::Feature;
pub use load::{
    convert_file, convert_file_with, is_csv, load_file, load_recorded, read_csv_str, read_file,
    FileFormat, Loaded,
};
pub use parse::parse_str;
pub use profile::PROFILE_TOLERANCE;
pub use recorded::Recorded;
pub use write::to_toml;

use crate::physics::geometry::{Body, Channel, Coupler, Handedness, Helix};
use crate::physics::profile::BodyProfile;

/// Standard gravity (m/s^2), CGPM 1901.
pub const STANDARD_GRAVITY_M_S2: f64 = 9.806_65;

/// The built-in dataset: the paper's six tails.
pub const PAPER_TOML: &str = include_str!("../../data/paper.toml");

/// The paper's dataset, parsed.
/// The coupler's gap to the seal when a dataset gives none (mm): an
/// estimate for the paper's robot, which gives no figure.
pub const DEFAULT_COUPLER_GAP_MM: f64 = 1.0;

pub fn paper() -> Dataset {
    parse_str(PAPER_TOML, "<built-in paper data>").expect("the built-in paper data is valid")
}

/// The paper's six tails (Table II) as `(lambda, B_o, L_t)` in mm, read
/// from the built-in data, for tests and studies of the tail alone.
pub fn paper_tails_mm() -> Vec<(f64, f64, f64)> {
    paper()
        .cases
        .iter()
        .map(|c| (c.wavelength_mm, c.amplitude_mm, c.tail_length_mm))
        .collect()
}

#[derive(Debug, Clone, PartialEq)]
pub struct Dataset {
    pub name: String,
    pub source: String,
    pub cases: Vec<Case>,
    /// What the rig can run (`[rig]`; empty when the file states nothing).
    pub rig: rig::RigLimits,
}

impl Dataset {
    /// The cases with a measured speed or rotation rate: those any error,
    /// fit or diagnosis is computed on.
    pub fn measured_cases(&self) -> usize {
        self.cases
            .iter()
            .filter(|c| c.u_mm_s.is_some() || c.omega_body_hz.is_some())
            .count()
    }
}

/// A measured mean with its confidence interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    pub mean: f64,
    /// Half-width of the confidence interval at `confidence`.
    pub ci_half_width: f64,
    pub confidence: f64,
    /// Number of trials behind the mean (sets the Student-t factor).
    pub trials: u32,
}

impl Measured {
    /// Standard error of the mean: the CI half-width over the two-sided
    /// Student-t quantile with `trials - 1` degrees of freedom.
    pub fn standard_error(&self) -> f64 {
        self.ci_half_width / crate::stats::student_t_quantile(self.confidence, self.trials)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Orientation {
    Vertical,
    Horizontal,
}

/// One robot configuration, with every `[setup]` default resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub id: String,
    pub wavelength_mm: f64,
    pub amplitude_mm: f64,
    pub tail_length_mm: f64,
    pub wire_diameter_mm: f64,
    pub handedness: Handedness,
    /// Observed tail rotation rate (Hz).
    pub frequency_hz: f64,
    pub channel_diameter_mm: f64,
    pub channel_length_mm: f64,
    pub channel_closed: bool,
    pub orientation: Orientation,
    pub viscosity_pa_s: f64,
    pub density_kg_m3: f64,
    pub body_diameter_mm: f64,
    pub body_length_mm: f64,
    pub coupler_diameter_mm: f64,
    pub coupler_length_mm: f64,
    /// Axial gap between the coupler's top face and the body's seal (mm);
    /// [`DEFAULT_COUPLER_GAP_MM`] if not given (the paper states none).
    pub coupler_gap_mm: f64,
    /// The body's shape as cylindrical sections (`body_profile`), if given;
    /// see [`Case::body_profile`].
    pub body_profile: Option<BodyProfile>,
    /// The robot's weight minus the weight of the oil it displaces, as a
    /// mass (g): positive sinks. 0 (the default) is the paper's neutral
    /// trim; in a vertical channel it is a constant axial load
    /// ([`Case::net_weight_n`]).
    pub net_weight_g: f64,
    /// Swimming speed along the channel (mm/s), if measured.
    pub u_mm_s: Option<Measured>,
    /// Body counter-rotation rate (Hz), if measured.
    pub omega_body_hz: Option<Measured>,
    /// Input uncertainties and recording conventions ([`uncertainty`]).
    pub inputs: uncertainty::CaseInputs,
    /// What the lab recorded beside the case that the model does not read
    /// ([`recorded`]): numbers offered to `diagnose`, labels carried.
    pub recorded: Recorded,
    /// Quantities the tool computed for the case from a model
    /// ([`model_quantities`]); none as read from a file.
    pub derived: model_quantities::Derived,
}

impl Case {
    /// The tail, joined behind the coupler (joint at `-(L_b/2 + L_c)`).
    pub fn helix(&self) -> Helix {
        Helix {
            handedness: self.handedness,
            joint_x_m: -(0.5 * self.body_length_mm + self.coupler_length_mm) * 1e-3,
            ..Helix::from_mm(
                self.wavelength_mm,
                self.amplitude_mm,
                self.tail_length_mm,
                self.wire_diameter_mm,
            )
        }
    }

    pub fn body(&self) -> Body {
        Body::from_mm(self.body_length_mm, self.body_diameter_mm)
    }

    /// The body's surface of revolution: the dataset's `body_profile` if
    /// given, else the model's spheroid `body_length_mm x body_diameter_mm`.
    pub fn body_profile(&self) -> BodyProfile {
        self.body_profile
            .clone()
            .unwrap_or_else(|| BodyProfile::spheroid(self.body_length_mm, self.body_diameter_mm))
    }

    pub fn coupler(&self) -> Coupler {
        Coupler {
            length_m: self.coupler_length_mm * 1e-3,
            diameter_m: self.coupler_diameter_mm * 1e-3,
        }
    }

    pub fn channel(&self) -> Channel {
        Channel {
            diameter_m: self.channel_diameter_mm * 1e-3,
            length_m: self.channel_length_mm * 1e-3,
            closed: self.channel_closed,
            vertical: self.orientation == Orientation::Vertical,
        }
    }

    /// The axial load of the trim error (N, positive up the channel, the
    /// swimming direction): `-net_weight_g g` in a vertical channel, none
    /// in a horizontal one (the weight acts across the axis there).
    pub fn net_weight_n(&self) -> f64 {
        match self.orientation {
            Orientation::Vertical => -self.net_weight_g * 1e-3 * STANDARD_GRAVITY_M_S2,
            Orientation::Horizontal => 0.0,
        }
    }

    /// Tail rotation rate `omega = 2 pi f` (rad/s).
    pub fn tail_rate_rad_s(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.frequency_hz
    }

    /// Number of waves on the tail, `N_lambda = L_t / lambda`.
    pub fn n_waves(&self) -> f64 {
        self.tail_length_mm / self.wavelength_mm
    }

    /// The paper's grouping variable `B_o / R_body`.
    pub fn amplitude_ratio(&self) -> f64 {
        self.amplitude_mm / (0.5 * self.body_diameter_mm)
    }
}

/// A dataset that failed to load: where and what.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}{}{}: {message}", case.as_ref().map(|c| format!(": case `{c}`")).unwrap_or_default(), field.as_ref().map(|f| format!(": field `{f}`")).unwrap_or_default())]
pub struct DataError {
    pub file: String,
    pub case: Option<String>,
    pub field: Option<String>,
    pub message: String,
}
