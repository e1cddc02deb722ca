//! The tube wall's effect on the tail's local resistance. In RFT the
//! logarithm's outer length is the wavelength (the distance over which the
//! filament's own flow decays); near a wall the flow is cut off at about
//! twice the wall distance `h = R_ch - B_o` instead (slender body parallel
//! to a plane wall: log argument `2h/a`). Combining the two cut-offs as
//! `1/l_eff = 1/lambda + gamma/(2h)` rescales both coefficients of the base
//! set by the Gray-Hancock ratio of logarithms:
//!
//! `c_t *= (ln(lambda/D) - 1/2) / (ln(l_eff/D) - 1/2)`,
//! `c_n *= (ln(lambda/D) + 1/2) / (ln(l_eff/D) + 1/2)`.
//!
//! One free parameter, `gamma` (1 for the plain-wall estimate).
//!
//! References: R. E. Katz, J. R. Blake & S. L. Paveri-Fontana,
//! J. Fluid Mech. 72 (1975) 529; C. Brennen & H. Winet, Annu. Rev. Fluid
//! Mech. 9 (1977) 339.

use super::{Effect, ParamSpec};
use crate::data::Case;
use crate::physics::coefficients::LocalDrag;
use std::borrow::Cow;

pub struct TailConfinement;

const PARAMS: &[ParamSpec] = &[ParamSpec {
    name: Cow::Borrowed("gamma"),
    unit: Cow::Borrowed("1"),
    default: 1.0,
    min: 0.0,
    max: 20.0,
    free: true,
    doc: Cow::Borrowed(
        "weight of the wall cut-off 2h against the wavelength in the log's outer length",
    ),
}];

/// Factors on `(c_t, c_n)` for wall weight `gamma`.
pub fn factors(case: &Case, gamma: f64) -> (f64, f64) {
    let d = case.wire_diameter_mm;
    let lambda = case.wavelength_mm;
    let h = 0.5 * case.channel_diameter_mm - case.amplitude_mm;
    // Keep the log's argument where the slender-body expansion still means
    // something (l_eff >= 2 D), so the factors stay finite and positive.
    let l_eff = (1.0 / (1.0 / lambda + gamma / (2.0 * h))).max(2.0 * d);
    let ln_free = (lambda / d).ln();
    let ln_wall = (l_eff / d).ln();
    (
        (ln_free - 0.5) / (ln_wall - 0.5),
        (ln_free + 0.5) / (ln_wall + 0.5),
    )
}

impl Effect for TailConfinement {
    fn name(&self) -> &'static str {
        "tail-confinement"
    }
    fn statement(&self) -> &'static str {
        "the tube wall at distance R_ch - B_o cuts off the tail's flow and raises its local drag coefficients"
    }
    fn reference(&self) -> &'static str {
        "Katz, Blake & Paveri-Fontana, J. Fluid Mech. 72 (1975) 529; Brennen & Winet, Annu. Rev. Fluid Mech. 9 (1977) 339"
    }
    fn params(&self) -> &'static [ParamSpec] {
        PARAMS
    }
    fn acts_on_local_drag(&self) -> bool {
        true
    }
    fn local_drag(&self, p: &[f64], case: &Case, drag: &mut LocalDrag) {
        let (ft, fn_) = factors(case, p[0]);
        drag.tangential *= ft;
        drag.normal *= fn_;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_wall_weight_means_no_change_and_wider_helices_feel_more() {
        let data = crate::data::paper();
        let (t, n) = factors(&data.cases[0], 0.0);
        assert!((t - 1.0).abs() < 1e-15 && (n - 1.0).abs() < 1e-15);
        let narrow = factors(&data.cases[1], 1.0).0; // B_o = 2.5 mm
        let wide = factors(&data.cases[5], 1.0).0; // B_o = 7.5 mm
        assert!(wide > narrow && narrow > 1.0);
    }
}
