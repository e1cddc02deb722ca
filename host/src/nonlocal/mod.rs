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
//! - Body (prolate spheroid): a surface of regularized Stokeslets in free
//!   space, see [`surface`] and [`robot`]. In the tube: the leak-free wall
//!   (method of fundamental solutions, solved by its rotational symmetry)
//!   with its flux diagnostics, [`tube`], and the exact axisymmetric body,
//!   [`axisym`]. The old wall of regularized Stokeslets leaked; it survives
//!   only in `tail_resistance_in_channel` and `tube::WallModel::Leaky`, as
//!   the contrast that shows the leak.
//!
//! Both tail methods also add the local torque of the wire spinning about
//! its own axis, `4 pi mu a^2` per length (`wire_spin`), which RFT omits.
//!
//! # Checks (`tests/nonlocal.rs`, measured)
//! - Straight rod vs Cox (1970) / Batchelor (1970): SBT 0.90 % / 0.57 %
//!   (parallel / perpendicular) at `l/a = 1e3`, 0.36 % / 0.27 % at `1e4`;
//!   regularized Stokeslets 1.06 % / 0.72 % and 0.42 % / 0.31 %: the
//!   `O(1/ln^2)` remainder of the asymptotic formula.
//! - Helix, regularized Stokeslets: 12 segments per turn is within 0.4 % of
//!   48 per turn on `B_xx`, `B_x,wx`, `B_wx,wx` for tails #1 and #5; 24 per
//!   turn within 0.06 %.
//! - SBT vs regularized Stokeslets, two-turn helix: worst axial entry differs
//!   by 0.37 % at wire 0.1 mm and 0.11 % at 0.01 mm. On the 1 mm paper tails
//!   they agree within 0.3 % on `B_xx` and 0.7 % on `B_wx,wx`, but the thrust
//!   coupling `B_x,wx` differs by 1-7 % (largest for the tight tail #1),
//!   which is the size of the SBT resolution spread (2.7 %).
//! - Prolate spheroid 5:2 vs Chwang & Wu (1975): 1.9 % / 1.3 % at spacing
//!   `0.2 b`, first order in the spacing.
//! - Sphere on a tube axis, `a/R = 0.3`, vs Haberman & Sayre (1958): see
//!   `tests/tail_tube.rs` (leak-free wall) and `tests/axisym.rs` (Bohlin).
//!
//! # Cost (release build, this 2-core machine shared with others)
//! Dense `3N x 3N` systems assembled in parallel with rayon and solved by
//! faer's partial-pivoting LU (13x faster than nalgebra's at `3N = 3000`:
//! 0.82 s vs 10.9 s). The fastest converged tail setting (1 % on the axial
//! entries) is the default, 12 segments per turn: 2-11 ms per paper tail
//! (regularized Stokeslets), 48 per turn 20-200 ms. With the body (1.5 mm
//! spacing, about 1200 points) and the closed 35 mm channel (3 mm spacing,
//! 2000-3500 points), `3N` is 10 000-14 000: 0.8-1.6 GB and 0.5-1.5 min
//! densely; [`tube`] avoids the wall's share of that by its symmetry.
//! Memory is `8 (3N)^2` bytes, so 24 GiB holds `3N` up to about 50 000
//! (N = 17 000 points), but its LU (`2/3 (3N)^3` flops at the ~20 Gflop/s
//! measured) would take over an hour; `3N ~ 20 000` (3 GB, ~4 min) is the
//! practical limit.
pub mod axisym;
pub mod cache;
pub mod confined;
pub mod curve;
pub mod gauss_legendre;
pub mod linalg;
pub mod memo;
pub mod mrs_line;
pub mod rigid;
pub mod robot;
pub mod sbt;
pub mod stokeslet;
pub mod surface;
pub mod tube;

pub use confined::{
    free_body_resistance, robot_resistance, tail_resistance_in_channel, RobotResistance,
};

use crate::physics::geometry::Helix;
use curve::Centreline;
use nalgebra::Matrix6;

/// Errors of the non-local models; geometry is checked before any work.
#[derive(Debug, Clone, thiserror::Error, PartialEq)]
pub enum NonlocalError {
    #[error("invalid geometry: {0}")]
    Geometry(String),
    /// The body's profile, with what is wrong as data.
    #[error("invalid geometry: {0}")]
    Profile(#[from] crate::physics::profile::ProfileError),
    /// A surface that cannot be cut into elements.
    #[error("invalid geometry: {0}")]
    Mesh(#[from] axisym::mesh::MeshError),
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

/// Resolution and model choices. `Default` is the fastest converged
/// setting: 12 segments per turn puts the axial entries of tails #1 and #5
/// within 0.4 % of 48 per turn (`tests/nonlocal.rs`).
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
            segments_per_turn: 12,
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
    linalg::check_memory(n)?;
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
