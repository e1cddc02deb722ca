//! The body's resistance `B_b` (paper eq. 10): a prolate spheroid of the
//! body's overall length and diameter in unbounded fluid, with the
//! closed-form translational and rotational resistances of a prolate
//! spheroid; `D` and `E` diagonal, `G = 0` (axisymmetric, centred).
//!
//! With semi-axes `a > b`, eccentricity `e = sqrt(1 - b²/a²)` and
//! `L = ln((1+e)/(1-e))`:
//!
//! ```text
//! axial translation       16 pi mu a e³ / ((1+e²) L - 2e)
//! transverse translation  32 pi mu a e³ / (2e + (3e²-1) L)
//! axial rotation          32/3 pi mu a b² e³ / (2e - (1-e²) L)
//! transverse rotation     32/3 pi mu a³ e³ (2-e²) / ((1+e²) L - 2e)
//! ```
//!
//! Each tends to the sphere's `6 pi mu a`, `8 pi mu a³` as `e -> 0` and the
//! axial drag to slender-body theory's `2 pi mu (2a) / (ln(2a/b) - 1/2)` as
//! `e -> 1` (both tested).
//!
//! The paper takes its body coefficients from its ref. \[28\], which is not
//! available to us; this spheroid is the documented base instead, and the
//! paper's Table III factors (`body-correction`) multiply it.
//!
//! References: A. T. Chwang & T. Y. Wu, J. Fluid Mech. 63 (1974) 607 and
//! 67 (1975) 787; S. Kim & S. J. Karrila, *Microhydrodynamics* (1991), ch. 3.

use super::geometry::Body;
use nalgebra::Matrix6;
use std::f64::consts::PI;

/// Diagonal resistances of an axisymmetric body (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyResistance {
    /// Axial translation `D(1,1)` (N s / m).
    pub axial_n_s_per_m: f64,
    /// Transverse translation `D(2,2) = D(3,3)` (N s / m).
    pub transverse_n_s_per_m: f64,
    /// Axial rotation `E(1,1)` (N m s).
    pub axial_rot_n_m_s: f64,
    /// Transverse rotation `E(2,2) = E(3,3)` (N m s).
    pub transverse_rot_n_m_s: f64,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BodyError {
    #[error("body length {length_mm} mm is shorter than its diameter {diameter_mm} mm: the prolate-spheroid body model needs length >= diameter")]
    NotProlate { length_mm: f64, diameter_mm: f64 },
}

impl BodyResistance {
    /// Prolate spheroid of the body's length and diameter (see module docs).
    pub fn prolate_spheroid(body: &Body, viscosity_pa_s: f64) -> Result<Self, BodyError> {
        let a = 0.5 * body.length_m;
        let b = 0.5 * body.diameter_m;
        if b > a {
            return Err(BodyError::NotProlate {
                length_mm: body.length_m * 1e3,
                diameter_mm: body.diameter_m * 1e3,
            });
        }
        let mu = viscosity_pa_s;
        let e = (1.0 - (b / a).powi(2)).sqrt();
        let f = shape_factors(e);
        Ok(BodyResistance {
            axial_n_s_per_m: 6.0 * PI * mu * a * f.axial,
            transverse_n_s_per_m: 6.0 * PI * mu * a * f.transverse,
            axial_rot_n_m_s: 8.0 * PI * mu * a * b * b * f.axial_rot,
            transverse_rot_n_m_s: 8.0 * PI * mu * a.powi(3) * f.transverse_rot,
        })
    }

    /// The 6x6 `B_b` of eq. 10.
    pub fn matrix(&self) -> Matrix6<f64> {
        Matrix6::from_diagonal(&nalgebra::Vector6::new(
            self.axial_n_s_per_m,
            self.transverse_n_s_per_m,
            self.transverse_n_s_per_m,
            self.axial_rot_n_m_s,
            self.transverse_rot_n_m_s,
            self.transverse_rot_n_m_s,
        ))
    }
}

