//! Slender-body theory for a rigid filament of uniform radius: the
//! Keller-Rubinow / Johnson centre-line integral equation.
//!
//! With `f(s)` the force per length the filament exerts on the fluid and
//! `u(s)` the centre-line velocity (Johnson 1980, eq. 1 without the rotlet
//! and doublet corrections, which are `O(a^2)` for translation),
//!
//! ```text
//! 8 pi mu u(s) = [(I + t t) L(s) + (I - 3 t t)] f(s)
//!              + int_0^l { [I + R R / |R|^2] / |R| f(s') - (I + t t) f(s) / |s - s'| } ds'
//! L(s) = ln(4 s (l - s) / a^2)
//! ```
//!
//! (R. E. Johnson, "An improved slender-body theory for Stokes flow",
//! J. Fluid Mech. 99 (1980) 411-431; J. B. Keller & S. I. Rubinow, J. Fluid
//! Mech. 75 (1976) 705-714.) For a straight rod this reproduces Cox's (1970)
//! and Batchelor's (1970) drags `2 pi mu l / (ln(l/a) - 0.807)` and
//! `4 pi mu l / (ln(l/a) + 0.193)` to their order; tested in `tests/nonlocal.rs`.
//!
//! Discretisation: piecewise-constant `f` on `n` equal segments, collocation
//! at segment midpoints; the regular part of the integral by adaptive
//! Gauss-Legendre quadrature over the true curved segment, the subtracted
//! `1 / |s - s'|` part and the segment average of `L(s)` analytically, so the
//! log singularity at the ends is integrable. The rotation of the wire about
//! its own tangent adds the local rotlet torque `4 pi mu a^2 (t . Omega) t` per
//! length (Johnson 1980, the twist term), if enabled.

use super::curve::{Centreline, Segments};
use super::linalg;
use super::rigid;
use super::stokeslet::stokeslet;
use super::NonlocalError;
use nalgebra::{Matrix3, Matrix6, Vector3};
use std::f64::consts::PI;

/// Shortest segment, in wire radii, that SBT is used with. The
/// Keller-Rubinow operator is not positive for force modes shorter than a
/// few radii (Goetz 2000; Tornberg & Shelley, J. Comput. Phys. 196 (2004)
/// 8-40), and collocation on finer segments excites them: measured here,
/// `h = 1.25 a` on a rod and `h = 1.8 a` on tail #1 give errors of 20 % and
/// 5 %, while every `h >= 2.5 a` tried is stable. [`super::tail_resistance`]
/// caps the segment count accordingly.
pub const MIN_SEGMENT_OVER_RADIUS: f64 = 3.0;

/// Full 6x6 resistance of a rigid filament by slender-body theory.
pub fn resistance(
    curve: Centreline,
    wire_radius_m: f64,
    viscosity_pa_s: f64,
    n_segments: usize,
    wire_spin: bool,
) -> Result<Matrix6<f64>, NonlocalError> {
    let seg = Segments::new(curve, n_segments);
    let (len, a) = (curve.length_m(), wire_radius_m);
    let c = 1.0 / (8.0 * PI * viscosity_pa_s);
    // segment average of ln s over [s0, s1]
    let avg_ln = |s0: f64, s1: f64| {
        let f = |s: f64| if s > 0.0 { s * s.ln() - s } else { 0.0 };
        (f(s1) - f(s0)) / (s1 - s0)
    };
    linalg::check_memory(seg.n)?;
    let matrix = linalg::assemble(seg.n, |i, j| {
        let xi = seg.mid_point_m[i];
        if i == j {
            let t = seg.mid_tangent[i];
            let tt = t * t.transpose();
            let (s0, s1, h) = (seg.edges_s_m[i], seg.edges_s_m[i + 1], seg.h_m[i]);
            let l_avg = (4.0 / (a * a)).ln() + avg_ln(s0, s1) + avg_ln(len - s1, len - s0);
            let si = seg.mid_s_m[i];
            let outside = (2.0 * si / h).ln() + (2.0 * (len - si) / h).ln();
            let id = Matrix3::identity();
            ((id + tt) * (l_avg - outside) + (id - tt * 3.0)) * (c / h)
        } else {
            let mut blk = Matrix3::zeros();
            for (y, w) in seg.quadrature_for(&xi, j, 0.0) {
                blk += stokeslet(&(xi - y), viscosity_pa_s) * w;
            }
            blk / seg.h_m[j]
        }
    });
    let moving = vec![true; seg.n];
    let rhs = rigid::unit_motions(&seg.mid_point_m, &moving);
    let forces = linalg::solve(matrix, &rhs)?;
    let centroids = segment_centroids(&seg);
    let mut b = rigid::loads(&forces, &centroids, 0..seg.n, 0..6);
    if wire_spin {
        add_wire_spin(&mut b, &seg, wire_radius_m, viscosity_pa_s);
    }
    Ok(b)
}

/// Arc-length centroid of each curved segment: the lever arm of its force.
pub fn segment_centroids(seg: &Segments) -> Vec<Vector3<f64>> {
    (0..seg.n)
        .map(|j| {
            seg.quadrature(j, 4)
                .into_iter()
                .fold(Vector3::zeros(), |acc, (p, w)| acc + p * w)
                / seg.h_m[j]
        })
        .collect()
}

/// Local torque of a wire spinning about its own centre-line,
/// `4 pi mu a^2 (t . Omega) t` per length (exact for an infinite cylinder):
/// the only resistance a line of Stokeslets misses at order `a^2`.
pub fn add_wire_spin(
    b: &mut Matrix6<f64>,
    seg: &Segments,
    wire_radius_m: f64,
    viscosity_pa_s: f64,
) {
    let k = 4.0 * PI * viscosity_pa_s * wire_radius_m * wire_radius_m;
    for (t, h) in seg.mid_tangent.iter().zip(&seg.h_m) {
        let tt = t * t.transpose() * (k * h);
        for r in 0..3 {
            for c in 0..3 {
                b[(3 + r, 3 + c)] += tt[(r, c)];
            }
        }
    }
}
