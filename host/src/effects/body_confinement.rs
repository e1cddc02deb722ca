//! The body as a cylinder coaxial in the tube (radius `a` in a tube of
//! radius `b`, `k = a/b`, length `L_b`), replacing the free-space spheroid's
//! axial resistances by the annular-gap flows, with no free parameter:
//!
//! * axial translation, closed tube (zero net flux: the displaced oil flows
//!   back through the gap, Couette-Poiseuille):
//!   `F = 2 pi mu L U / [ln(1/k) - (1-k²)/(1+k²)]`;
//!   open tube (no pressure gradient, pure annular Couette): `2 pi mu L U / ln(1/k)`;
//! * axial rotation (cylindrical Couette flow):
//!   `T = 4 pi mu L omega a² b² / (b² - a²)`.
//!
//! End effects of the finite body are neglected, which is fair when the gap
//! `b - a` is small against `L_b` (7.5 mm against 50 mm in the paper).
//! The closed-tube translation already contains the back-flow, so this
//! effect and `backflow` describe overlapping physics.
//!
//! References: falling-cylinder viscometer, F. Chen, J. Lescarboura &
//! G. Swift, AIChE J. 14 (1968) 123, and N. A. Park & T. F. Irvine,
//! Rev. Sci. Instrum. 59 (1988) 2051; Couette flow: Landau & Lifshitz,
//! *Fluid Mechanics*, §18.

use super::Effect;
use crate::data::Case;
use nalgebra::Matrix6;
use std::f64::consts::PI;

pub struct BodyConfinement;

/// Axial translational resistance of the coaxial cylinder (N s / m).
pub fn axial_translation(case: &Case) -> f64 {
    let mu = case.viscosity_pa_s;
    let len = case.body_length_mm * 1e-3;
    let k = case.body_diameter_mm / case.channel_diameter_mm;
    let ln = (1.0 / k).ln();
    let denominator = if case.channel_closed {
        ln - (1.0 - k * k) / (1.0 + k * k)
    } else {
        ln
    };
    2.0 * PI * mu * len / denominator
}

/// Axial rotational resistance of the coaxial cylinder (N m s).
pub fn axial_rotation(case: &Case) -> f64 {
    let mu = case.viscosity_pa_s;
    let len = case.body_length_mm * 1e-3;
    let a2 = (0.5e-3 * case.body_diameter_mm).powi(2);
    let b2 = (0.5e-3 * case.channel_diameter_mm).powi(2);
    4.0 * PI * mu * len * a2 * b2 / (b2 - a2)
}

impl Effect for BodyConfinement {
    fn name(&self) -> &'static str {
        "body-confinement"
    }
    fn statement(&self) -> &'static str {
        "body as a coaxial cylinder in the tube: annular Couette-Poiseuille drag (zero net flux if closed) and Couette torque"
    }
    fn reference(&self) -> &'static str {
        "Chen, Lescarboura & Swift, AIChE J. 14 (1968) 123; Park & Irvine, Rev. Sci. Instrum. 59 (1988) 2051; Landau & Lifshitz §18"
    }
    fn order(&self) -> u8 {
        0
    }
    fn replaces_body(&self) -> bool {
        true
    }
    fn body(&self, _p: &[f64], case: &Case, body: &mut Matrix6<f64>) {
        body[(0, 0)] = axial_translation(case);
        body[(3, 3)] = axial_rotation(case);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_tube_drag_exceeds_open_tube_drag_and_diverges_as_the_gap_closes() {
        let mut c = crate::data::paper().cases[0].clone();
        let closed = axial_translation(&c);
        c.channel_closed = false;
        let open = axial_translation(&c);
        assert!(closed > 5.0 * open, "closed {closed} open {open}");
        c.channel_closed = true;
        c.channel_diameter_mm = 20.5;
        assert!(axial_translation(&c) > 100.0 * closed);
    }

    #[test]
    fn wide_gap_rotation_tends_to_the_free_cylinder() {
        let mut c = crate::data::paper().cases[0].clone();
        c.channel_diameter_mm = 1e5;
        let free = 4.0 * PI * c.viscosity_pa_s * 0.05 * (0.01f64).powi(2);
        assert!((axial_rotation(&c) / free - 1.0).abs() < 1e-6);
    }
}
