//! The paper's catch-all correction of the body resistance (Table III):
//! `D_x -> Upsilon_T D_x`, `E_x -> Upsilon_R E_x`. Two free factors with no
//! physics behind them; the paper used (16, 1.4) with Gray-Hancock and
//! (4.5, 3.4) with Lighthill, calibrated on the `B_o/R_body = 0.45` tails.
//!
//! Reference: the paper, section II.B and Table III.

use super::{Effect, ParamSpec};
use crate::data::Case;
use nalgebra::Matrix6;
use std::borrow::Cow;

pub struct BodyCorrection;

const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        name: Cow::Borrowed("translation"),
        unit: Cow::Borrowed("1"),
        default: 1.0,
        min: 0.01,
        max: 100.0,
        free: true,
        doc: Cow::Borrowed("Upsilon_T,x: factor on the body's axial translational resistance"),
    },
    ParamSpec {
        name: Cow::Borrowed("rotation"),
        unit: Cow::Borrowed("1"),
        default: 1.0,
        min: 0.01,
        max: 100.0,
        free: true,
        doc: Cow::Borrowed("Upsilon_R,x: factor on the body's axial rotational resistance"),
    },
];

impl Effect for BodyCorrection {
    fn name(&self) -> &'static str {
        "body-correction"
    }
    fn statement(&self) -> &'static str {
        "empirical factors on the body's x-translation and x-rotation resistance (the paper's Table III)"
    }
    fn reference(&self) -> &'static str {
        "paper Table III"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn body(&self, p: &[f64], _case: &Case, body: &mut Matrix6<f64>) {
        body[(0, 0)] *= p[0];
        body[(3, 3)] *= p[1];
    }
}