/// Chwang & Wu's resistances divided by the sphere values of the same `a`
/// (axial rotation by `8 pi mu a b²`), all -> 1 as e -> 0.
struct ShapeFactors {
    axial: f64,
    transverse: f64,
    axial_rot: f64,
    transverse_rot: f64,
}

fn shape_factors(e: f64) -> ShapeFactors {
    if e < 1e-3 {
        // The closed forms are 0/0 at the sphere; their limit is 1 with an
        // O(e²) correction far below the data's precision here.
        return ShapeFactors {
            axial: 1.0,
            transverse: 1.0,
            axial_rot: 1.0,
            transverse_rot: 1.0,
        };
    }
    let l = ((1.0 + e) / (1.0 - e)).ln();
    let e3 = e.powi(3);
    ShapeFactors {
        axial: (8.0 / 3.0) * e3 / ((1.0 + e * e) * l - 2.0 * e),
        transverse: (16.0 / 3.0) * e3 / (2.0 * e + (3.0 * e * e - 1.0) * l),
        axial_rot: (4.0 / 3.0) * e3 / (2.0 * e - (1.0 - e * e) * l),
        transverse_rot: (4.0 / 3.0) * e3 * (2.0 - e * e) / ((1.0 + e * e) * l - 2.0 * e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_sphere_tends_to_stokes_drag_and_rotlet_torque() {
        let mu = 2.0;
        let r = 0.01;
        let nearly = Body {
            length_m: 2.0 * r * 1.0001,
            diameter_m: 2.0 * r,
        };
        let res = BodyResistance::prolate_spheroid(&nearly, mu).unwrap();
        let stokes = 6.0 * PI * mu * r;
        let rot = 8.0 * PI * mu * r.powi(3);
        assert!((res.axial_n_s_per_m / stokes - 1.0).abs() < 1e-3);
        assert!((res.transverse_n_s_per_m / stokes - 1.0).abs() < 1e-3);
        assert!((res.axial_rot_n_m_s / rot - 1.0).abs() < 1e-3);
        assert!((res.transverse_rot_n_m_s / rot - 1.0).abs() < 1e-3);
    }

    #[test]
    fn slender_limit_matches_slender_body_axial_drag() {
        let mu = 1.0;
        let (a, b) = (1.0, 1e-4);
        let res = BodyResistance::prolate_spheroid(
            &Body {
                length_m: 2.0 * a,
                diameter_m: 2.0 * b,
            },
            mu,
        )
        .unwrap();
        let sbt = 2.0 * PI * mu * (2.0 * a) / ((2.0 * a / b).ln() - 0.5);
        assert!(
            (res.axial_n_s_per_m / sbt - 1.0).abs() < 1e-3,
            "{} vs {sbt}",
            res.axial_n_s_per_m
        );
        let sbt_transverse = 4.0 * PI * mu * (2.0 * a) / ((2.0 * a / b).ln() + 0.5);
        let t = res.transverse_n_s_per_m;
        assert!(
            (t / sbt_transverse - 1.0).abs() < 1e-3,
            "{t} vs {sbt_transverse}"
        );
    }

    #[test]
    fn elongation_orders_the_resistances() {
        let res = BodyResistance::prolate_spheroid(&Body::from_mm(50.0, 20.0), 3.5).unwrap();
        assert!(res.transverse_n_s_per_m > res.axial_n_s_per_m);
        assert!(res.transverse_rot_n_m_s > res.axial_rot_n_m_s);
        assert!(res.matrix().cholesky().is_some());
    }

    #[test]
    fn oblate_body_is_rejected_with_its_dimensions() {
        let err = BodyResistance::prolate_spheroid(&Body::from_mm(10.0, 20.0), 1.0).unwrap_err();
        assert!(err.to_string().contains("10 mm"));
    }
}
