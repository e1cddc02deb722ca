//! Settings of the tube solve: which wall, which solver, the wall's
//! resolution and the memory limit. The defaults are the converged
//! settings of `docs/tail-in-tube.md` (wall spacing, source offset, cap
//! distance) and the ring solver of [`super::rings`].

use super::super::{NonlocalError, NonlocalSettings, TailMethod};
use super::wall::CapLayout;

/// Which wall.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WallModel {
    /// Leak-free: singular Stokeslets outside the wall (MFS).
    Mfs,
    /// The old wall: regularized Stokeslets on it, blob
    /// `tail.surface_blob_over_spacing` times the spacing. For contrast only.
    Leaky,
}

/// Which linear solver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WallSolver {
    /// Split the wall into Fourier modes by its rotational symmetry
    /// ([`super::rings`]); the default.
    Rings,
    /// One dense LU of everything ([`super::mfs::solve_dense`]): the reference.
    Dense,
}

/// Default peak memory of one solve: 4 GB. The machine has 24 GB shared
/// by several processes; a larger solve would also take minutes.
pub const DEFAULT_MAX_PEAK_BYTES: usize = 4_000_000_000;

/// Resolution of the tube solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TubeSettings {
    /// Tail and body discretisation (the `wall_*` fields are not read).
    pub tail: NonlocalSettings,
    pub wall: WallModel,
    pub solver: WallSolver,
    /// How the closed tube's end caps are covered.
    pub caps: CapLayout,
    /// Distance between wall collocation points (m).
    pub wall_spacing_m: f64,
    /// MFS source distance outside the wall over the wall spacing.
    pub source_offset_over_spacing: f64,
    /// Caps (closed) or open ends this many tube radii beyond the object.
    pub cap_margin_over_radius: f64,
    /// Refuse a solve whose estimated peak memory exceeds this (bytes).
    pub max_peak_bytes: usize,
}

impl Default for TubeSettings {
    /// Measured on two-turn tail #6 in the closed 35 mm tube: the axial
    /// entries at 3 mm are within 0.03 % of 2.5 mm, within 0.15 % of
    /// sources 2 spacings out, within 0.1 % of caps 1 and 2 radii away, net
    /// flux 0.08 % of the piston flux; offsets of 0.35-1 spacing leak (21 %
    /// to 1.3 %), and 4.5 mm walls can excite spurious cap modes
    /// (`docs/tail-in-tube.md`).
    fn default() -> Self {
        TubeSettings {
            tail: NonlocalSettings::default(),
            wall: WallModel::Mfs,
            solver: WallSolver::Rings,
            caps: CapLayout::Rings,
            wall_spacing_m: 3.0e-3,
            source_offset_over_spacing: 1.5,
            cap_margin_over_radius: 1.5,
            max_peak_bytes: DEFAULT_MAX_PEAK_BYTES,
        }
    }
}

impl TubeSettings {
    pub(crate) fn validate(&self) -> Result<(), NonlocalError> {
        self.tail.validate()?;
        if self.tail.method != TailMethod::RegularizedStokeslets {
            return Err(NonlocalError::Settings(
                "the tube solver represents the tail by regularized Stokeslets only".into(),
            ));
        }
        for (name, v) in [
            ("wall_spacing_m", self.wall_spacing_m),
            (
                "source_offset_over_spacing",
                self.source_offset_over_spacing,
            ),
            ("cap_margin_over_radius", self.cap_margin_over_radius),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(NonlocalError::Settings(format!(
                    "{name} must be positive and finite, got {v}"
                )));
            }
        }
        Ok(())
    }
}
