//! Non-local hydrodynamics of the tail: local RFT ignores the flow that one
//! part of the helix induces at every other part. This effect replaces the
//! RFT tail matrix by the regularized-Stokeslet one (Cortez blob, 12
//! segments per turn, converged to 1 % on the axial entries), i.e. it adds
//! the difference between the non-local and the local tail. No free
//! parameter. Local-drag effects (tail-confinement) would not act on it and
//! are refused with it ([`super::tail_compat`]); the matrix is taken at the
//! helix's reference phase.
//!
//! References: R. Cortez, L. Fauci & A. Medovikov, Phys. Fluids 17 (2005)
//! 031504; B. Rodenborn, C.-H. Chen, H. L. Swinney, B. Liu & H. P. Zhang,
//! PNAS 110 (2013) E338 (RFT fails for helices of this pitch).

use super::{Effect, EffectError};
use crate::data::Case;
use crate::nonlocal::memo::nonlocal_tail;
use crate::nonlocal::TailMethod;
use nalgebra::Matrix6;

pub struct NonlocalTail;

/// Segments per turn of the effect's regularized-Stokeslet solve.
pub const SEGMENTS_PER_TURN: usize = 12;

impl Effect for NonlocalTail {
    fn name(&self) -> &'static str {
        "nonlocal-tail"
    }
    fn statement(&self) -> &'static str {
        "hydrodynamic interaction along the helix: the tail matrix by regularized Stokeslets instead of local RFT"
    }
    fn reference(&self) -> &'static str {
        "Cortez, Fauci & Medovikov, Phys. Fluids 17 (2005) 031504; Rodenborn et al., PNAS 110 (2013) E338"
    }
    fn order(&self) -> u8 {
        0
    }
    fn replaces_tail(&self) -> bool {
        true
    }
    fn tail(&self, _p: &[f64], case: &Case, tail: &mut Matrix6<f64>) -> Result<(), EffectError> {
        *tail = nonlocal_tail(
            &case.helix(),
            case.viscosity_pa_s,
            TailMethod::RegularizedStokeslets,
            SEGMENTS_PER_TURN,
        )?;
        Ok(())
    }
}
