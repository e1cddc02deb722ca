//! Ring Stokeslets: the velocity at `(x, sigma)` of a ring of point forces
//! of radius `sigma0` at axial position `x0`, per unit force density and
//! per unit length of the generating curve (the ring's `sigma0 dphi` is
//! inside). With `u_a(x) = 1/(8 pi mu) int M_ab(x, x0) f_b(x0) dl(x0)`:
//!
//! * meridional (axial and radial forces, axial translation):
//!   `M_xx = s0 (I10 + x^2 I30)`, `M_xs = s0 x (s I31 - s0 I30)`,
//!   `M_sx = s0 x (s I30 - s0 I31)`,
//!   `M_ss = s0 (I11 + (s^2 + s0^2) I31 - s s0 (I30 + I32))`;
//! * azimuthal (swirl, axial rotation): `M_pp = s0 (I11 + s s0 (I30 - I32))`,
//!
//! where `x` is `x - x0` and `I_mn = int_0^2pi cos^n(phi) / D^(m/2) dphi`,
//! `D = x^2 + s^2 + s0^2 - 2 s s0 cos(phi)`.
//!
//! Two evaluations, each used where it is accurate:
//! * `m = 4 s s0 / rho^2 >= 1/2` (near the ring, `rho^2 = x^2 + (s+s0)^2`):
//!   closed forms in `K(m)`, `E(m)`, rearranged by hand so that the
//!   `1/d^2` (`d^2 = x^2 + (s-s0)^2`) parts of `I30`, `I31`, `I32` cancel
//!   analytically, not numerically; only the logarithm of `K` stays
//!   singular, and `k' = d / rho` is passed to the AGM without forming
//!   `1 - m`. The swirl kernel is `8 s0 [(2-m) K - 2 E] / (rho m)`.
//! * `m < 1/2` (far from the ring, or near the axis, where the closed forms
//!   lose digits to `1/m^2` cancellation): the periodic trapezoidal rule in
//!   `phi` on 24 points, exponentially convergent because the integrand is
//!   analytic in a strip of half-width `2 acosh(1/k) >= 1.76`
//!   (error below `e^(-24 x 1.76) ~ 1e-18`); 12 points for `m < 0.1`
//!   (half-width >= 3.6, error below `e^-43`), the bulk of the pairs.
//!
//! The two branches are tested against each other at the switch and against
//! a fine trapezoidal rule, and the kernels against the reciprocity
//! `M_ab(x; x0) / s0 = M_ba(x0; x) / s`.
//!
//! References: C. Pozrikidis, *Boundary Integral and Singularity Methods
//! for Linearized Viscous Flow* (Cambridge, 1992), §2.4 and §7.2; the
//! swirl kernel as in Pozrikidis (1992), eq. (2.4.10) family.

use super::elliptic::complete_ke;
use std::f64::consts::PI;

/// The five ring-kernel entries at one (target, source) pair, or their
/// integrals over a source element.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Ring {
    pub xx: f64,
    pub xs: f64,
    pub sx: f64,
    pub ss: f64,
    /// Azimuthal (swirl) kernel.
    pub pp: f64,
}

impl Ring {
    pub fn add_scaled(&mut self, o: &Ring, w: f64) {
        self.xx += w * o.xx;
        self.xs += w * o.xs;
        self.sx += w * o.sx;
        self.ss += w * o.ss;
        self.pp += w * o.pp;
    }
}

/// Points of the periodic trapezoidal rule (full period).
const TRAPEZOID_POINTS: usize = 24;
/// Below this `m` the trapezoidal rule is used.
pub const M_SWITCH: f64 = 0.5;

/// The ring kernel at target `(x, s)` from the ring `(x0, s0)`; `s0 > 0`.
pub fn ring(x: f64, s: f64, x0: f64, s0: f64) -> Ring {
    let xh = x - x0;
    let rho2 = xh * xh + (s + s0) * (s + s0);
    let m = 4.0 * s * s0 / rho2;
    if m < 0.1 {
        // Strip half-width 2 acosh(1/k) >= 3.6: 12 points give e^-43.
        ring_trapezoid(xh, s, s0, TRAPEZOID_POINTS / 2)
    } else if m < M_SWITCH {
        ring_trapezoid(xh, s, s0, TRAPEZOID_POINTS)
    } else {
        ring_elliptic(xh, s, s0)
    }
}

/// Closed forms in `K`, `E`; accurate for `m >= 1/2`.
pub fn ring_elliptic(xh: f64, s: f64, s0: f64) -> Ring {
    let x2 = xh * xh;
    let rho2 = x2 + (s + s0) * (s + s0);
    let d2 = x2 + (s - s0) * (s - s0);
    let rho = rho2.sqrt();
    let m = 4.0 * s * s0 / rho2;
    let kc = (d2 / rho2).sqrt();
    let (kk, ee) = complete_ke(m, kc);
    let j1 = 4.0 * kk / rho;
    let j3 = 4.0 * ee / (rho * d2);
    let jm1 = 4.0 * rho * ee;
    let ds2 = s * s - s0 * s0;
    Ring {
        xx: s0 * (j1 + x2 * j3),
        xs: 0.5 * xh * ((x2 + ds2) * j3 - j1),
        sx: s0 * xh / (2.0 * s) * ((ds2 - x2) * j3 + j1),
        ss: ((ds2 * ds2 - x2 * x2) * j3 + 2.0 * (2.0 * x2 + s * s + s0 * s0) * j1 - 3.0 * jm1)
            / (4.0 * s),
        pp: 8.0 * s0 * ((2.0 - m) * kk - 2.0 * ee) / (rho * m),
    }
}

