//! Assembly and solution of the two first-kind single-layer problems of a
//! body of revolution translating along and rotating about the axis of a
//! tube (closed by flat caps, open, or absent), and the diagnostics.
//!
//! Collocation at element midpoints, one constant traction per element:
//! * meridional, `2N x 2N`: `u = e_x` on the body, `0` on wall and caps;
//!   the axial drag is `int f_x dA` over the body;
//! * swirl, `N x N`: `u_phi = sigma` on the body, `0` elsewhere; the axial
//!   torque is `int sigma f_phi dA`.
//!
//! Both share one pass of kernel integrals. The flux diagnostic integrates
//! the represented velocity over the gap at the body's centre section and
//! over the full tube section midway between nose and tube end: mass
//! conservation demands `Q_gap + pi a^2 U = Q_ahead`, and in a closed tube
//! `Q_ahead = 0`. A porous wall fails exactly this test.
//!
//! References: C. Pozrikidis, *Boundary Integral and Singularity Methods
//! for Linearized Viscous Flow* (1992), ch. 4 and §7.2.

use super::kernels::Ring;
use super::mesh::{discretize, Element, Part, Sizing};
use super::quadrature::{over_element, over_own_element};
use super::{AxisymSettings, BodySolve, Confinement, FluxCheck};
use crate::nonlocal::gauss_legendre::unit_interval;
use crate::nonlocal::{linalg, NonlocalError};
use crate::physics::profile::{BodyProfile, Piece};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use std::f64::consts::PI;

/// The mesh of body and tube for one problem.
pub struct Mesh {
    pub elements: Vec<Element>,
    pub body_x: (f64, f64),
}

fn geometry_error(msg: impl Into<String>) -> NonlocalError {
    NonlocalError::Geometry(msg.into())
}

/// Resolution in [1, 200] elements per gap, growth in (0, 1].
/// The tube's wall in the meridian plane, from `lo` to `hi` at `radius`,
/// with its end caps when `closed`, and its two rims as corners refined to
/// half the element size `h0` (shared by the body solve and the coupler's
/// spin solve).
pub(super) fn tube_wall(
    lo: f64,
    hi: f64,
    radius: f64,
    closed: bool,
    h0: f64,
    corners: &mut Vec<([f64; 2], f64)>,
    wall_pieces: &mut Vec<Piece>,
) {
    for x in [lo, hi] {
        corners.push(([x, radius], 0.5 * h0));
    }
    wall_pieces.push(Piece::Line {
        a: [lo, radius],
        b: [hi, radius],
    });
    if closed {
        wall_pieces.push(Piece::Line {
            a: [hi, radius],
            b: [hi, 0.0],
        });
        wall_pieces.push(Piece::Line {
            a: [lo, 0.0],
            b: [lo, radius],
        });
    }
}

pub(super) fn check_settings(s: &AxisymSettings) -> Result<(), NonlocalError> {
    if !(s.resolution.is_finite() && s.resolution >= 1.0 && s.resolution <= 200.0) {
        return Err(NonlocalError::Settings(format!(
            "resolution must be in [1, 200] elements per gap, got {}",
            s.resolution
        )));
    }
    if !(s.growth.is_finite() && s.growth > 0.0 && s.growth <= 1.0) {
        return Err(NonlocalError::Settings(format!(
            "growth must be in (0, 1], got {}",
            s.growth
        )));
    }
    Ok(())
}

