//! The coupler between body and tail (Table I: 6 mm x 10 mm). It translates
//! with the robot and turns with the tail (it sits on the rotor), so it
//! adds axial drag to the body, estimated as an isolated prolate spheroid
//! of its length and diameter (an upper bound: the body shields it), and
//! rotational drag to the tail: the swirl problem of the spinning coupler
//! with its free end face, a gap (the case's `coupler_gap_mm`, default
//! 1 mm) below the stationary body's seal, and the case's tube, solved by ring Stokeslets
//! (`crate::nonlocal::axisym::spin`; 6.00e-6 N m s for the paper's robot at
//! 3.5 Pa s, against 3.96e-6 for the side of an unbounded cylinder,
//! `4 pi mu a² L_c`, which this replaces). No free parameter: the gap is a
//! dataset input that can carry an uncertainty, and `docs/physics.md`
//! section 4 gives the torque from 0.5 to 2 mm (6.63 to 5.66e-6 N m s).
//!
//! The same solve gives the torque the coupler's swirl puts on the body,
//! `S` (2.68e-6 N m s, 45 % of `R`): the off-diagonal of the grand
//! resistance of body and coupler rotation. It is subtracted from the
//! body's and the tail's axial rotational resistance, so the tail gains
//! `R - S` (3.32e-6 N m s, the torque that reaches the tube wall) and the
//! body loses `S`.
//!
//! Cost: one swirl solve of about 400 elements (0.2-0.4 s), memoised in
//! memory and on disk (`crate::nonlocal::cache`, kind
//! `coupler-swirl-per-pa-s`, at 1 Pa s: Stokes torque is linear in the
//! viscosity).
//!
//! References: Chwang & Wu, J. Fluid Mech. 67 (1975) 787 (spheroid);
//! C. Pozrikidis, *Boundary Integral and Singularity Methods for
//! Linearized Viscous Flow* (1992), §2.4, §7.2 (swirl ring Stokeslets).

use super::body_confinement_exact::profile_words;
use super::{Effect, EffectError};
use crate::data::Case;
use crate::nonlocal::axisym::spin::{solve_spin, Stack};
use crate::nonlocal::axisym::{AxisymSettings, Confinement};
use crate::nonlocal::cache;
use crate::physics::body::BodyResistance;
use crate::physics::geometry::Body;
use crate::physics::profile::BodyProfile;
use nalgebra::Matrix6;

pub struct Coupler;

/// Elements across the gap (or the coupler's radius): within 0.05 % of
/// resolution 32 on the paper's robot (table in docs/physics.md, section 4).
pub const SPIN_RESOLUTION: f64 = 4.0;

/// The coupler's axial rotational drag `R` and the torque its swirl puts
/// on the body, `S` (both N m s per rad/s of the coupler), in the case's
/// tube, below the case's body at `gap_mm`.
pub fn coupler_spin(case: &Case, gap_mm: f64) -> Result<(f64, f64), EffectError> {
    let c = case.coupler();
    let mu = case.viscosity_pa_s;
    if !(mu.is_finite() && mu > 0.0) {
        return Err(EffectError::Viscosity { viscosity_pa_s: mu });
    }
    let stack = Stack {
        rotor: BodyProfile::cylinder(c.length_m * 1e3, c.diameter_m * 1e3, 0.0),
        stator: Some(case.body_profile()),
        gap_m: gap_mm * 1e-3,
    };
    let s = AxisymSettings {
        resolution: SPIN_RESOLUTION,
        ..AxisymSettings::default()
    };
    let channel = case.channel();
    let key: Vec<u64> = [
        c.length_m.to_bits(),
        c.diameter_m.to_bits(),
        gap_mm.to_bits(),
    ]
    .into_iter()
    .chain(profile_words(&case.body_profile()))
    .chain(cache::channel_words(&channel))
    .chain([s.resolution.to_bits(), s.growth.to_bits()])
    .collect();
    let m = cache::cached_matrix("coupler-swirl-per-pa-s", &key, || {
        solve_spin(&stack, &Confinement::of_channel(&channel), 0.0, 1.0, &s).map(|r| {
            let mut m = Matrix6::zeros();
            m[(3, 3)] = r.rotational_drag_n_m_s;
            m[(0, 3)] = r.stator_torque_n_m_s;
            m
        })
    })
    .map_err(|e| EffectError::Solve(e.to_string()))?;
    Ok((mu * m[(3, 3)], mu * m[(0, 3)]))
}

