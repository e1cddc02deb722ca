//! Diagnostics that expose a leaking tube wall, computed from the solved
//! flow itself rather than assumed:
//!
//! 1. Net flux through cross-sections. In a closed tube the fluid between a
//!    cross-section and a cap is a closed volume, so the net flux
//!    `Q = int u_x dA` through every section vanishes exactly (a force-only
//!    line displaces no volume). A porous wall lets the back-flow escape
//!    through it instead, and `Q != 0`. Reported over the piston flux
//!    `pi R^2 U` (axial translation at `U`) and `pi R^2 Omega r_ref` (axial
//!    rotation at `Omega`, `r_ref` the object's radius). In an open tube `Q`
//!    is the real pumped flux, not an error.
//! 2. Wall velocity between collocation points: the largest `|u|` on a grid
//!    staggered from the collocation points (between rings, and between the
//!    points of a ring), on the cylinder and on the caps, over the same
//!    reference speeds.
//!
//! Quadrature of the flux: Gauss-Legendre in `r` (24 nodes), trapezoid in
//! the angle (at least three nodes per wall point of a ring, exponentially
//! accurate for the periodic integrand).

use super::mfs::Solution;
use super::wall::Wall;
use nalgebra::Vector3;
use std::f64::consts::PI;

/// Leak diagnostics of one moving object's axial motions.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Diagnostics {
    /// Axial positions of the cross-sections (m).
    pub sections_x_m: Vec<f64>,
    /// Net flux through each section over `pi R^2 U`, axial translation.
    pub flux_over_piston_translation: Vec<f64>,
    /// Net flux through each section over `pi R^2 Omega r_ref`, axial rotation.
    pub flux_over_piston_rotation: Vec<f64>,
    /// Largest wall speed between collocation points over `U`.
    pub wall_slip_over_u: f64,
    /// Largest wall speed between collocation points over `Omega r_ref`.
    pub wall_slip_over_omega_r: f64,
    /// Where the translation's wall slip is largest: axial position and
    /// radius (m); `r < R` is on a cap.
    pub wall_slip_at_x_r_m: [f64; 2],
    /// Reference radius of the rotation speeds (m).
    pub rotation_ref_radius_m: f64,
    /// Points (3 unknowns each) of the solve, and on the wall.
    pub n_points: usize,
    pub n_wall_points: usize,
    /// Peak memory of the solve, estimated before it (bytes).
    pub peak_bytes: usize,
    /// Wall-clock time of the solve and of these diagnostics (s).
    pub solve_seconds: f64,
    pub diagnostics_seconds: f64,
}

impl Diagnostics {
    /// Largest `|Q|` over the piston flux of either axial motion.
    pub fn max_flux(&self) -> f64 {
        self.flux_over_piston_translation
            .iter()
            .chain(&self.flux_over_piston_rotation)
            .fold(0.0, |m, v| m.max(v.abs()))
    }

    /// Largest wall slip of either axial motion.
    pub fn max_slip(&self) -> f64 {
        self.wall_slip_over_u.max(self.wall_slip_over_omega_r)
    }
}

const RADIAL_NODES: usize = 24;

/// Quadrature points and weights of the cross-section at `x`.
fn section(wall: &Wall, x: f64) -> (Vec<Vector3<f64>>, Vec<f64>) {
    let r_wall = wall.radius_m;
    let n_th = (3.0 * 2.0 * PI * r_wall / wall.spacing_m).ceil().max(64.0) as usize;
    let (nodes, weights) = crate::nonlocal::gauss_legendre::symmetric(RADIAL_NODES);
    let mut pts = Vec::with_capacity(RADIAL_NODES * n_th);
    let mut w = Vec::with_capacity(RADIAL_NODES * n_th);
    for (&t, &wt) in nodes.iter().zip(weights) {
        let r = 0.5 * r_wall * (1.0 + t);
        for k in 0..n_th {
            let th = 2.0 * PI * k as f64 / n_th as f64;
            pts.push(Vector3::new(x, r * th.cos(), r * th.sin()));
            w.push(0.5 * r_wall * wt * r * 2.0 * PI / n_th as f64);
        }
    }
    (pts, w)
}

