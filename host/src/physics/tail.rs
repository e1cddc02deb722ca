//! The rigid helical tail's 6x6 resistance matrix, paper eq. 3:
//!
//! ```text
//! B_t = ∫ [ K      -K S   ] ds,    K = R C R^T = c_n I + (c_t - c_n) t t^T,   S = skew(P)
//!         [ S K    -S K S ]
//! ```
//!
//! (`C = diag(c_t, c_n, c_b)` in the Frenet frame with `c_b = c_n`, so the
//! rotation `R` collapses to the tangent `t`.) Three evaluations:
//!
//! * [`axial_closed_form`]: the three entries the paper's x-only runs need,
//!   by hand. Along a uniform helix they are constant per unit arc length
//!   (pitch angle `psi`, `tan psi = k B`):
//!   drag `c_n sin²psi + c_t cos²psi`, coupling `chi (c_t - c_n) B sin psi cos psi`,
//!   torque `B² (c_n cos²psi + c_t sin²psi)`: the classical results
//!   (Lighthill 1976; Purcell 1997).
//! * [`matrix_exact`]: all 36 entries exactly. Every entry of the integrand
//!   lies in the span of `xi^p e^{i m theta}` with `p <= 2`, `|m| <= 4`
//!   (`P_x` is linear in `xi`, `P_y`, `P_z`, `t` are first-degree
//!   trigonometric in `theta = k xi + phi`, and `S K S` multiplies four of
//!   them). Sampling the integrand on 3 `xi` x 9 `theta` nodes therefore
//!   determines those coefficients exactly (Lagrange in `xi`, discrete
//!   Fourier in `theta`), and each basis function integrates in closed form
//!   over `[0, L_t]`: exact for any number of turns and any phase.
//! * [`matrix_quadrature`]: the paper's procedure, the composite trapezoidal
//!   rule on nodes spaced `lambda / n` (100 per wavelength in the paper);
//!   second-order accurate because the integrand is not periodic over a
//!   non-integer number of turns.

use super::coefficients::LocalDrag;
use super::geometry::Helix;
use nalgebra::{Complex, Matrix3, Matrix6, Vector3};
use std::f64::consts::PI;

/// The x-translation / x-rotation block of the tail matrix (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxialResistance {
    /// `B_t(1,1)`: axial drag (N s / m).
    pub drag_n_s_per_m: f64,
    /// `B_t(1,4)`: axial force per unit rotation rate (N s); negative for a
    /// right-handed helix, which is what pushes it along +x.
    pub thrust_n_s: f64,
    /// `B_t(4,4)`: axial torque per unit rotation rate (N m s).
    pub torque_n_m_s: f64,
}

/// The paper's quadrature resolution: nodes per wavelength.
pub const PAPER_NODES_PER_WAVELENGTH: usize = 100;

/// Closed-form axial entries of eq. 3 (see the module docs).
pub fn axial_closed_form(helix: &Helix, drag: LocalDrag) -> AxialResistance {
    let psi = helix.pitch_angle_rad();
    let (s, c) = psi.sin_cos();
    let (ct, cn) = (drag.tangential, drag.normal);
    let b = helix.amplitude_m;
    let l = helix.arc_length_m();
    let chi = helix.handedness.sign();
    AxialResistance {
        drag_n_s_per_m: l * (cn * s * s + ct * c * c),
        thrust_n_s: l * chi * (ct - cn) * b * s * c,
        torque_n_m_s: l * b * b * (cn * c * c + ct * s * s),
    }
}

/// Weighted sums over centre-line nodes from which eq. 3's integrand is
/// assembled. With `K = c_n I + Delta t t^T` (`Delta = c_t - c_n`) and
/// `u = P x t = S t`, the four blocks are
/// `K`, `-K S = -c_n S + Delta t u^T`, `S K = c_n S + Delta u t^T` and
/// `-S K S = c_n (|P|² I - P P^T) + Delta u u^T`, so summing `t t^T`,
/// `t u^T`, `u u^T`, `P`, `P P^T` and `|P|²` over the nodes and assembling
/// once costs a few dozen flops per node instead of three 3x3 products.
#[derive(Default)]
struct NodeSums {
    weight: f64,
    tt: Matrix3<f64>,
    tu: Matrix3<f64>,
    uu: Matrix3<f64>,
    p: Vector3<f64>,
    pp: Matrix3<f64>,
    p2: f64,
}

