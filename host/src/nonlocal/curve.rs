//! A slender filament's centre-line cut into equal arc-length segments.

use crate::physics::geometry::Helix;
use nalgebra::Vector3;

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
                start_m, direction, ..
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

/// Arc-length segments of a centre-line: uniform, optionally with the two
/// end segments split geometrically down to `end_min_m` (the force density
/// of a regularized line peaks within a blob size of the tips, and resolving
/// that peak is what makes the end correction converge).
#[derive(Debug, Clone)]
pub struct Segments {
    pub curve: Centreline,
    pub n: usize,
    pub edges_s_m: Vec<f64>,
    pub h_m: Vec<f64>,
    pub mid_s_m: Vec<f64>,
    pub mid_point_m: Vec<Vector3<f64>>,
    pub mid_tangent: Vec<Vector3<f64>>,
}

impl Segments {
    /// `n_uniform` equal segments.
    pub fn new(curve: Centreline, n_uniform: usize) -> Self {
        Self::graded(curve, n_uniform, f64::INFINITY)
    }

    /// `n_uniform` equal segments with the end ones halved repeatedly until
    /// the first is no longer than `end_min_m`.
    pub fn graded(curve: Centreline, n_uniform: usize, end_min_m: f64) -> Self {
        let len = curve.length_m();
        let h0 = len / n_uniform as f64;
        let mut end = vec![h0];
        while end[0] > end_min_m && end.len() < 40 && n_uniform >= 2 {
            let first = end[0] * 0.5;
            end[0] = first;
            end.insert(0, first);
        }
        // end = [tiny, ..., h0/2]: sizes from the tip inwards, summing to h0
        let mut sizes: Vec<f64> = end.clone();
        if n_uniform >= 2 {
            sizes.extend(std::iter::repeat_n(h0, n_uniform - 2));
            sizes.extend(end.iter().rev());
        }
        let mut edges_s_m = vec![0.0];
        for h in &sizes {
            edges_s_m.push(edges_s_m.last().unwrap() + h);
        }
        *edges_s_m.last_mut().unwrap() = len;
        let n = sizes.len();
        let h_m: Vec<f64> = (0..n).map(|i| edges_s_m[i + 1] - edges_s_m[i]).collect();
        let mid_s_m: Vec<f64> = (0..n)
            .map(|i| 0.5 * (edges_s_m[i] + edges_s_m[i + 1]))
            .collect();
        let mid_point_m = mid_s_m.iter().map(|&s| curve.point(s)).collect();
        let mid_tangent = mid_s_m.iter().map(|&s| curve.tangent(s)).collect();
        Segments {
            curve,
            n,
            edges_s_m,
            h_m,
            mid_s_m,
            mid_point_m,
            mid_tangent,
        }
    }

    /// Quadrature over segment `j` with `m` Gauss points: `(point, arc weight)`.
    pub fn quadrature(&self, j: usize, m: usize) -> Vec<(Vector3<f64>, f64)> {
        let mut out = Vec::with_capacity(m);
        self.push_gauss(&mut out, self.edges_s_m[j], self.edges_s_m[j + 1], m);
        out
    }

    fn push_gauss(&self, out: &mut Vec<(Vector3<f64>, f64)>, s0: f64, s1: f64, m: usize) {
        let (nodes, weights) = super::gauss_legendre::symmetric(m);
        let half = 0.5 * (s1 - s0);
        for (&x, &w) in nodes.iter().zip(weights) {
            out.push((self.curve.point(s0 + half * (1.0 + x)), w * half));
        }
    }

    /// Quadrature of segment `j` accurate for a kernel seen from `target`
    /// that varies on the length scale `max(distance, smoothing)`: plain
    /// Gauss when the segment is far, otherwise composite Gauss on pieces
    /// growing geometrically away from the point nearest to the target.
    pub fn quadrature_for(
        &self,
        target: &Vector3<f64>,
        j: usize,
        smoothing_m: f64,
    ) -> Vec<(Vector3<f64>, f64)> {
        let (s0, s1) = (self.edges_s_m[j], self.edges_s_m[j + 1]);
        let h = s1 - s0;
        let d = ((target - self.mid_point_m[j]).norm() - 0.5 * h).max(0.0);
        let scale = d.max(smoothing_m).max(1e-9 * h);
        if scale >= 0.5 * h {
            let m = ((3.0 * h / scale).ceil() as usize + 1).clamp(2, 8);
            return self.quadrature(j, m);
        }
        // nearest point on the chord
        let (p0, p1) = (self.curve.point(s0), self.curve.point(s1));
        let chord = p1 - p0;
        let u = ((target - p0).dot(&chord) / chord.norm_squared()).clamp(0.0, 1.0);
        let sc = s0 + u * h;
        let mut out = Vec::new();
        for (lo, hi, dir) in [(sc, s1, 1.0), (s0, sc, -1.0)] {
            let total = hi - lo;
            let mut done = 0.0;
            let mut piece = scale;
            while done < total {
                let step = piece.min(total - done);
                let (a, b) = if dir > 0.0 {
                    (lo + done, lo + done + step)
                } else {
                    (hi - done - step, hi - done)
                };
                self.push_gauss(&mut out, a, b, 6);
                done += step;
                piece *= 2.0;
            }
        }
        out
    }
}
