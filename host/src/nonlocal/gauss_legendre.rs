//! Gauss-Legendre quadrature: the `m` nodes and weights that integrate
//! polynomials of degree `2m - 1` exactly, on `[-1, 1]` and on `[0, 1]`.
//!
//! Nodes by Newton's method on the three-term Legendre recurrence from
//! Tricomi's initial guess `cos(pi (i + 3/4) / (m + 1/2))`, weights
//! `2 / ((1 - x²) P'_m(x)²)`; computed once per order and cached, since
//! the kernels ask for the same few orders millions of times.
//!
//! Written here rather than taken from a crate: the rule is twenty lines,
//! and the quadrature crates either fix the order at compile time or
//! allocate per call.
//!
//! References: G. H. Golub & J. H. Welsch, Math. Comp. 23 (1969) 221;
//! W. H. Press et al., Numerical Recipes, 3rd ed. (2007) §4.6.

use std::f64::consts::PI;
use std::sync::OnceLock;

/// The highest order cached.
pub const MAX_ORDER: usize = 64;

/// Nodes and weights on `[-1, 1]` for `m` in `1..=MAX_ORDER` (clamped).
pub fn symmetric(m: usize) -> (&'static [f64], &'static [f64]) {
    static TABLE: OnceLock<Vec<(Vec<f64>, Vec<f64>)>> = OnceLock::new();
    let table = TABLE.get_or_init(|| (0..=MAX_ORDER).map(compute).collect());
    let (x, w) = &table[m.clamp(1, MAX_ORDER)];
    (x, w)
}

/// `(node, weight)` pairs on `[0, 1]` (weights sum to 1), nodes ascending.
pub fn unit_interval(m: usize) -> Vec<(f64, f64)> {
    let (x, w) = symmetric(m);
    x.iter()
        .zip(w)
        .map(|(x, w)| (0.5 * (1.0 - x), 0.5 * w))
        .collect()
}

fn compute(m: usize) -> (Vec<f64>, Vec<f64>) {
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
            dp = m as f64 * (z * p1 - p0) / (z * z - 1.0);
            let dz = p1 / dp;
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
    fn integrates_polynomials_of_degree_two_m_minus_one_exactly() {
        for m in [1usize, 2, 5, 12, 40] {
            let (x, w) = symmetric(m);
            for deg in 0..(2 * m) {
                let num: f64 = x.iter().zip(w).map(|(x, w)| w * x.powi(deg as i32)).sum();
                let exact = if deg % 2 == 1 {
                    0.0
                } else {
                    2.0 / (deg as f64 + 1.0)
                };
                assert!(
                    (num - exact).abs() < 1e-12,
                    "m={m} deg={deg}: {num} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn on_the_unit_interval_too() {
        for n in [4, 8, 12] {
            let r = unit_interval(n);
            assert!(r.windows(2).all(|p| p[0].0 < p[1].0), "ascending");
            for p in 0..2 * n {
                let q: f64 = r.iter().map(|(x, w)| w * x.powi(p as i32)).sum();
                assert!((q - 1.0 / (p as f64 + 1.0)).abs() < 1e-14, "n {n} p {p}");
            }
        }
    }
}