impl Effect for Coupler {
    fn name(&self) -> &'static str {
        "coupler"
    }
    fn statement(&self) -> &'static str {
        "the coupler adds axial drag to the body and rotational drag to the tail: its spin beside the seal, in the tube, by ring Stokeslets (no free parameter)"
    }
    fn reference(&self) -> &'static str {
        "Chwang & Wu, J. Fluid Mech. 67 (1975) 787; Pozrikidis (1992) §2.4, §7.2"
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
        // The cross term of the grand resistance `[[E, -S], [-S, R]]` of
        // body and coupler rotation: the body, turning against the tail,
        // shears the gap more, and the coupler's swirl drags it along. In
        // either drive it enters the x-only balance as `-S` on the body's
        // and on the tail's axial rotational resistance (docs/physics.md,
        // section 4). A failed solve is reported by the tail stage.
        if let Ok((_, s)) = coupler_spin(case, case.coupler_gap_mm) {
            body[(3, 3)] -= s;
        }
    }
    fn tail(&self, _p: &[f64], case: &Case, tail: &mut Matrix6<f64>) -> Result<(), EffectError> {
        let (r, s) = coupler_spin(case, case.coupler_gap_mm).map_err(|e| EffectError::Within {
            context: format!("coupler spin (coupler_gap_mm {})", case.coupler_gap_mm),
            source: Box::new(e),
        })?;
        tail[(3, 3)] += r - s;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::paper;

    #[test]
    fn the_tail_gets_the_solved_spin_torque_and_a_closed_gap_is_refused() {
        let case = paper().cases[0].clone();
        assert_eq!(case.coupler_gap_mm, 1.0);
        let mut tail = Matrix6::zeros();
        Coupler.tail(&[], &case, &mut tail).unwrap();
        let stack = Stack {
            rotor: BodyProfile::cylinder(10.0, 6.0, 0.0),
            stator: Some(case.body_profile()),
            gap_m: 1e-3,
        };
        let s = AxisymSettings {
            resolution: SPIN_RESOLUTION,
            ..AxisymSettings::default()
        };
        let direct = solve_spin(
            &stack,
            &Confinement::of_channel(&case.channel()),
            0.0,
            case.viscosity_pa_s,
            &s,
        )
        .unwrap();
        let (r, s) = (direct.rotational_drag_n_m_s, direct.stator_torque_n_m_s);
        let rel = tail[(3, 3)] / (r - s) - 1.0;
        assert!(rel.abs() < 1e-12, "{} vs {direct:?}", tail[(3, 3)]);
        let mut body = Matrix6::zeros();
        Coupler.body(&[], &case, &mut body);
        assert!((body[(3, 3)] + s).abs() < 1e-12 * s, "{body}");
        // The coupler alone is above the side-only 4 pi mu a^2 L_c (the end
        // faces and the seal add); the grand resistance stays positive
        // definite (S^2 < R E for the body's E in the tube, 3.2e-4 N m s).
        let side = 4.0 * std::f64::consts::PI * case.viscosity_pa_s * 9e-6 * 0.01;
        assert!(r > 1.3 * side && s > 0.0 && s < r, "{r} {s} vs {side}");
        let mut tight = case.clone();
        tight.coupler_gap_mm = 0.01;
        let e = Coupler
            .tail(&[], &tight, &mut tail)
            .unwrap_err()
            .to_string();
        assert!(e.contains("gap") && e.contains("singular"), "{e}");
    }
}