/// Direct periodic trapezoidal rule in `phi` with `n` points (even).
pub fn ring_trapezoid(xh: f64, s: f64, s0: f64, n: usize) -> Ring {
    let r2 = xh * xh + s * s + s0 * s0;
    let two_ss0 = 2.0 * s * s0;
    let (mut i10, mut i30, mut i11, mut i31, mut i32) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let half = n / 2;
    let h = 2.0 * PI / n as f64;
    // The integrand is even in phi: points 0 and n/2 once, the others twice.
    for j in 0..=half {
        let w = if j == 0 || j == half { h } else { 2.0 * h };
        let c = (j as f64 * h).cos();
        let d = r2 - two_ss0 * c;
        let inv = 1.0 / d.sqrt();
        let inv3 = inv / d;
        i10 += w * inv;
        i30 += w * inv3;
        i11 += w * c * inv;
        i31 += w * c * inv3;
        i32 += w * c * c * inv3;
    }
    let ss0 = s * s0;
    Ring {
        xx: s0 * (i10 + xh * xh * i30),
        xs: s0 * xh * (s * i31 - s0 * i30),
        sx: s0 * xh * (s * i30 - s0 * i31),
        ss: s0 * (i11 + (s * s + s0 * s0) * i31 - ss0 * (i30 + i32)),
        pp: s0 * (i11 + ss0 * (i30 - i32)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Ring, b: &Ring, tol: f64) -> bool {
        let scale = a.xx.abs().max(a.ss.abs()).max(a.pp.abs()).max(1e-300);
        [
            (a.xx, b.xx),
            (a.xs, b.xs),
            (a.sx, b.sx),
            (a.ss, b.ss),
            (a.pp, b.pp),
        ]
        .iter()
        .all(|(p, q)| (p - q).abs() <= tol * scale)
    }

    #[test]
    fn closed_forms_agree_with_fine_quadrature() {
        // m from the switch up to 0.97, where 20 000 trapezoid points still
        // converge; both signs of x - x0, inner and outer targets.
        for &(xh, s, s0) in &[
            (0.3, 1.0, 0.8),
            (-0.3, 0.8, 1.0),
            (0.1, 1.0, 1.05),
            (-0.05, 2.0, 1.9),
            (0.6, 1.0, 1.0),
            (0.0, 1.0, 0.6),
        ] {
            let m = 4.0 * s * s0 / (xh * xh + (s + s0) * (s + s0));
            assert!(m >= M_SWITCH, "{m}");
            let e = ring_elliptic(xh, s, s0);
            let t = ring_trapezoid(xh, s, s0, 20_000);
            assert!(close(&e, &t, 1e-9), "m {m}: {e:?} vs {t:?}");
        }
    }

    #[test]
    fn branches_agree_at_the_switch() {
        // Choose x - x0 so that m is exactly at the switch.
        for &(s, s0) in &[(1.0, 1.0), (1.0, 0.3), (0.5, 1.5)] {
            let xh = (4.0 * s * s0 / M_SWITCH - (s + s0) * (s + s0)).sqrt();
            let e = ring_elliptic(xh, s, s0);
            let t = ring_trapezoid(xh, s, s0, TRAPEZOID_POINTS);
            assert!(close(&e, &t, 1e-12), "{e:?} vs {t:?}");
        }
    }

    #[test]
    fn the_coarse_far_rule_is_converged() {
        // Just below m = 0.1, where `ring` switches to 12 points.
        for &(s, s0) in &[(1.0_f64, 1.0_f64), (0.2, 2.0)] {
            let xh = (4.0 * s * s0 / 0.0999 - (s + s0) * (s + s0)).sqrt();
            let coarse = ring(xh, s, 0.0, s0);
            let fine = ring_trapezoid(xh, s, s0, 2000);
            assert!(close(&coarse, &fine, 1e-13), "{coarse:?} vs {fine:?}");
        }
    }

    #[test]
    fn reciprocity() {
        // M_ab(x; x0) / s0 = M_ba(x0; x) / s: the Stokeslet is symmetric.
        for &(xh, s, s0) in &[(0.3, 1.0, 0.8), (2.0, 0.5, 1.5), (0.01, 1.0, 1.001)] {
            let a = ring(xh, s, 0.0, s0);
            let b = ring(0.0, s0, xh, s);
            let tol = 1e-11 * (a.xx.abs() / s0);
            assert!((a.xx / s0 - b.xx / s).abs() < tol);
            assert!((a.xs / s0 - b.sx / s).abs() < tol, "{a:?} {b:?}");
            assert!((a.sx / s0 - b.xs / s).abs() < tol);
            assert!((a.ss / s0 - b.ss / s).abs() < tol);
            assert!((a.pp / s0 - b.pp / s).abs() < tol);
        }
    }

    #[test]
    fn far_field_is_a_point_stokeslet() {
        // A ring seen from far away is a point force 2 pi s0 f: u_x = 2 * 2 pi s0 / r on the axis line.
        let r = 1e3;
        let k = ring(r, 1e-3, 0.0, 1.0);
        let point = 2.0 * 2.0 * PI / r;
        assert!((k.xx / point - 1.0).abs() < 1e-5, "{}", k.xx / point);
    }

    #[test]
    fn logarithmic_singularity_of_the_axial_kernel() {
        // M_xx ~ -2 ln d per unit length near the ring (line force on a
        // locally straight ring: 2 (-ln d) from the 1/r part, x2/d2 bounded).
        let (a, b) = (
            ring(0.0, 1.0 + 1e-6, 0.0, 1.0),
            ring(0.0, 1.0 + 1e-7, 0.0, 1.0),
        );
        let slope = (b.xx - a.xx) / (10f64).ln();
        assert!((slope - 2.0).abs() < 1e-4, "{slope}");
    }
}
