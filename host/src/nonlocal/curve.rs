//! A slender filament's centre-line cut into equal arc-length segments, and
//! the Gauss-Legendre quadrature used to integrate kernels over a segment.

use crate::physics::geometry::Helix;
use nalgebra::Vector3;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// The centre-line shapes the non-local models handle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Centreline {
    Helix(Helix),
    /// A straight rod from `start_m` along the unit vector `direction`.
    Rod {
        start_m: [f64; 3],
        direction: [f64; 3],
        length_m: f64,
    },
}

impl Centreline {
    pub fn length_m(&self) -> f64 {
        match self {
            Centreline::Helix(h) => h.arc_length_m(),
            Centreline::Rod { length_m, .. } => *length_m,
        }
    }

    /// Point at arc length `s` from the first end.
    pub fn point(&self, s_m: f64) -> Vector3<f64> {
        match self {
            Centreline::Helix(h) => Vector3::from(h.point(s_m / h.arc_per_axial())),
            Centreline::Rod {
                start_m,
                direction,
                ..
            } => Vector3::from(*start_m) + Vector3::from(*direction) * s_m,
        }
    }

    /// Unit tangent at arc length `s`.
    pub fn tangent(&self, s_m: f64) -> Vector3<f64> {
        match self {
            Centreline::Helix(h) => Vector3::from(h.tangent(s_m / h.arc_per_axial())),
            Centreline::Rod { direction, .. } => Vector3::from(*direction).normalize(),
        }
    }
}

/// `n` equal arc-length segments of a centre-line, with their midpoints.
#[derive(Debug, Clone)]
pub struct Segments {
    pub curve: Centreline,
    pub n: usize,
    /// Arc length of one segment (m).
    pub h_m: f64,
    pub mid_s_m: Vec<f64>,
    pub mid_point_m: Vec<Vector3<f64>>,
    pub mid_tangent: Vec<Vector3<f64>>,
}

impl Segments {
    pub fn new(curve: Centreline, n: usize) -> Self {
        let len = curve.length_m();
        let h = len / n as f64;
        let mid_s_m: Vec<f64> = (0..n).map(|i| (i as f64 + 0.5) * h).collect();
        let mid_point_m = mid_s_m.iter().map(|&s| curve.point(s)).collect();
        let mid_tangent = mid_s_m.iter().map(|&s| curve.tangent(s)).collect();
        Segments {
            curve,
            n,
            h_m: h,
            mid_s_m,
            mid_point_m,
            mid_tangent,
        }
    }

    /// Quadrature over segment `j` with `m` Gauss points: `(point, arc weight)`.
    pub fn quadrature(&self, j: usize, m: usize) -> impl Iterator<Item = (Vector3<f64>, f64)> + '_ {
        let (nodes, weights) = gauss_legendre(m);
        let s0 = j as f64 * self.h_m;
        let half = 0.5 * self.h_m;
        nodes.iter().zip(weights.iter()).map(move |(&x, &w)| {
            let s = s0 + half * (1.0 + x);
            (self.curve.point(s), w * half)
        })
    }

    /// Gauss points needed on segment `j` for a kernel that varies on the
    /// length scale `max(distance from target, smoothing)`: about three points
    /// per such length, two at least, 64 at most.
    pub fn points_needed(&self, target: &Vector3<f64>, j: usize, smoothing_m: f64) -> usize {
        let d = ((target - self.mid_point_m[j]).norm() - 0.5 * self.h_m).max(0.0);
        let scale = d.max(smoothing_m);
        ((3.0 * self.h_m / scale).ceil() as usize + 1).clamp(2, MAX_GAUSS)
    }
}

const MAX_GAUSS: usize = 64;

/// Gauss-Legendre nodes and weights on `[-1, 1]` for `m` in `1..=64`
/// (Newton iteration on the Legendre recurrence, computed once).
pub fn gauss_legendre(m: usize) -> (&'static [f64], &'static [f64]) {
    static TABLE: OnceLock<Vec<(Vec<f64>, Vec<f64>)>> = OnceLock::new();
    let table = TABLE.get_or_init(|| (0..=MAX_GAUSS).map(gauss_legendre_compute).collect());
    let (x, w) = &table[m.clamp(1, MAX_GAUSS)];
    (x, w)
}

fn gauss_legendre_compute(m: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; m];
    let mut w = vec![0.0; m];
    for i in 0..m {
        let mut z = (PI * (i as f64 + 0.75) / (m as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, z);
            for k in 2..=m {
                let p2 = ((2 * k - 1) as f64 * z * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let p = if m == 0 { 1.0 } else { p1 };
            dp = m as f64 * (z * p - p0) / (z * z - 1.0);
            let dz = p / dp;
            z -= dz;
            if dz.abs() < 1e-15 {
                break;
            }
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
    (x, w)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        for m in [1usize, 2, 5, 12, 40] {
            let (x, w) = gauss_legendre(m);
            for deg in 0..(2 * m) {
                let num: f64 = x.iter().zip(w).map(|(x, w)| w * x.powi(deg as i32)).sum();
                let exact = if deg % 2 == 1 { 0.0 } else { 2.0 / (deg as f64 + 1.0) };
                assert!((num - exact).abs() < 1e-12, "m={m} deg={deg}: {num} vs {exact}");
            }
        }
    }
}
