//! Method of regularized Stokeslets on a filament centre-line, with the
//! force density piecewise constant on segments ("regularized Stokeslet
//! segments", integrated by adaptive Gauss quadrature rather than in closed
//! form).
//!
//! Blob size. For the Cortez et al. (2005) blob, a uniform line density `f`
//! of regularized Stokeslets along a straight stretch of length `l` moves its
//! own centre-line at
//!
//! ```text
//! 8 pi mu u = [2 ln(l/eps) + 2] f_n + [4 ln(l/eps)] f_t        (l >> eps)
//! ```
//!
//! while slender-body theory for a cylinder of radius `a` gives
//! `[2 ln(l/a) + 1] f_n + [4 ln(l/a) - 2] f_t` (see `sbt.rs`). Both the
//! normal and the tangential terms match if and only if
//! `eps = a e^(1/2) ~ 1.65 a`, which is the default `blob_over_wire_radius`.
//! (Zhao & Koens, "Regularized Stokeslets lines suitable for slender bodies
//! in viscous flow", Fluids 6 (2021) 335, show that `eps` must be
//! proportional to `a` for the far field to be right; the constant above is
//! the one for this blob.) Common practice of `eps ~ a` (Cortez, Fauci &
//! Medovikov 2005; Rodenborn, Chen, Swinney, Liu & Zhang, PNAS 110 (2013)
//! E338) would make the wire effectively thicker by `ln(1.65)` in the
//! logarithm, i.e. a few percent more drag.
//!
//! Because the kernel is integrated over each segment with enough Gauss
//! points to resolve `eps` (`Segments::quadrature_for`), the segment length
//! is not tied to `eps`: the resolution only has to follow the force density.

use super::curve::{Centreline, Segments};
use super::linalg;
use super::rigid;
use super::sbt::{add_wire_spin, segment_centroids};
use super::stokeslet::add_regularized_stokeslet;
use super::NonlocalError;
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};
use std::f64::consts::PI;

/// `e^(1/2)`: the blob-to-wire-radius ratio that matches slender-body theory.
pub const MATCHED_BLOB_OVER_RADIUS: f64 = 1.648_721_270_700_128_2;

/// A discretised filament of regularized Stokeslet segments, usable on its
/// own or as one object among others (body, wall) in a grand system.
#[derive(Debug, Clone)]
pub struct LineSources {
    pub seg: Segments,
    pub blob_m: f64,
    pub centroids: Vec<Vector3<f64>>,
}

impl LineSources {
    /// `n_uniform` segments, the end ones graded down to half a blob.
    pub fn new(curve: Centreline, n_uniform: usize, blob_m: f64) -> Self {
        let seg = Segments::graded(curve, n_uniform, 0.5 * blob_m);
        let centroids = segment_centroids(&seg);
        LineSources {
            seg,
            blob_m,
            centroids,
        }
    }

    /// Velocity at `target` per unit total force on segment `j`.
    pub fn block(&self, target: &Vector3<f64>, j: usize, viscosity_pa_s: f64) -> Matrix3<f64> {
        let c = 1.0 / (8.0 * PI * viscosity_pa_s * self.seg.h_m[j]);
        let mut blk = Matrix3::zeros();
        for (y, w) in self.seg.quadrature_for(target, j, self.blob_m) {
            add_regularized_stokeslet(&mut blk, &(target - y), self.blob_m, w * c);
        }
        blk
    }
}

/// Full 6x6 resistance of a rigid filament in free space by regularized
/// Stokeslet segments.
pub fn resistance(
    curve: Centreline,
    wire_radius_m: f64,
    viscosity_pa_s: f64,
    n_segments: usize,
    blob_over_radius: f64,
    wire_spin: bool,
) -> Result<Matrix6<f64>, NonlocalError> {
    let src = LineSources::new(curve, n_segments, blob_over_radius * wire_radius_m);
    let pts = &src.seg.mid_point_m;
    linalg::check_memory(src.seg.n)?;
    let matrix: DMatrix<f64> =
        linalg::assemble(src.seg.n, |i, j| src.block(&pts[i], j, viscosity_pa_s));
    let rhs = rigid::unit_motions(pts, &vec![true; src.seg.n]);
    let forces = linalg::solve(matrix, &rhs)?;
    let mut b = rigid::loads(&forces, &src.centroids, 0..src.seg.n, 0..6);
    if wire_spin {
        add_wire_spin(&mut b, &src.seg, wire_radius_m, viscosity_pa_s);
    }
    Ok(b)
}
