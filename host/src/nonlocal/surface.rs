//! Point clouds of regularized Stokeslets on closed or open surfaces: the
//! body (prolate spheroid, or sphere), the channel wall (cylinder) and its
//! end caps. Points are laid on rings of roughly equal spacing `h`, with
//! the exact ring area shared among the ring's points as quadrature weight.
//!
//! The blob of a surface point is `eps = blob_over_spacing * h` with `h` the
//! square root of the mean area per point: the usual MRS choice of `eps`
//! comparable with the point spacing (Cortez, Fauci & Medovikov 2005, sec.
//! IV, sphere tests), so the discrete sum resolves the regularized kernel.

use nalgebra::Vector3;
use std::f64::consts::PI;

/// Points of one surface with their areas (m^2).
#[derive(Debug, Clone, Default)]
pub struct SurfacePoints {
    pub points_m: Vec<Vector3<f64>>,
    pub area_m2: Vec<f64>,
}

impl SurfacePoints {
    pub fn len(&self) -> usize {
        self.points_m.len()
    }

    pub fn is_empty(&self) -> bool {
        self.points_m.is_empty()
    }

    /// Square root of the mean area per point (m).
    pub fn spacing_m(&self) -> f64 {
        (self.area_m2.iter().sum::<f64>() / self.len().max(1) as f64).sqrt()
    }

    pub fn extend(&mut self, other: SurfacePoints) {
        self.points_m.extend(other.points_m);
        self.area_m2.extend(other.area_m2);
    }

    fn push_ring(&mut self, x: f64, r: f64, band_area: f64, h: f64, stagger: bool) {
        let n = ((2.0 * PI * r / h).round() as usize).max(1);
        let shift = if stagger { 0.5 } else { 0.0 };
        for k in 0..n {
            let phi = 2.0 * PI * (k as f64 + shift) / n as f64;
            let p = if n == 1 && r < 0.5 * h {
                Vector3::new(x, 0.0, 0.0)
            } else {
                Vector3::new(x, r * phi.cos(), r * phi.sin())
            };
            self.points_m.push(p);
            self.area_m2.push(band_area / n as f64);
        }
    }
}

/// Prolate (or oblate) spheroid about the x axis centred at `centre_x_m`:
/// half-length `c`, radius `b`, about `h` apart. A sphere is `c = b`.
pub fn spheroid(
    centre_x_m: f64,
    half_length_m: f64,
    radius_m: f64,
    spacing_m: f64,
) -> SurfacePoints {
    let (c, b) = (half_length_m, radius_m);
    // meridian length by midpoint rule, to pick the number of bands
    let meridian: f64 = (0..2000)
        .map(|i| {
            let th = PI * (i as f64 + 0.5) / 2000.0;
            (c * c * th.sin().powi(2) + b * b * th.cos().powi(2)).sqrt() * PI / 2000.0
        })
        .sum();
    let n_bands = ((meridian / spacing_m).round() as usize).max(2);
    let mut out = SurfacePoints::default();
    for i in 0..n_bands {
        let (t0, t1) = (
            PI * i as f64 / n_bands as f64,
            PI * (i + 1) as f64 / n_bands as f64,
        );
        // band area: int 2 pi b sin(t) sqrt(c^2 sin^2 t + b^2 cos^2 t) dt, 8-point Gauss
        let (nodes, w) = super::gauss_legendre::symmetric(8);
        let area: f64 = nodes
            .iter()
            .zip(w)
            .map(|(&x, &w)| {
                let t = 0.5 * (t0 + t1) + 0.5 * (t1 - t0) * x;
                let ds = (c * c * t.sin().powi(2) + b * b * t.cos().powi(2)).sqrt();
                w * 0.5 * (t1 - t0) * 2.0 * PI * b * t.sin() * ds
            })
            .sum();
        let t = 0.5 * (t0 + t1);
        out.push_ring(
            centre_x_m + c * t.cos(),
            b * t.sin(),
            area,
            spacing_m,
            i % 2 == 1,
        );
    }
    out
}

/// Cylinder wall of radius `r` from `x0` to `x1`, with flat end caps if
/// `capped` (a closed container: no net flux through any cross-section).
pub fn tube(radius_m: f64, x0_m: f64, x1_m: f64, spacing_m: f64, capped: bool) -> SurfacePoints {
    let len = x1_m - x0_m;
    let n_rings = ((len / spacing_m).round() as usize).max(1);
    let dx = len / n_rings as f64;
    let mut out = SurfacePoints::default();
    for i in 0..n_rings {
        let x = x0_m + (i as f64 + 0.5) * dx;
        out.push_ring(x, radius_m, 2.0 * PI * radius_m * dx, spacing_m, i % 2 == 1);
    }
    if capped {
        for &x in &[x0_m, x1_m] {
            out.extend(disc(x, radius_m, spacing_m));
        }
    }
    out
}

/// Flat disc at `x` of radius `r`, normal along x.
pub fn disc(x_m: f64, radius_m: f64, spacing_m: f64) -> SurfacePoints {
    let n_rings = ((radius_m / spacing_m).round() as usize).max(1);
    let dr = radius_m / n_rings as f64;
    let mut out = SurfacePoints::default();
    for j in 0..n_rings {
        let (r0, r1) = (j as f64 * dr, (j + 1) as f64 * dr);
        let area = PI * (r1 * r1 - r0 * r0);
        let r = if j == 0 { 0.0 } else { 0.5 * (r0 + r1) };
        if j == 0 {
            out.points_m.push(Vector3::new(x_m, 0.0, 0.0));
            out.area_m2.push(area);
        } else {
            out.push_ring(x_m, r, area, spacing_m, j % 2 == 1);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn areas_add_up() {
        let s = spheroid(0.0, 1.0, 1.0, 0.1);
        let a: f64 = s.area_m2.iter().sum();
        assert!((a - 4.0 * PI).abs() < 1e-6 * 4.0 * PI, "{a}");
        let t = tube(2.0, -1.0, 3.0, 0.2, true);
        let a: f64 = t.area_m2.iter().sum();
        let exact = 2.0 * PI * 2.0 * 4.0 + 2.0 * PI * 4.0;
        assert!((a - exact).abs() < 1e-9 * exact, "{a} vs {exact}");
        // spacing close to the requested one
        assert!(
            (s.spacing_m() / 0.1 - 1.0).abs() < 0.15,
            "{}",
            s.spacing_m()
        );
    }
}