/// Check the geometry and build the mesh.
pub fn build_mesh(
    profile: &BodyProfile,
    confinement: &Confinement,
    centre_m: f64,
    s: &AxisymSettings,
) -> Result<Mesh, NonlocalError> {
    profile.validate()?;
    check_settings(s)?;
    if !centre_m.is_finite() {
        return Err(geometry_error(format!("body position {centre_m} m")));
    }
    let half_len = 0.5e-3 * profile.length_mm();
    let a_max = 0.5e-3 * profile.max_diameter_mm();
    let body_x = (centre_m - half_len, centre_m + half_len);
    let mut h0 = a_max / s.resolution;
    let mut h_max = 2.0 * a_max;
    if let Some((radius, length, _)) = confinement.tube() {
        if !(radius.is_finite() && radius > 0.0 && length.is_finite() && length > 0.0) {
            return Err(geometry_error(format!(
                "tube diameter {} m and length {length} m must be positive and finite",
                2.0 * radius
            )));
        }
        if a_max >= radius {
            return Err(geometry_error(format!(
                "the body (diameter {} mm) does not fit in the {} mm tube",
                2e3 * a_max,
                2e3 * radius
            )));
        }
        if body_x.0 <= -0.5 * length || body_x.1 >= 0.5 * length {
            return Err(geometry_error(format!(
                "the body ({} mm long, centre at {} mm) does not fit between the tube ends at +-{} mm",
                2e3 * half_len,
                1e3 * centre_m,
                0.5e3 * length
            )));
        }
        h0 = h0.min((radius - a_max) / s.resolution);
        // An open tube carries the displaced flux along its whole length,
        // so its far wall must hold a Poiseuille flow without leaking
        // between collocation points: finer than a closed tube's, where
        // the flow decays within a radius or two of the body.
        let (_, _, closed) = confinement.tube().unwrap_or((0.0, 0.0, true));
        h_max = if closed { 0.5 * radius } else { 0.25 * radius };
    }
    let meridian = profile.meridian(centre_m);
    let mut corners: Vec<([f64; 2], f64)> =
        meridian.corners.iter().map(|&c| (c, 0.25 * h0)).collect();
    let mut wall_pieces = Vec::new();
    if let Some((radius, length, closed)) = confinement.tube() {
        let (lo, hi) = (-0.5 * length, 0.5 * length);
        // The tube's rims: the open pipe's free edge has a singular
        // traction; a closed tube's concave corner is mild but cheap to refine.
        tube_wall(lo, hi, radius, closed, h0, &mut corners, &mut wall_pieces);
    }
    let sizing = Sizing {
        h0,
        growth: s.growth,
        h_max,
        body_x,
        corners,
    };
    let mut elements = Vec::new();
    for (pieces, part) in [(&meridian.pieces, Part::Body), (&wall_pieces, Part::Wall)] {
        for p in pieces.iter() {
            elements.extend(discretize(p, &sizing, part, s.max_elements)?);
            if elements.len() > s.max_elements {
                return Err(NonlocalError::Settings(format!(
                    "the mesh needs more than {} elements; lower the resolution",
                    s.max_elements
                )));
            }
        }
    }
    Ok(Mesh { elements, body_x })
}

/// Memory of the dense solve (bytes) for `n` elements: the meridional and
/// swirl matrices, faer's LU copies of them, and the kernel table.
pub fn dense_bytes(n: usize) -> usize {
    let m = (2 * n) * (2 * n) + n * n;
    2 * 8 * m + std::mem::size_of::<Ring>() * n * n
}

/// Velocity (per unit force density, `mu = 1`) of the solved tractions at `p`.
fn velocity(mesh: &Mesh, fx: &[f64], fs: &[f64], p: [f64; 2]) -> f64 {
    mesh.elements
        .iter()
        .enumerate()
        .map(|(j, e)| {
            let k = over_element(p, e);
            (k.xx * fx[j] + k.xs * fs[j]) / (8.0 * PI)
        })
        .sum()
}

/// Volume flux `int 2 pi sigma u_x dsigma` over `[s_lo, s_hi]` at `x`.
fn flux(mesh: &Mesh, fx: &[f64], fs: &[f64], x: f64, s_lo: f64, s_hi: f64) -> f64 {
    unit_interval(24)
        .par_iter()
        .map(|&(u, w)| {
            let sg = s_lo + u * (s_hi - s_lo);
            w * (s_hi - s_lo) * 2.0 * PI * sg * velocity(mesh, fx, fs, [x, sg])
        })
        .sum()
}

/// Radius of the meshed body (the polygon) at `x`.
fn body_radius_at(mesh: &Mesh, x: f64) -> f64 {
    mesh.elements
        .iter()
        .filter(|e| e.part == Part::Body)
        .filter_map(|e| {
            let (x0, x1) = (e.a[0].min(e.b[0]), e.a[0].max(e.b[0]));
            if x < x0 || x > x1 || x1 - x0 < 1e-15 {
                return None;
            }
            let t = (x - e.a[0]) / (e.b[0] - e.a[0]);
            Some(e.a[1] + t * (e.b[1] - e.a[1]))
        })
        .fold(0.0, f64::max)
}

