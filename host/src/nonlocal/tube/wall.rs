//! The still tube wall: its collocation points, their sources and the
//! kernel, laid out as rings of equal point count so that the wall is
//! symmetric under rotation by `2 pi / n_theta` about the tube axis.
//!
//! MFS wall ([`Wall::mfs`]). No-slip (zero velocity) is collocated at points
//! on the cylinder `r = R` and, for a closed tube, on flat end caps and the
//! rims where they meet. Each collocation point has one singular
//! free-space Stokeslet (the Oseen tensor) placed OUTSIDE the fluid, pushed
//! along the outward normal by `d = offset * h` (`h` the point spacing):
//! radially to `r = R + d` on the cylinder, axially beyond the caps, along
//! the bisector at the rims. The sources lie outside the fluid, so the
//! velocity they induce is an exact, smooth Stokes flow inside the tube and
//! the only error is the residual wall velocity between collocation points,
//! which decays exponentially with `d / h` (Fairweather & Karageorghis
//! 1998; Young et al. 2006), measured by `super::diagnostics`.
//!
//! Rings. Every ring of the wall (cylinder, cap and rim) carries the same
//! number `n_theta = round(2 pi R / h)` of points, so rotating the tube by
//! one station maps the wall onto itself: in each point's own cylindrical
//! frame the wall-wall matrix is block-circulant, which `super::rings`
//! solves mode by mode. Cap rings therefore get more points near the axis
//! than their circumference needs ([`CapLayout::Rings`]); the old layout,
//! with ring counts proportional to the radius, is kept as
//! [`CapLayout::Graded`] for comparison: its cap points are "extra" points
//! that the ring solver treats densely, like the moving objects. The axis
//! point of each cap is always extra.
//!
//! The leaky wall ([`Wall::leaky`], the old model of
//! `super::super::confined`): regularized Stokeslets ON the wall. Its
//! velocity between points is of the order of the wall stress times
//! `h / mu`, so a closed tube's pressure difference drives oil through it.
//!
//! References: G. Fairweather & A. Karageorghis, Adv. Comput. Math. 9
//! (1998) 69; D. L. Young, S. J. Jane, C. M. Fan, K. Murugesan & C. C. Tsai,
//! J. Comput. Phys. 211 (2006) 1.

use super::super::stokeslet::add_regularized_stokeslet;
use super::super::surface;
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::{FRAC_1_SQRT_2, PI};

/// Kernel of the wall's sources.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WallKernel {
    /// Singular Stokeslets off the wall (MFS, leak-free).
    Singular,
    /// Regularized Stokeslets on the wall itself (the old, leaky wall).
    Regularized { blob_m: f64 },
}

/// How the end caps are covered with points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CapLayout {
    /// Every cap ring has the cylinder's `n_theta` points (rotationally
    /// symmetric with the rest of the wall; the default).
    Rings,
    /// Ring counts proportional to the radius, about `h` apart (the layout
    /// before the ring solver; its caps are solved densely).
    Graded,
}

/// One ring of `n_theta` wall points: point `k` at angle
/// `2 pi (k + shift) / n_theta`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ring {
    pub x_m: f64,
    pub radius_m: f64,
    pub source_x_m: f64,
    pub source_radius_m: f64,
    pub shift: f64,
    /// Outward normal in the point's own frame: axial and radial parts.
    pub normal_xr: [f64; 2],
}

/// A still tube wall: collocation points, their sources and the kernel.
/// The first `rings.len() * n_theta` points are the rings' (ring by ring),
/// the rest are extra points without the rotational symmetry.
#[derive(Debug, Clone)]
pub struct Wall {
    pub radius_m: f64,
    /// Axial extent of the cylinder (the caps sit at the two ends).
    pub x0_m: f64,
    pub x1_m: f64,
    pub spacing_m: f64,
    pub capped: bool,
    pub n_theta: usize,
    pub rings: Vec<Ring>,
    pub collocation_m: Vec<Vector3<f64>>,
    pub sources_m: Vec<Vector3<f64>>,
    /// Outward unit normal at each collocation point.
    pub normals: Vec<Vector3<f64>>,
    pub kernel: WallKernel,
}

fn radial(p: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(0.0, p[1], p[2]).normalize()
}

/// Points per ring of a wall of radius `r` and spacing `h`.
pub fn ring_count(radius_m: f64, spacing_m: f64) -> usize {
    ((2.0 * PI * radius_m / spacing_m).round() as usize).max(3)
}

