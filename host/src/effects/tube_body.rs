//! The tube wall's effect on the body, resolved: the body's axial
//! translation `B_b[0,0]` and axial rotation `B_b[3,3]` are replaced by
//! those of the prolate spheroid (a surface of regularized Stokeslets)
//! inside the case's channel, whose wall is a cylinder of regularized
//! Stokeslets held still and closed by end caps if the channel is closed
//! (zero net flux: the displaced oil must flow back through the gap). It is
//! the wall-resolved counterpart of `body-confinement`, which treats the
//! body as a coaxial cylinder without end effects; this one keeps the
//! spheroid's shape and the finite gap length, with no free parameter
//! (`crate::nonlocal::body_resistance`).
//!
//! Not proposed by the default `diagnose` (`costly()` is true): a cold
//! solve costs seconds; `diagnose --nonlocal` includes it. Solves are
//! memoised in memory and on disk (`crate::nonlocal::cache`).
//!
//! A failed solve cannot be reported through [`Effect::body`], which
//! returns nothing (and the trait is shared by every effect): the entries
//! are then set to NaN, which the force balance rejects
//! (`SolveError::NonFinite`), so the case fails with an error rather than
//! a silently wrong prediction; the solver's message goes to stderr once.
//!
//! Resolution ([`settings`]): body points 1.5 mm apart, wall points 3 mm
//! apart. Measured cost (release, shared 2-core machine): 14 s for the
//! paper's body (one solve serves all six cases); the coarse wall leaks, so
//! the axial drag is underestimated by about 7 % (against a 2.5 mm wall)
//! to 25 % (against zero spacing): see [`WALL_SPACING_M`].
//!
//! References: R. Cortez, L. Fauci & A. Medovikov, Phys. Fluids 17 (2005)
//! 031504; J. Ainley et al., J. Comput. Phys. 227 (2008) 4600; the
//! annular-gap limit: F. Chen, J. Lescarboura & G. Swift, AIChE J. 14
//! (1968) 123.

use super::Effect;
use crate::data::Case;
use crate::nonlocal::{body_resistance, cache, NonlocalSettings};
use nalgebra::Matrix6;
use std::collections::HashSet;
use std::sync::{Mutex, OnceLock};

pub struct TubeBody;

/// Body surface point spacing (m): the module default, 0.15 body radii
/// (prolate spheroid 5:2 within 2 % of Chwang & Wu at 0.2 radii).
pub const BODY_SPACING_M: f64 = 1.5e-3;

/// Wall point spacing (m), the blob half of it. Measured for the paper's
/// body (50 mm x 20 mm spheroid, 1.5 mm body spacing) in the closed 35 mm
/// channel (release build, shared 2-core machine, `--example tube_effects
/// -- resolution`), at wall spacings 5 / 4 / 3 / 2.5 mm: axial drag 4.05 /
/// 4.36 / 4.90 / 5.26 times the free spheroid's, axial torque 1.297 /
/// 1.293 / 1.287 / 1.284 times, costing 3.4 / 5.1 / 14.0 / 29.6 s. The
/// coarse wall leaks, so the drag is underestimated: at 3 mm by 7 % against
/// 2.5 mm and by roughly 20-25 % against an extrapolation to zero spacing;
/// the torque is converged to 0.3 %. 3 mm (finer than the tail's 4 mm) is
/// affordable because every paper case shares one body and one channel:
/// one 14 s solve per machine, memoised on disk.
pub const WALL_SPACING_M: f64 = 3.0e-3;

/// The solver settings of this effect.
pub fn settings() -> NonlocalSettings {
    NonlocalSettings {
        body_spacing_m: BODY_SPACING_M,
        wall_spacing_m: WALL_SPACING_M,
        ..NonlocalSettings::default()
    }
}

/// The body's 6x6 matrix in the case's channel at [`settings`], memoised.
pub fn body_in_tube(case: &Case) -> Result<Matrix6<f64>, String> {
    let (body, channel, mu, s) = (case.body(), case.channel(), case.viscosity_pa_s, settings());
    let key: Vec<u64> = cache::body_words(&body)
        .into_iter()
        .chain(cache::channel_words(&channel))
        .chain([mu.to_bits()])
        .chain(cache::settings_words(&s))
        .collect();
    cache::cached_matrix("body-in-channel", &key, || {
        body_resistance(&body, Some(&channel), mu, &s)
    })
}

/// Print each distinct failure once, not once per prediction of a fit.
fn warn_once(message: String) {
    static SEEN: OnceLock<Mutex<HashSet<String>>> = OnceLock::new();
    let seen = SEEN.get_or_init(|| Mutex::new(HashSet::new()));
    if seen
        .lock()
        .map(|mut s| s.insert(message.clone()))
        .unwrap_or(true)
    {
        eprintln!("warning: {message}");
    }
}

impl Effect for TubeBody {
    fn name(&self) -> &'static str {
        "body-confinement-stokeslets"
    }
    fn statement(&self) -> &'static str {
        "the body's axial drag and torque by regularized Stokeslets: spheroid inside the channel wall (zero net flux if closed)"
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
    fn body(&self, _p: &[f64], case: &Case, body: &mut Matrix6<f64>) {
        match body_in_tube(case) {
            Ok(m) => {
                body[(0, 0)] = m[(0, 0)];
                body[(3, 3)] = m[(3, 3)];
            }
            Err(e) => {
                warn_once(format!(
                    "body-confinement-stokeslets, case {}: {e}; the case fails as non-finite",
                    case.id
                ));
                body[(0, 0)] = f64::NAN;
                body[(3, 3)] = f64::NAN;
            }
        }
    }
}
