//! Tail-wall contact. A tail long against the channel cannot stay coaxial
//! ("maintaining coaxial swimming is unrealistic with comparable channel
//! and tail lengths", section III); where it wobbles onto the wall, the
//! rotating helix rolls on a lubricated film and screws itself along like a
//! thread in a nut, an extra thrust the paper invokes for tail #1. Modelled
//! as an axial force proportional to the viscous lubrication scale
//! `mu omega B_o L_t`: `F_x = c_w mu omega B_o L_t`, for tails with
//! `L_t / D_ch >= min_length_ratio`.
//!
//! Reference: the paper, section III (tail #1); lubrication of a rotating
//! cylinder near a wall: O. Reynolds (1886), and Tabak & Yesilyurt's
//! horizontal in-channel experiments (the paper's refs. [17]-[18]).

use super::{Effect, ParamSpec};
use crate::data::Case;
use crate::physics::solve::ForceBalance;
use std::borrow::Cow;

pub struct WallContact;

const PARAMS: &[ParamSpec] = &[
    ParamSpec {
        name: Cow::Borrowed("thrust"),
        unit: Cow::Borrowed("1"),
        default: 0.1,
        min: -5.0,
        max: 5.0,
        free: true,
        doc: Cow::Borrowed("c_w: contact thrust in units of mu omega B_o L_t"),
    },
    ParamSpec {
        name: Cow::Borrowed("min_length_ratio"),
        unit: Cow::Borrowed("1"),
        default: 3.0,
        min: 0.0,
        max: 100.0,
        free: false,
        doc: Cow::Borrowed("L_t / D_ch above which the tail touches the wall"),
    },
];

impl Effect for WallContact {
    fn name(&self) -> &'static str {
        "wall-contact"
    }
    fn statement(&self) -> &'static str {
        "long tails touch the wall and roll on a lubricated film: extra thrust c_w mu omega B_o L_t"
    }
    fn reference(&self) -> &'static str {
        "paper section III (tail #1); refs. [17]-[18] of the paper"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn applies_to(&self, case: &Case, p: &[f64]) -> bool {
        case.tail_length_mm / case.channel_diameter_mm >= p[1]
    }
    fn applicability(&self) -> &'static str {
        "tails with L_t / D_ch >= min_length_ratio"
    }
    fn balance(&self, p: &[f64], case: &Case, fb: &mut ForceBalance) {
        let scale = case.viscosity_pa_s
            * case.tail_rate_rad_s()
            * case.amplitude_mm
            * 1e-3
            * case.tail_length_mm
            * 1e-3;
        fb.load[0] += p[0] * scale;
    }
}