/// Cylinder rings between `x0` and `x1`, about `h` apart, every other one
/// staggered by half a station (as `surface::tube`).
fn cylinder_rings(radius_m: f64, x0_m: f64, x1_m: f64, h: f64, d: f64) -> Vec<Ring> {
    let n_rings = (((x1_m - x0_m) / h).round() as usize).max(1);
    let dx = (x1_m - x0_m) / n_rings as f64;
    (0..n_rings)
        .map(|i| Ring {
            x_m: x0_m + (i as f64 + 0.5) * dx,
            radius_m,
            source_x_m: x0_m + (i as f64 + 0.5) * dx,
            source_radius_m: radius_m + d,
            shift: if i % 2 == 1 { 0.5 } else { 0.0 },
            normal_xr: [0.0, 1.0],
        })
        .collect()
}

/// Cap at `x` (sources pushed by `out` along x): its inner rings (as
/// `surface::disc`, without the axis point) and its rim.
fn cap_rings(x: f64, radius_m: f64, h: f64, out: f64) -> Vec<Ring> {
    let n_caps = ((radius_m / h).round() as usize).max(1);
    let dr = radius_m / n_caps as f64;
    let sign = out.signum();
    let mut rings: Vec<Ring> = (1..n_caps)
        .map(|j| Ring {
            x_m: x,
            radius_m: (j as f64 + 0.5) * dr,
            source_x_m: x + out,
            source_radius_m: (j as f64 + 0.5) * dr,
            shift: if j % 2 == 1 { 0.5 } else { 0.0 },
            normal_xr: [sign, 0.0],
        })
        .collect();
    // The rim where cylinder meets cap is collocated too, its sources
    // pushed out along the bisector: without it the corner is the one
    // place the wall is free to leak.
    let s = FRAC_1_SQRT_2;
    rings.push(Ring {
        x_m: x,
        radius_m,
        source_x_m: x + s * out,
        source_radius_m: radius_m + s * out.abs(),
        shift: 0.25,
        normal_xr: [sign * s, s],
    });
    rings
}

impl Wall {
    /// Leak-free MFS wall: sources `offset_over_spacing * spacing` outside.
    pub fn mfs(
        radius_m: f64,
        (x0_m, x1_m): (f64, f64),
        spacing_m: f64,
        offset_over_spacing: f64,
        capped: Option<CapLayout>,
    ) -> Wall {
        let d = offset_over_spacing * spacing_m;
        let mut rings = cylinder_rings(radius_m, x0_m, x1_m, spacing_m, d);
        let mut extras: Vec<[Vector3<f64>; 3]> = Vec::new();
        for (x, out) in [(x0_m, -d), (x1_m, d)]
            .into_iter()
            .filter(|_| capped.is_some())
        {
            let axial = Vector3::new(out.signum(), 0.0, 0.0);
            let mut caps = cap_rings(x, radius_m, spacing_m, out);
            if capped == Some(CapLayout::Graded) {
                let rim = caps.pop();
                let disc = surface::disc(x, radius_m, spacing_m);
                extras.extend(disc.points_m.iter().map(|p| [*p, p + axial * d, axial]));
                rings.extend(rim);
            } else {
                let centre = Vector3::new(x, 0.0, 0.0);
                extras.push([centre, centre + axial * d, axial]);
                rings.extend(caps);
            }
        }
        Wall::build(
            (radius_m, x0_m, x1_m, spacing_m),
            capped.is_some(),
            rings,
            extras,
            WallKernel::Singular,
        )
    }

    /// The old wall of `super::super::confined`: regularized Stokeslets on
    /// the wall with blob `blob_over_spacing` times the mean point spacing.
    pub fn leaky(
        radius_m: f64,
        (x0_m, x1_m): (f64, f64),
        spacing_m: f64,
        blob_over_spacing: f64,
        capped: bool,
    ) -> Wall {
        let all = surface::tube(radius_m, x0_m, x1_m, spacing_m, capped);
        let blob_m = blob_over_spacing * all.spacing_m();
        let rings = cylinder_rings(radius_m, x0_m, x1_m, spacing_m, 0.0);
        let mut extras = Vec::new();
        for (x, sign) in [(x0_m, -1.0), (x1_m, 1.0)].into_iter().filter(|_| capped) {
            let n = Vector3::new(sign, 0.0, 0.0);
            let disc = surface::disc(x, radius_m, spacing_m);
            extras.extend(disc.points_m.iter().map(|p| [*p, *p, n]));
        }
        Wall::build(
            (radius_m, x0_m, x1_m, spacing_m),
            capped,
            rings,
            extras,
            WallKernel::Regularized { blob_m },
        )
    }