impl NodeSums {
    fn add(&mut self, w: f64, p: Vector3<f64>, t: Vector3<f64>) {
        let u = p.cross(&t);
        self.weight += w;
        self.tt += (t * w) * t.transpose();
        self.tu += (t * w) * u.transpose();
        self.uu += (u * w) * u.transpose();
        self.p += p * w;
        self.pp += (p * w) * p.transpose();
        self.p2 += w * p.norm_squared();
    }

    fn assemble(&self, drag: LocalDrag) -> Matrix6<f64> {
        let (cn, d) = (drag.normal, drag.tangential - drag.normal);
        let s = skew(&self.p);
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(Matrix3::identity() * (cn * self.weight) + self.tt * d));
        m.fixed_view_mut::<3, 3>(0, 3)
            .copy_from(&(-s * cn + self.tu * d));
        m.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(s * cn + self.tu.transpose() * d));
        m.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&((Matrix3::identity() * self.p2 - self.pp) * cn + self.uu * d));
        m
    }
}

/// Centre-line point and unit tangent at axial coordinate `xi`, with the
/// helix angle given through its sine and cosine.
fn node(helix: &Helix, xi: f64, sin_theta: f64, cos_theta: f64) -> (Vector3<f64>, Vector3<f64>) {
    let chi = helix.handedness.sign();
    let b = helix.amplitude_m;
    let g = helix.arc_per_axial();
    let kb = helix.wavenumber() * b;
    let p = Vector3::new(helix.joint_x_m - xi, b * cos_theta, -chi * b * sin_theta);
    let t = Vector3::new(-1.0, -kb * sin_theta, -chi * kb * cos_theta) / g;
    (p, t)
}

/// The integrand of eq. 3 per unit axial length at axial coordinate `xi`
/// and helix angle `theta` (kept independent so that [`matrix_exact`] can
/// sample the two dependences separately).
fn integrand(helix: &Helix, drag: LocalDrag, xi: f64, theta: f64) -> Matrix6<f64> {
    let (s, c) = theta.sin_cos();
    let (p, t) = node(helix, xi, s, c);
    let mut sums = NodeSums::default();
    sums.add(helix.arc_per_axial(), p, t);
    sums.assemble(drag)
}

/// The cross-product matrix: `skew(p) v = p x v`.
pub fn skew(p: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -p.z, p.y, p.z, 0.0, -p.x, -p.y, p.x, 0.0)
}

const XI_NODES: usize = 3;
const THETA_NODES: usize = 9;
const MAX_HARMONIC: usize = 4;

/// Exact eq. 3 for a uniform helix (see the module docs for the method).
pub fn matrix_exact(helix: &Helix, drag: LocalDrag) -> Matrix6<f64> {
    let len = helix.axial_length_m;
    let xi_nodes = [0.0, 0.5 * len, len];
    // Fourier coefficients c_m(xi_i) of every entry, m = 0..=4.
    let mut coef = [[Matrix6::<Complex<f64>>::zeros(); MAX_HARMONIC + 1]; XI_NODES];
    for (i, &xi) in xi_nodes.iter().enumerate() {
        for j in 0..THETA_NODES {
            let theta = 2.0 * PI * j as f64 / THETA_NODES as f64;
            let f = integrand(helix, drag, xi, theta);
            for (m, c) in coef[i].iter_mut().enumerate() {
                let w = Complex::from_polar(1.0 / THETA_NODES as f64, -(m as f64) * theta);
                *c += f.map(|v| w * v);
            }
        }
    }
    let k = helix.wavenumber();
    let h = 0.5 * len;
    let mut out = Matrix6::zeros();
    let [at_start, at_middle, at_end] = &coef;
    let harmonics = at_start.iter().zip(at_middle).zip(at_end).enumerate();
    for (m, ((n0, n1), n2)) in harmonics {
        let phase = Complex::from_polar(1.0, m as f64 * helix.phase_rad);
        let j = moments(m as f64 * k, len);
        let weight = if m == 0 { 1.0 } else { 2.0 };
        for idx in 0..36 {
            // Quadratic in xi through the three nodes: c(xi) = c0 + a1 xi + a2 xi^2.
            let (c0, c1, c2) = (n0[idx], n1[idx], n2[idx]);
            let a1 = (c1 * 4.0 - c0 * 3.0 - c2) / (2.0 * h);
            let a2 = (c2 - c1 * 2.0 + c0) / (2.0 * h * h);
            out[idx] += weight * ((c0 * j[0] + a1 * j[1] + a2 * j[2]) * phase).re;
        }
    }
    symmetrised(out)
}

