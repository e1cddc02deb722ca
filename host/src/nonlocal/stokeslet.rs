//! Stokes-flow point singularities: the free-space Stokeslet and the
//! regularized Stokeslet / rotlet of Cortez, Fauci & Medovikov (2005).
//!
//! All kernels return the velocity per unit force (or torque) *exerted on the
//! fluid*, already divided by `8 pi mu`, so `u = K(x - y) F`.
//!
//! References:
//! - R. Cortez, "The method of regularized Stokeslets", SIAM J. Sci. Comput.
//!   23 (2001) 1204-1225.
//! - R. Cortez, L. Fauci & A. Medovikov, "The method of regularized Stokeslets
//!   in three dimensions: analysis, validation, and application to helical
//!   swimming", Phys. Fluids 17 (2005) 031504, eqs. (10)-(11) for the blob
//!   `phi_eps(r) = 15 eps^4 / (8 pi (r^2 + eps^2)^(7/2))`.

use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// Free-space (singular) Stokeslet, the Oseen tensor:
/// `u = (I / r + x x^T / r^3) F / (8 pi mu)`.
///
/// Undefined at `x = 0`; callers exclude the self term.
pub fn stokeslet(x: &Vector3<f64>, viscosity_pa_s: f64) -> Matrix3<f64> {
    let r2 = x.norm_squared();
    let r = r2.sqrt();
    let c = 1.0 / (8.0 * PI * viscosity_pa_s);
    (Matrix3::identity() / r + x * x.transpose() / (r2 * r)) * c
}

/// Regularized Stokeslet with the Cortez et al. (2005) blob:
/// `u = [I (r^2 + 2 eps^2) + x x^T] / (r^2 + eps^2)^(3/2) F / (8 pi mu)`.
///
/// Finite everywhere; at `x = 0` it is `2 / eps` times the identity over
/// `8 pi mu`.
pub fn regularized_stokeslet(x: &Vector3<f64>, eps_m: f64, viscosity_pa_s: f64) -> Matrix3<f64> {
    let mut out = Matrix3::zeros();
    add_regularized_stokeslet(&mut out, x, eps_m, 1.0 / (8.0 * PI * viscosity_pa_s));
    out
}

/// `out += weight * [I (r^2 + 2 eps^2) + x x^T] / (r^2 + eps^2)^(3/2)`:
/// the allocation-free inner loop of every matrix assembly here (the caller
/// folds `1 / (8 pi mu)` and quadrature weights into `weight`).
#[inline]
pub fn add_regularized_stokeslet(
    out: &mut Matrix3<f64>,
    x: &Vector3<f64>,
    eps_m: f64,
    weight: f64,
) {
    let r2 = x.norm_squared();
    let e2 = eps_m * eps_m;
    let d = r2 + e2;
    let inv = weight / (d * d.sqrt());
    let diag = (r2 + 2.0 * e2) * inv;
    for a in 0..3 {
        for b in 0..3 {
            out[(a, b)] += x[a] * x[b] * inv;
        }
        out[(a, a)] += diag;
    }
}

/// Regularized rotlet of Cortez et al. (2005) for the same blob: the velocity
/// due to a point torque `L` on the fluid,
/// `u = (2 r^2 + 5 eps^2) / (2 (r^2 + eps^2)^(5/2)) (L x x) / (8 pi mu)`.
///
/// Returned as the matrix `M` with `u = M L`.
pub fn regularized_rotlet(x: &Vector3<f64>, eps_m: f64, viscosity_pa_s: f64) -> Matrix3<f64> {
    let r2 = x.norm_squared();
    let e2 = eps_m * eps_m;
    let d = r2 + e2;
    let g = (2.0 * r2 + 5.0 * e2) / (2.0 * d * d * d.sqrt()) / (8.0 * PI * viscosity_pa_s);
    // L x x = -x x L = -skew(x) L
    -skew(x) * g
}

/// `skew(p) v = p x v`.
pub fn skew(p: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -p[2], p[1], p[2], 0.0, -p[0], -p[1], p[0], 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regularized_tends_to_singular_far_away() {
        let x = Vector3::new(0.3, -0.2, 0.5);
        let s = stokeslet(&x, 2.0);
        let r = regularized_stokeslet(&x, 1e-4, 2.0);
        assert!((s - r).norm() < 1e-6 * s.norm());
    }

    #[test]
    fn regularized_stokeslet_is_divergence_free() {
        // u_a = K_ab F_b; div u = d_a K_ab F_b must vanish for each F_b.
        let eps = 0.3;
        let x = Vector3::new(0.2, 0.1, -0.4);
        let h = 1e-5;
        for b in 0..3 {
            let mut div = 0.0;
            for a in 0..3 {
                let mut dx = Vector3::zeros();
                dx[a] = h;
                let kp = regularized_stokeslet(&(x + dx), eps, 1.0);
                let km = regularized_stokeslet(&(x - dx), eps, 1.0);
                div += (kp[(a, b)] - km[(a, b)]) / (2.0 * h);
            }
            assert!(div.abs() < 1e-6, "div = {div}");
        }
    }

    #[test]
    fn rotlet_is_curl_of_stokeslet_half() {
        // The rotlet is (1/2) curl of the Stokeslet applied to L, for any blob.
        let eps = 0.2;
        let x = Vector3::new(0.15, -0.3, 0.25);
        let l = Vector3::new(0.3, 0.7, -0.4);
        let h = 1e-5;
        let u = |p: Vector3<f64>| regularized_stokeslet(&p, eps, 1.0) * l;
        let mut curl = Vector3::zeros();
        for a in 0..3 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let mut db = Vector3::zeros();
            db[b] = h;
            let mut dc = Vector3::zeros();
            dc[c] = h;
            let d_b_uc = (u(x + db)[c] - u(x - db)[c]) / (2.0 * h);
            let d_c_ub = (u(x + dc)[b] - u(x - dc)[b]) / (2.0 * h);
            curl[a] = d_b_uc - d_c_ub;
        }
        let rot = regularized_rotlet(&x, eps, 1.0) * l;
        assert!(
            (rot - curl * 0.5).norm() < 1e-6 * rot.norm(),
            "{rot} vs {}",
            curl * 0.5
        );
    }
}