/// Points on the wall half-way between collocation points.
pub fn staggered_wall_points(wall: &Wall) -> Vec<Vector3<f64>> {
    let (r, h) = (wall.radius_m, wall.spacing_m);
    let len = wall.x1_m - wall.x0_m;
    let n_rings = ((len / h).round() as usize).max(1);
    let dx = len / n_rings as f64;
    let n_th = ((2.0 * PI * r / h).round() as usize).max(1);
    let mut out = Vec::new();
    let ring = |out: &mut Vec<Vector3<f64>>, x: f64, rr: f64, n: usize, shift: f64| {
        for k in 0..n {
            let th = 2.0 * PI * (k as f64 + shift) / n as f64;
            out.push(Vector3::new(x, rr * th.cos(), rr * th.sin()));
        }
    };
    for i in 0..=n_rings {
        // between rings (and on the rim where cylinder meets cap)
        ring(&mut out, wall.x0_m + i as f64 * dx, r, n_th, 0.75);
        if i < n_rings {
            // on a ring, between its (possibly staggered) points
            let shift = if i % 2 == 1 { 0.0 } else { 0.5 };
            ring(&mut out, wall.x0_m + (i as f64 + 0.5) * dx, r, n_th, shift);
        }
    }
    if wall.capped {
        let n_caps = ((r / h).round() as usize).max(1);
        let dr = r / n_caps as f64;
        for x in [wall.x0_m, wall.x1_m] {
            for j in 1..n_caps {
                let rr = j as f64 * dr;
                let n = ((2.0 * PI * rr / h).round() as usize).max(3);
                ring(&mut out, x, rr, n, 0.25);
            }
        }
    }
    out
}

/// Diagnostics of moving object `q`'s axial translation and rotation.
pub fn diagnose(
    sol: &Solution<'_>,
    q: usize,
    sections_x_m: &[f64],
    rotation_ref_radius_m: f64,
) -> Diagnostics {
    let t0 = std::time::Instant::now();
    let wall = sol.system.wall;
    let (ct, cr) = (6 * q, 6 * q + 3);
    let piston = PI * wall.radius_m * wall.radius_m;
    let rot_speed = rotation_ref_radius_m;
    let mut flux_t = Vec::new();
    let mut flux_r = Vec::new();
    for &x in sections_x_m {
        let (pts, w) = section(wall, x);
        let u = sol.velocities(&pts, &[ct, cr]);
        let qt: f64 = u.iter().zip(&w).map(|(u, w)| u[0][0] * w).sum();
        let qr: f64 = u.iter().zip(&w).map(|(u, w)| u[1][0] * w).sum();
        flux_t.push(qt / piston);
        flux_r.push(qr / (piston * rot_speed));
    }
    let pts = staggered_wall_points(wall);
    let u = sol.velocities(&pts, &[ct, cr]);
    let worst = (0..pts.len())
        .max_by(|&a, &b| u[a][0].norm().total_cmp(&u[b][0].norm()))
        .unwrap_or(0);
    let p = pts.get(worst).copied().unwrap_or_default();
    let max_speed = |c: usize| u.iter().fold(0.0_f64, |m, u| m.max(u[c].norm()));
    let n_points = sol.system.len();
    Diagnostics {
        sections_x_m: sections_x_m.to_vec(),
        flux_over_piston_translation: flux_t,
        flux_over_piston_rotation: flux_r,
        wall_slip_over_u: max_speed(0),
        wall_slip_over_omega_r: max_speed(1) / rot_speed,
        wall_slip_at_x_r_m: [p[0], (p[1] * p[1] + p[2] * p[2]).sqrt()],
        rotation_ref_radius_m,
        n_points,
        n_wall_points: wall.len(),
        peak_bytes: sol.peak_bytes,
        solve_seconds: sol.seconds,
        diagnostics_seconds: t0.elapsed().as_secs_f64(),
    }
}