/// `J_p = ∫_0^L xi^p e^{i a xi} dxi` for p = 0, 1, 2, in closed form.
fn moments(a: f64, len: f64) -> [Complex<f64>; 3] {
    let x = a * len;
    if x.abs() < 0.5 {
        // Power series: the closed form cancels catastrophically as a L -> 0.
        let mut j = [Complex::new(0.0, 0.0); 3];
        let mut term = Complex::new(1.0, 0.0); // (i a)^n / n!
        for n in 0..30 {
            for (p, jp) in j.iter_mut().enumerate() {
                *jp += term * len.powi((n + p + 1) as i32) / (n + p + 1) as f64;
            }
            term = term * Complex::new(0.0, a) / (n + 1) as f64;
        }
        return j;
    }
    let ia = Complex::new(0.0, a);
    let e = Complex::from_polar(1.0, x);
    let j0 = (e - 1.0) / ia;
    let j1 = (e * len - j0) / ia;
    let j2 = (e * (len * len) - j1 * 2.0) / ia;
    [j0, j1, j2]
}

/// Composite trapezoidal rule for eq. 3 on nodes spaced at most
/// `lambda / nodes_per_wavelength` (the paper: 100 per wavelength).
pub fn matrix_quadrature(
    helix: &Helix,
    drag: LocalDrag,
    nodes_per_wavelength: usize,
) -> Matrix6<f64> {
    let n = quadrature_nodes(helix, nodes_per_wavelength);
    let h = helix.axial_length_m / (n - 1) as f64;
    let g = helix.arc_per_axial();
    // The helix angle advances by k h per node: rotate (sin, cos) by that
    // step instead of calling sin_cos per node (the dominant cost); the
    // recurrence's drift over 10^4 nodes is ~1e-12, far below h².
    let (step_s, step_c) = (helix.wavenumber() * h).sin_cos();
    let (mut s, mut c) = helix.phase_rad.sin_cos();
    let mut sums = NodeSums::default();
    for i in 0..n {
        let w = if i == 0 || i == n - 1 { 0.5 } else { 1.0 };
        let (p, t) = node(helix, i as f64 * h, s, c);
        sums.add(w * g * h, p, t);
        (s, c) = (s * step_c + c * step_s, c * step_c - s * step_s);
    }
    symmetrised(sums.assemble(drag))
}

/// Number of quadrature nodes: `ceil(N_lambda * nodes_per_wavelength)`, at
/// least 2 (839 for the paper's tail #1).
pub fn quadrature_nodes(helix: &Helix, nodes_per_wavelength: usize) -> usize {
    let n = (helix.n_waves() * nodes_per_wavelength.max(1) as f64).ceil();
    (n as usize).max(2)
}

/// Eq. 3 is symmetric by construction (reciprocal theorem); averaging with
/// the transpose removes round-off asymmetry so Cholesky-based checks and
/// solvers see an exactly symmetric matrix.
fn symmetrised(m: Matrix6<f64>) -> Matrix6<f64> {
    (m + m.transpose()) * 0.5
}
