//! The tube wall's effect on the whole tail, resolved: the tail matrix is
//! replaced by the regularized-Stokeslet helix (Cortez blob on the
//! centre-line) inside the case's channel, whose wall is a cylinder of
//! regularized Stokeslets held still (closed by end caps if the channel is
//! closed, so no net flux passes a cross-section). It is the wall-resolved
//! counterpart of `tail-confinement`, with no free parameter: the wall
//! distance, the wavelength and the tail's non-local self-interaction all
//! come out of one Stokes solve (`crate::nonlocal::tail_resistance_in_channel`).
//!
//! Not proposed by the default `diagnose` (`costly()` is true): a cold
//! solve costs seconds per tail; `diagnose --nonlocal` includes it.
//! Solves are memoised in memory and on disk (`crate::nonlocal::cache`), so
//! only the first run on a machine pays for them.
//!
//! Resolution ([`settings`]): 12 segments per turn, wall points 4 mm apart.
//! Measured cost (release, shared 2-core machine): 0.5-3.3 s per paper tail
//! cold, 9.4 s for all six; the coarse wall leaks, so the wall's effect is
//! underestimated by about 10 % (against a 2.5 mm wall) to 25 % (against
//! zero spacing) on the axial drag and thrust coupling: see
//! [`WALL_SPACING_M`].
//!
//! References: R. Cortez, L. Fauci & A. Medovikov, Phys. Fluids 17 (2005)
//! 031504; wall of regularized Stokeslets: J. Ainley, S. Durkin, R. Embid,
//! P. Boindala & R. Cortez, J. Comput. Phys. 227 (2008) 4600.

use super::Effect;
use crate::data::Case;
use crate::nonlocal::{cache, tail_resistance_in_channel, NonlocalSettings};
use nalgebra::Matrix6;

pub struct TubeTail;

/// Tail segments per helical turn: the module default, within 0.4 % of
/// 48 per turn on the axial entries in free space.
pub const SEGMENTS_PER_TURN: usize = 12;

/// Wall point spacing (m), the blob half of it. Measured in the closed
/// 35 mm paper channel (release build, shared 2-core machine, `--example
/// tube_effects -- resolution`), tail #6 in tube / free at wall spacings
/// 5 / 4 / 3 / 2.5 mm: `B_xx` 2.80 / 2.93 / 3.14 / 3.27, `B_x,wx` 3.07 /
/// 3.21 / 3.43 / 3.57, `B_wx,wx` 1.108 / 1.107 / 1.106 / 1.105, costing
/// 0.3 / 0.8 / 3.4 / 8.9 s. A coarse wall of regularized Stokeslets leaks
/// (the back-flow partly passes through it), so confinement is
/// underestimated: at 4 mm by 10 % against 2.5 mm on the axial drag and
/// thrust coupling, and by about 20-25 % against a linear extrapolation to
/// zero spacing (the convergence is slower than first order here, so that
/// extrapolation is itself uncertain by ~5 %); the axial torque is
/// converged to 0.2 %. 4 mm is chosen for cost: all six paper tails take
/// 9.4 s cold at 4 mm (tail #1 3.3 s), against about 35 s at 3 mm (tail #1
/// 14.9 s).
pub const WALL_SPACING_M: f64 = 4.0e-3;

/// The solver settings of this effect.
pub fn settings() -> NonlocalSettings {
    NonlocalSettings {
        wall_spacing_m: WALL_SPACING_M,
        ..NonlocalSettings::default().with_segments_per_turn(SEGMENTS_PER_TURN)
    }
}

/// The tail matrix in the case's channel at [`settings`], memoised.
pub fn tail_in_tube(case: &Case) -> Result<Matrix6<f64>, String> {
    let (helix, channel, mu, s) = (
        case.helix(),
        case.channel(),
        case.viscosity_pa_s,
        settings(),
    );
    let key: Vec<u64> = cache::helix_words(&helix)
        .into_iter()
        .chain(cache::channel_words(&channel))
        .chain([mu.to_bits()])
        .chain(cache::settings_words(&s))
        .collect();
    cache::cached_matrix("tail-in-channel", &key, || {
        tail_resistance_in_channel(&helix, &channel, mu, &s)
    })
}

impl Effect for TubeTail {
    fn name(&self) -> &'static str {
        "tail-confinement-stokeslets"
    }
    fn statement(&self) -> &'static str {
        "the tail matrix by regularized Stokeslets inside the channel wall (closed or open), with the tail's non-local self-interaction"
    }
    fn reference(&self) -> &'static str {
        "Cortez, Fauci & Medovikov, Phys. Fluids 17 (2005) 031504; Ainley et al., J. Comput. Phys. 227 (2008) 4600"
    }
    /// Too costly for the default diagnosis (seconds per cold solve).
    fn costly(&self) -> bool {
        true
    }
    fn order(&self) -> u8 {
        0
    }
    fn tail(&self, _p: &[f64], case: &Case, tail: &mut Matrix6<f64>) -> Result<(), String> {
        *tail = tail_in_tube(case)?;
        Ok(())
    }
}
