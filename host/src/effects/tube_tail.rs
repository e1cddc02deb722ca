//! The tube wall's effect on the whole tail, resolved without a leak: the
//! tail matrix is replaced by the regularized-Stokeslet helix (Cortez blob
//! on the centre-line) coaxial in the case's channel, whose wall is
//! represented by the method of fundamental solutions: singular Stokeslets
//! outside the wall, zero velocity collocated on the cylinder and, for a
//! closed channel, on end caps (`crate::nonlocal::tube`). It is the
//! wall-resolved counterpart of `tail-confinement`, with no free parameter.
//!
//! The previous version put regularized Stokeslets ON the wall; that wall is
//! porous (the closed tube's back-flow partly passes through it: 16-27 % of
//! the piston flux through a cross-section for the paper's tails, against
//! well under 1 % now) and missed about a third of the tube's axial drag and
//! thrust coupling; the axial torque agrees within about 1 %
//! (`docs/tail-in-tube.md`).
//!
//! Not proposed by the default `diagnose` (`costly()` is true): a cold
//! solve costs seconds per tail; `diagnose --nonlocal` includes it.
//! Solves are memoised in memory and on disk (`crate::nonlocal::cache`,
//! kind `tail-in-tube-rings-per-pa-s`, at 1 Pa s), so only the first run
//! on a machine pays.
//!
//! References: R. Cortez, L. Fauci & A. Medovikov, Phys. Fluids 17 (2005)
//! 031504; G. Fairweather & A. Karageorghis, Adv. Comput. Math. 9 (1998) 69.

use super::{Effect, EffectError};
use crate::data::Case;
use crate::nonlocal::cache;
use crate::nonlocal::tube::{tail_matrix_in_tube, CapLayout, TubeSettings, WallModel};
use nalgebra::Matrix6;

pub struct TubeTail;

/// The solver settings of this effect: the tube module's default (wall
/// points 3 mm apart, sources 1.5 spacings outside, caps 1.5 radii beyond
/// the tail): within 0.1 % of a 2.5 mm wall, of sources 2 spacings out and
/// of caps 2 radii away on the axial entries, net flux through sections
/// below 0.1 % of the piston flux (two-turn tail #6, 35 mm tube).
pub fn settings() -> TubeSettings {
    TubeSettings::default()
}

/// Key words of the tube settings, every field that changes the result.
fn tube_words(s: &TubeSettings) -> impl Iterator<Item = u64> {
    cache::settings_words(&s.tail).into_iter().chain([
        u64::from(s.wall == WallModel::Mfs),
        u64::from(s.caps == CapLayout::Rings),
        s.wall_spacing_m.to_bits(),
        s.source_offset_over_spacing.to_bits(),
        s.cap_margin_over_radius.to_bits(),
    ])
}

/// The tail's matrix in the case's tube. Stokes flow is linear in the
/// viscosity (every kernel and the wire spin carry one factor `mu`), so
/// the matrix is solved and cached at 1 Pa s and scaled: a perturbed
/// viscosity (an uncertainty band) costs no solve. The leak diagnostics
/// are not recomputed here; `helix --channel-diameter-mm` and
/// `examples/tail_tube.rs` show them at these settings.
pub fn tail_in_tube(case: &Case) -> Result<Matrix6<f64>, EffectError> {
    let (helix, channel, mu, s) = (
        case.helix(),
        case.channel(),
        case.viscosity_pa_s,
        settings(),
    );
    if !(mu.is_finite() && mu > 0.0) {
        return Err(EffectError::Viscosity { viscosity_pa_s: mu });
    }
    let key: Vec<u64> = cache::helix_words(&helix)
        .into_iter()
        .chain(cache::channel_words(&channel))
        .chain(tube_words(&s))
        .collect();
    let unit = cache::cached_matrix("tail-in-tube-rings-per-pa-s", &key, || {
        tail_matrix_in_tube(&helix, &channel, 1.0, &s)
    })
    .map_err(|e| EffectError::Solve(e.to_string()))?;
    Ok(unit * mu)
}

impl Effect for TubeTail {
    fn name(&self) -> &'static str {
        "tail-confinement-stokeslets"
    }
    fn statement(&self) -> &'static str {
        "the tail matrix by regularized Stokeslets inside a leak-free channel wall (method of fundamental solutions, closed or open), with the tail's non-local self-interaction"
    }
    fn reference(&self) -> &'static str {
        "Cortez, Fauci & Medovikov, Phys. Fluids 17 (2005) 031504; Fairweather & Karageorghis, Adv. Comput. Math. 9 (1998) 69"
    }
    /// Too costly for the default diagnosis (seconds per cold solve).
    fn costly(&self) -> bool {
        true
    }
    fn order(&self) -> u8 {
        0
    }
    fn replaces_tail(&self) -> bool {
        true
    }
    fn tail(&self, _p: &[f64], case: &Case, tail: &mut Matrix6<f64>) -> Result<(), EffectError> {
        *tail = tail_in_tube(case)?;
        Ok(())
    }
}