    fn build(
        (radius_m, x0_m, x1_m, spacing_m): (f64, f64, f64, f64),
        capped: bool,
        rings: Vec<Ring>,
        extras: Vec<[Vector3<f64>; 3]>,
        kernel: WallKernel,
    ) -> Wall {
        let n_theta = ring_count(radius_m, spacing_m);
        let mut w = Wall {
            radius_m,
            x0_m,
            x1_m,
            spacing_m,
            capped,
            n_theta,
            rings,
            collocation_m: Vec::new(),
            sources_m: Vec::new(),
            normals: Vec::new(),
            kernel,
        };
        for g in 0..w.rings.len() {
            let ring = w.rings[g];
            for k in 0..n_theta {
                let t = w.frame(g, k);
                let at = |x: f64, r: f64| Vector3::new(x, 0.0, 0.0) + t.column(1) * r;
                w.collocation_m.push(at(ring.x_m, ring.radius_m));
                w.sources_m.push(at(ring.source_x_m, ring.source_radius_m));
                w.normals
                    .push(t.column(0) * ring.normal_xr[0] + t.column(1) * ring.normal_xr[1]);
            }
        }
        for [c, s, n] in extras {
            w.collocation_m.push(c);
            w.sources_m.push(s);
            w.normals.push(if n.norm() > 0.0 { n } else { radial(&c) });
        }
        w
    }

    /// Angle of point `k` of ring `g`.
    pub fn angle(&self, g: usize, k: usize) -> f64 {
        2.0 * PI * (k as f64 + self.rings[g].shift) / self.n_theta as f64
    }

    /// The point's own frame: columns `e_x`, `e_r`, `e_theta` (Cartesian).
    pub fn frame(&self, g: usize, k: usize) -> Matrix3<f64> {
        let (s, c) = self.angle(g, k).sin_cos();
        Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
    }

    /// Number of ring points (the symmetric part; extras follow).
    pub fn n_ring_points(&self) -> usize {
        self.rings.len() * self.n_theta
    }

    pub fn len(&self) -> usize {
        self.collocation_m.len()
    }

    pub fn is_empty(&self) -> bool {
        self.collocation_m.is_empty()
    }

    /// Velocity at `target` per unit force on wall source `j`.
    pub fn block(&self, target: &Vector3<f64>, j: usize, c: f64) -> Matrix3<f64> {
        let x = target - self.sources_m[j];
        let mut m = Matrix3::zeros();
        match self.kernel {
            WallKernel::Singular => {
                let r2 = x.norm_squared();
                let r = r2.sqrt();
                let inv = c / (r2 * r);
                for a in 0..3 {
                    for b in 0..3 {
                        m[(a, b)] = x[a] * x[b] * inv;
                    }
                    m[(a, a)] += c / r;
                }
            }
            WallKernel::Regularized { blob_m } => add_regularized_stokeslet(&mut m, &x, blob_m, c),
        }
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rings_are_rotations_of_each_other_and_normals_point_out() {
        let w = Wall::mfs(0.02, (-0.03, 0.05), 0.004, 1.5, Some(CapLayout::Rings));
        let m = w.n_theta;
        assert_eq!(m, ring_count(0.02, 0.004));
        let rot = |a: f64| {
            let (s, c) = a.sin_cos();
            Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
        };
        let step = rot(2.0 * PI / m as f64);
        for g in 0..w.rings.len() {
            for k in 0..m {
                let (i, j) = (g * m + k, g * m + (k + 1) % m);
                for v in [&w.collocation_m, &w.sources_m, &w.normals] {
                    assert!((step * v[i] - v[j]).norm() < 1e-12);
                }
                // sources lie outside the fluid, along the outward normal
                let out = w.sources_m[i] - w.collocation_m[i];
                assert!(out.dot(&w.normals[i]) > 0.99 * out.norm());
            }
        }
        // two axis points, one per cap
        assert_eq!(w.len(), w.n_ring_points() + 2);
    }
}
