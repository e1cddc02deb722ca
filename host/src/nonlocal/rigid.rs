//! Rigid-body motions of collocation points and the generalized load
//! (force, torque about the origin) of a set of point forces.
//!
//! Convention shared with the RFT model: `V = [U; Omega]`, the load on the
//! object is `F = -B V`, so `B V` is the force and torque the object exerts
//! on the fluid.

use super::stokeslet::skew;
use nalgebra::{DMatrix, Matrix6, Vector3};

/// Right-hand sides for the six unit rigid motions: `3N x 6`, column `k` is
/// the velocity `U + Omega x p` of every point for `V = e_k`.
/// `moving[i] = false` pins point `i` (a wall) at zero velocity.
pub fn unit_motions(points: &[Vector3<f64>], moving: &[bool]) -> DMatrix<f64> {
    let mut rhs = DMatrix::zeros(3 * points.len(), 6);
    for (i, (p, &m)) in points.iter().zip(moving).enumerate() {
        if !m {
            continue;
        }
        for a in 0..3 {
            rhs[(3 * i + a, a)] = 1.0;
        }
        // Omega x p = -skew(p) Omega
        let s = -skew(p);
        for a in 0..3 {
            for b in 0..3 {
                rhs[(3 * i + a, 3 + b)] = s[(a, b)];
            }
        }
    }
    rhs
}

/// `sum_j [F_j; c_j x F_j]` over the sources `j` in `range`, for each of the
/// solution columns: column `k` of the result is the load for the motion in
/// column `columns.start + k` of `forces`, i.e. a resistance block.
pub fn loads(
    forces: &DMatrix<f64>,
    centroids: &[Vector3<f64>],
    range: std::ops::Range<usize>,
    columns: std::ops::Range<usize>,
) -> Matrix6<f64> {
    let mut b = Matrix6::zeros();
    for (k, col) in columns.enumerate() {
        let mut f_tot = Vector3::zeros();
        let mut t_tot = Vector3::zeros();
        for j in range.clone() {
            let f = Vector3::new(
                forces[(3 * j, col)],
                forces[(3 * j + 1, col)],
                forces[(3 * j + 2, col)],
            );
            f_tot += f;
            t_tot += centroids[j].cross(&f);
        }
        for a in 0..3 {
            b[(a, k)] = f_tot[a];
            b[(3 + a, k)] = t_tot[a];
        }
    }
    b
}

/// Smallest eigenvalue of the symmetric part scaled to unit diagonal
/// (`D^-1/2 B_sym D^-1/2`, so force and torque units do not matter), and the
/// largest asymmetry `|B_ij - B_ji| / sqrt(B_ii B_jj)`: the two properties
/// every resistance matrix must have (positive dissipation, Lorentz
/// reciprocity).
pub fn spd_check(b: &Matrix6<f64>) -> (f64, f64) {
    let d = b.diagonal().map(|v| 1.0 / v.abs().sqrt());
    let scaled = Matrix6::from_fn(|i, j| b[(i, j)] * d[i] * d[j]);
    let sym = (scaled + scaled.transpose()) * 0.5;
    let min_eig = sym.symmetric_eigenvalues().min();
    let asym = (scaled - scaled.transpose()).abs().max();
    (min_eig, asym)
}
