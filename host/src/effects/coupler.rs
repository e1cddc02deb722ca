//! The coupler between body and tail (Table I: 6 mm x 10 mm). It translates
//! with the robot and turns with the tail (it sits on the rotor), so it
//! adds axial drag to the body, estimated as an isolated prolate spheroid
//! of its length and diameter (an upper bound: the body shields it), and
//! rotational drag to the tail, `4 pi mu a² L_c` per unit rate (a rotating
//! cylinder's exact torque per length). No free parameter.
//!
//! References: Chwang & Wu, J. Fluid Mech. 67 (1975) 787 (spheroid);
//! Landau & Lifshitz, *Fluid Mechanics*, §18 (rotating cylinder).

use super::Effect;
use crate::data::Case;
use crate::physics::body::BodyResistance;
use crate::physics::geometry::Body;
use nalgebra::Matrix6;
use std::f64::consts::PI;

pub struct Coupler;

impl Effect for Coupler {
    fn name(&self) -> &'static str {
        "coupler"
    }
    fn statement(&self) -> &'static str {
        "the coupler shaft adds axial drag to the body and rotational drag to the tail (no free parameter)"
    }
    fn reference(&self) -> &'static str {
        "Chwang & Wu, J. Fluid Mech. 67 (1975) 787; Landau & Lifshitz §18"
    }
    fn applies_to(&self, case: &Case, _p: &[f64]) -> bool {
        case.coupler_length_mm > 0.0 && case.coupler_diameter_mm > 0.0
    }
    fn applicability(&self) -> &'static str {
        "cases with a coupler"
    }
    fn body(&self, _p: &[f64], case: &Case, body: &mut Matrix6<f64>) {
        let c = case.coupler();
        let spheroid = Body {
            length_m: c.length_m.max(c.diameter_m),
            diameter_m: c.diameter_m,
        };
        if let Ok(r) = BodyResistance::prolate_spheroid(&spheroid, case.viscosity_pa_s) {
            body[(0, 0)] += r.axial_n_s_per_m;
        }
    }
    fn tail(&self, _p: &[f64], case: &Case, tail: &mut Matrix6<f64>) -> Result<(), String> {
        let c = case.coupler();
        let a = 0.5 * c.diameter_m;
        tail[(3, 3)] += 4.0 * PI * case.viscosity_pa_s * a * a * c.length_m;
        Ok(())
    }
}