/// Solve both problems on `mesh` for viscosity `mu`.
pub fn solve_mesh(
    mesh: &Mesh,
    confinement: &Confinement,
    mu: f64,
    s: &AxisymSettings,
) -> Result<BodySolve, NonlocalError> {
    let start = std::time::Instant::now();
    let els = &mesh.elements;
    let n = els.len();
    within_dense_limit(n, dense_bytes(n), "the dense solve", s)?;
    let table: Vec<Vec<Ring>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let t = els[i].mid();
            (0..n)
                .map(|j| {
                    if i == j {
                        over_own_element(&els[j])
                    } else {
                        over_element(t, &els[j])
                    }
                })
                .collect()
        })
        .collect();
    let c = 1.0 / (8.0 * PI);
    let merid = DMatrix::from_fn(2 * n, 2 * n, |r, col| {
        let k = &table[r / 2][col / 2];
        c * match (r % 2, col % 2) {
            (0, 0) => k.xx,
            (0, _) => k.xs,
            (_, 0) => k.sx,
            _ => k.ss,
        }
    });
    let swirl = DMatrix::from_fn(n, n, |r, col| c * table[r][col].pp);
    drop(table);
    let is_body: Vec<bool> = els.iter().map(|e| e.part == Part::Body).collect();
    let rhs_m = DVector::from_fn(2 * n, |r, _| {
        if r % 2 == 0 && is_body[r / 2] {
            1.0
        } else {
            0.0
        }
    });
    let rhs_s = DVector::from_fn(n, |r, _| if is_body[r] { els[r].mid()[1] } else { 0.0 });
    let fm = linalg::solve(
        merid,
        &DMatrix::from_column_slice(2 * n, 1, rhs_m.as_slice()),
    )?;
    let fsw = linalg::solve(swirl, &DMatrix::from_column_slice(n, 1, rhs_s.as_slice()))?;
    let fx: Vec<f64> = (0..n).map(|j| fm[(2 * j, 0)]).collect();
    let fs: Vec<f64> = (0..n).map(|j| fm[(2 * j + 1, 0)]).collect();
    let drag: f64 = (0..n)
        .filter(|&j| is_body[j])
        .map(|j| fx[j] * els[j].area())
        .sum();
    let torque: f64 = (0..n)
        .filter(|&j| is_body[j])
        .map(|j| fsw[(j, 0)] * els[j].moment_area())
        .sum();
    let solved_at = start.elapsed().as_secs_f64();
    let flux_check = confinement.tube().map(|(radius, length, closed)| {
        let xc = 0.5 * (mesh.body_x.0 + mesh.body_x.1);
        let a = body_radius_at(mesh, xc);
        let x_ahead = 0.5 * (mesh.body_x.1 + 0.5 * length);
        FluxCheck {
            closed,
            displaced: PI * a * a,
            gap: flux(mesh, &fx, &fs, xc, a, radius),
            ahead: flux(mesh, &fx, &fs, x_ahead, 0.0, radius),
        }
    });
    let body_elements = is_body.iter().filter(|b| **b).count();
    Ok(BodySolve {
        drag_n_s_per_m: mu * drag,
        rotational_drag_n_m_s: mu * torque,
        body_elements,
        wall_elements: n - body_elements,
        flux: flux_check,
        seconds: start.elapsed().as_secs_f64(),
        flux_seconds: start.elapsed().as_secs_f64() - solved_at,
    })
}

/// Refuses a dense solve of `n` elements whose matrix (`bytes`) exceeds the
/// settings' limit, naming `what` it is for, before anything is allocated.
pub(super) fn within_dense_limit(
    n: usize,
    bytes: usize,
    what: &str,
    s: &AxisymSettings,
) -> Result<(), NonlocalError> {
    if bytes > s.max_dense_bytes {
        return Err(NonlocalError::Settings(format!(
            "{n} elements need {:.2} GB for {what}, above the limit of {:.2} GB; lower the resolution",
            bytes as f64 / 1e9,
            s.max_dense_bytes as f64 / 1e9
        )));
    }
    Ok(())
}
