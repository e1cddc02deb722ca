//! Back-flow in a closed channel (paper eqs. 8-9). The robot displaces oil
//! that must flow back through the gap around the body at the mean speed
//! `U R_b² / (R_ch² - R_b²)` against the swimming direction; the body moves
//! relative to that flow, so the back-flow adds drag `-D_x beta U`,
//! `beta = R_b² / (R_ch² - R_b²)`.
//!
//! The paper writes eq. 9 with the observed speed and a sign that, taken
//! literally in eq. 11, would push the robot forward; physically the
//! back-flow opposes the motion, as here. Two variants:
//! `backflow` uses the predicted speed (self-consistent: an extra axial
//! resistance `beta D_x`); `backflow-observed` uses the measured speed as
//! the paper does (a known force), falling back to the predicted one for
//! cases without a measurement.
//!
//! Reference: the paper, eqs. 8-9 and its ref. [27].

use super::Effect;
use crate::data::Case;
use crate::physics::solve::ForceBalance;

/// `beta = R_b² / (R_ch² - R_b²)`: mean back-flow speed per unit robot speed.
pub fn backflow_ratio(case: &Case) -> f64 {
    let rb2 = (0.5 * case.body_diameter_mm).powi(2);
    let rc2 = (0.5 * case.channel_diameter_mm).powi(2);
    rb2 / (rc2 - rb2)
}

pub struct Backflow;

impl Effect for Backflow {
    fn name(&self) -> &'static str {
        "backflow"
    }
    fn statement(&self) -> &'static str {
        "closed channel: displaced oil flows back past the body at U R_b^2/(R_ch^2 - R_b^2), adding body drag (self-consistent in U)"
    }
    fn reference(&self) -> &'static str {
        "paper eqs. 8-9 (sign taken as drag)"
    }
    fn applies_to(&self, case: &Case, _p: &[f64]) -> bool {
        case.channel_closed
    }
    fn applicability(&self) -> &'static str {
        "closed channels"
    }
    fn balance(&self, _p: &[f64], case: &Case, fb: &mut ForceBalance) {
        fb.extra[(0, 0)] += backflow_ratio(case) * fb.body[(0, 0)];
    }
}

pub struct BackflowObserved;

impl Effect for BackflowObserved {
    fn name(&self) -> &'static str {
        "backflow-observed"
    }
    fn statement(&self) -> &'static str {
        "as backflow, but driven by the observed U as in the paper (predicted U where none is measured)"
    }
    fn reference(&self) -> &'static str {
        "paper eqs. 8-9 with U_robot observed"
    }
    fn candidate(&self) -> bool {
        false
    }
    fn applies_to(&self, case: &Case, _p: &[f64]) -> bool {
        case.channel_closed
    }
    fn applicability(&self) -> &'static str {
        "closed channels"
    }
    fn balance(&self, _p: &[f64], case: &Case, fb: &mut ForceBalance) {
        let beta = backflow_ratio(case);
        match case.u_mm_s {
            Some(u) => fb.load[0] -= beta * fb.body[(0, 0)] * u.mean * 1e-3,
            None => fb.extra[(0, 0)] += beta * fb.body[(0, 0)],
        }
    }
}
