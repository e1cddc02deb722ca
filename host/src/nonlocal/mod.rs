//! Non-local hydrodynamics of the helical tail: slender-body theory and the
//! method of regularized Stokeslets, in free space, with the body, and inside
//! the closed circular channel.
//!
//! Local RFT (paper eq. 3) ignores the interaction between distant parts of
//! the helix, the body and the wall. This module gives the same 6x6
//! resistance matrices without that approximation, in the swimmer frame of
//! [`crate::physics::geometry`] and the RFT convention `F = -B V`,
//! `V = [U; Omega]`, torque about the body centre.
//!
//! # Methods
//! - [`TailMethod::SlenderBody`]: Johnson (1980) / Keller & Rubinow (1976)
//!   slender-body theory for a uniform wire, see [`sbt`].
//! - [`TailMethod::RegularizedStokeslets`]: Cortez (2001), Cortez, Fauci &
//!   Medovikov (2005) regularized Stokeslets along the centre-line, blob
//!   `eps = e^(1/2) a` matched to SBT, see [`mrs_line`].
//! - Body (prolate spheroid) and channel wall (cylinder with end caps):
//!   surfaces of regularized Stokeslets, see [`surface`] and [`robot`].
//!
//! Both tail methods also add the local torque of the wire spinning about
//! its own axis, `4 pi mu a^2` per length (`wire_spin`), which RFT omits.
//!
//! # Cost (measured, see the report in `benches/nonlocal.rs`)
//! Dense `3N x 3N` systems assembled in parallel with rayon and solved by
//! faer's partial-pivoting LU (13x faster than nalgebra's at `3N = 3000` on
//! this 2-core machine: 0.82 s vs 10.9 s, release build).
pub mod confined;
pub mod curve;
pub mod linalg;
pub mod mrs_line;
pub mod rigid;
pub mod robot;
pub mod sbt;
pub mod stokeslet;
pub mod surface;

pub use confined::{
    body_resistance, robot_resistance, sphere_resistance, tail_resistance_in_channel,
    RobotResistance,
};

use crate::physics::geometry::Helix;
use curve::Centreline;
use nalgebra::Matrix6;

/// Errors of the non-local models; geometry is checked before any work.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum NonlocalError {
    #[error("invalid geometry: {0}")]
    Geometry(String),
    #[error("invalid settings: {0}")]
    Settings(String),
    #[error("the linear system could not be solved: {0}")]
    Singular(String),
}

/// Which non-local model represents the tail.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TailMethod {
    /// Johnson / Keller-Rubinow slender-body theory.
    SlenderBody,
    /// Regularized Stokeslet segments on the centre-line.
    RegularizedStokeslets,
}

/// Resolution and model choices; `Default` is the converged setting found in
/// `tests/nonlocal.rs` (axial entries within 1 % of the finest resolution
/// for all six paper tails).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NonlocalSettings {
    pub method: TailMethod,
    /// Segments per helical turn (one wavelength of axial length).
    pub segments_per_turn: usize,
    /// Lower bound on the total number of tail segments (short tails).
    pub min_segments: usize,
    /// Regularized Stokeslet blob `eps` over the wire radius `a`.
    /// Default `e^(1/2)`, the value that matches SBT (see [`mrs_line`]).
    pub blob_over_wire_radius: f64,
    /// Add the torque of the wire spinning about its own centre-line.
    pub wire_spin: bool,
    /// Point spacing on the body surface (m).
    pub body_spacing_m: f64,
    /// Point spacing on the channel wall and end caps (m).
    pub wall_spacing_m: f64,
    /// Surface blob over the local point spacing.
    pub surface_blob_over_spacing: f64,
    /// Distance of the end caps beyond the robot, in channel radii.
    pub tube_end_margin_over_radius: f64,
}

impl Default for NonlocalSettings {
    fn default() -> Self {
        NonlocalSettings {
            method: TailMethod::RegularizedStokeslets,
            segments_per_turn: 24,
            min_segments: 16,
            blob_over_wire_radius: mrs_line::MATCHED_BLOB_OVER_RADIUS,
            wire_spin: true,
            body_spacing_m: 1.5e-3,
            wall_spacing_m: 3.0e-3,
            surface_blob_over_spacing: 0.5,
            tube_end_margin_over_radius: 2.0,
        }
    }
}

impl NonlocalSettings {
    pub fn with_method(self, method: TailMethod) -> Self {
        NonlocalSettings { method, ..self }
    }

    pub fn with_segments_per_turn(self, segments_per_turn: usize) -> Self {
        NonlocalSettings {
            segments_per_turn,
            ..self
        }
    }

    /// Number of tail segments for `helix`.
    pub fn tail_segments(&self, helix: &Helix) -> usize {
        let turns = helix.n_waves();
        ((turns * self.segments_per_turn as f64).ceil() as usize).max(self.min_segments)
    }

    pub(crate) fn validate(&self) -> Result<(), NonlocalError> {
        if self.segments_per_turn < 4 || self.min_segments < 4 {
            return Err(NonlocalError::Settings(format!(
                "need at least 4 segments per turn and in total, got {} and {}",
                self.segments_per_turn, self.min_segments
            )));
        }
        if !(self.blob_over_wire_radius.is_finite() && self.blob_over_wire_radius > 0.0) {
            return Err(NonlocalError::Settings(format!(
                "blob_over_wire_radius must be positive, got {}",
                self.blob_over_wire_radius
            )));
        }
        let surf = [
            ("body_spacing_m", self.body_spacing_m),
            ("wall_spacing_m", self.wall_spacing_m),
            ("surface_blob_over_spacing", self.surface_blob_over_spacing),
            (
                "tube_end_margin_over_radius",
                self.tube_end_margin_over_radius,
            ),
        ];
        for (name, v) in surf {
            if !(v.is_finite() && v > 0.0) {
                return Err(NonlocalError::Settings(format!(
                    "{name} must be positive, got {v}"
                )));
            }
        }
        Ok(())
    }
}

/// Check that `helix` is a physical, slender, non-self-intersecting wire.
pub fn validate_helix(helix: &Helix) -> Result<(), NonlocalError> {
    let g = |msg: String| Err(NonlocalError::Geometry(msg));
    let fields = [
        ("wavelength", helix.wavelength_m),
        ("axial length", helix.axial_length_m),
        ("wire diameter", helix.wire_diameter_m),
    ];
    for (name, v) in fields {
        if !(v.is_finite() && v > 0.0) {
            return g(format!(
                "helix {name} must be positive and finite, got {v} m"
            ));
        }
    }
    if !(helix.amplitude_m.is_finite() && helix.amplitude_m >= 0.0) {
        return g(format!(
            "helix amplitude must be >= 0, got {} m",
            helix.amplitude_m
        ));
    }
    if !(helix.phase_rad.is_finite() && helix.joint_x_m.is_finite()) {
        return g("helix phase and joint position must be finite".into());
    }
    let a = 0.5 * helix.wire_diameter_m;
    // distance between neighbouring turns, measured across the wire
    let gap = helix.wavelength_m * helix.pitch_angle_rad().sin();
    if helix.amplitude_m > 0.0 && helix.wire_diameter_m >= gap {
        return g(format!(
            "wire ({:.3} mm) is thicker than the gap between turns ({:.3} mm)",
            helix.wire_diameter_m * 1e3,
            gap * 1e3
        ));
    }
    let k = helix.wavenumber();
    let curvature = helix.amplitude_m * k * k / (1.0 + (k * helix.amplitude_m).powi(2));
    if a * curvature >= 0.5 {
        return g(format!(
            "wire radius {:.3} mm is not small against the radius of curvature {:.3} mm",
            a * 1e3,
            1e3 / curvature
        ));
    }
    if helix.arc_length_m() < 10.0 * a {
        return g(format!(
            "wire of length {:.3} mm and radius {:.3} mm is not slender",
            helix.arc_length_m() * 1e3,
            a * 1e3
        ));
    }
    Ok(())
}

/// Full 6x6 resistance matrix of the rigid helical tail alone in unbounded
/// fluid, in the swimmer frame (torques about the origin), by the chosen
/// non-local method. Symmetric positive definite up to discretisation error.
pub fn tail_resistance(
    helix: &Helix,
    viscosity_pa_s: f64,
    settings: &NonlocalSettings,
) -> Result<Matrix6<f64>, NonlocalError> {
    validate_helix(helix)?;
    settings.validate()?;
    if !(viscosity_pa_s.is_finite() && viscosity_pa_s > 0.0) {
        return Err(NonlocalError::Settings(format!(
            "viscosity must be positive, got {viscosity_pa_s} Pa s"
        )));
    }
    let n = settings.tail_segments(helix);
    let a = 0.5 * helix.wire_diameter_m;
    let curve = Centreline::Helix(*helix);
    match settings.method {
        TailMethod::SlenderBody => {
            let n_max =
                (helix.arc_length_m() / (sbt::MIN_SEGMENT_OVER_RADIUS * a)).floor() as usize;
            sbt::resistance(
                curve,
                a,
                viscosity_pa_s,
                n.min(n_max.max(4)),
                settings.wire_spin,
            )
        }
        TailMethod::RegularizedStokeslets => mrs_line::resistance(
            curve,
            a,
            viscosity_pa_s,
            n,
            settings.blob_over_wire_radius,
            settings.wire_spin,
        ),
    }
}
