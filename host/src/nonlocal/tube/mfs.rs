//! The tube wall by the method of fundamental solutions (MFS), and the
//! dense solve that couples it with moving objects (tail line, body or
//! sphere surface).
//!
//! Wall. No-slip (zero velocity) is collocated at points on the cylinder
//! `r = R` and, for a closed tube, on flat end caps. Each collocation point
//! has one singular free-space Stokeslet (the Oseen tensor) placed OUTSIDE
//! the fluid, pushed along the outward normal by `d = offset * h` (`h` the
//! point spacing): radially to `r = R + d` on the cylinder, axially beyond
//! the caps. Because the sources lie outside the fluid, the velocity they
//! induce is an exact, smooth Stokes flow inside the tube, and the only
//! error is the residual wall velocity between collocation points, which
//! decays exponentially with `d / h` as long as the flow near the wall is
//! smooth on the scale `h` (Fairweather & Karageorghis 1998; Young, Jane,
//! Fan, Murugesan & Tsai 2006). The wall of regularized Stokeslets ON the
//! wall ([`Wall::leaky`], the old model of `super::super::confined`) instead
//! has a velocity between its points of the order of the wall stress times
//! `h / mu`, so the pressure difference that a closed tube builds drives oil
//! through it: that wall leaks. The residual is measured, not assumed, by
//! `super::diagnostics`.
//!
//! Moving objects keep their own discretisation (`super::super::robot::Object`):
//! regularized Stokeslet segments on the helix centre-line (Cortez, Fauci &
//! Medovikov 2005, validated in free space in `mrs_line`) and surfaces of
//! regularized Stokeslets for bodies. One dense system `A F = U` holds all
//! unknowns; the right-hand sides are the six unit rigid motions of each
//! moving object with everything else still.
//!
//! References:
//! - G. Fairweather & A. Karageorghis, "The method of fundamental solutions
//!   for elliptic boundary value problems", Adv. Comput. Math. 9 (1998) 69.
//! - D. L. Young, S. J. Jane, C. M. Fan, K. Murugesan & C. C. Tsai, "The
//!   method of fundamental solutions for 2D and 3D Stokes problems",
//!   J. Comput. Phys. 211 (2006) 1-8.
//! - R. Cortez, L. Fauci & A. Medovikov, Phys. Fluids 17 (2005) 031504.

use super::super::linalg;
use super::super::rigid;
use super::super::robot::Object;
use super::super::stokeslet::add_regularized_stokeslet;
use super::super::surface;
use super::super::NonlocalError;
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};
use rayon::prelude::*;
use std::f64::consts::PI;

/// Kernel of the wall's sources.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WallKernel {
    /// Singular Stokeslets off the wall (MFS, leak-free).
    Singular,
    /// Regularized Stokeslets on the wall itself (the old, leaky wall).
    Regularized { blob_m: f64 },
}

/// A still tube wall: collocation points, their sources and the kernel.
#[derive(Debug, Clone)]
pub struct Wall {
    pub radius_m: f64,
    /// Axial extent of the cylinder (the caps sit at the two ends).
    pub x0_m: f64,
    pub x1_m: f64,
    pub spacing_m: f64,
    pub capped: bool,
    pub collocation_m: Vec<Vector3<f64>>,
    pub sources_m: Vec<Vector3<f64>>,
    /// Outward unit normal at each collocation point.
    pub normals: Vec<Vector3<f64>>,
    pub kernel: WallKernel,
}

fn radial(p: &Vector3<f64>) -> Vector3<f64> {
    Vector3::new(0.0, p[1], p[2]).normalize()
}

impl Wall {
    /// Leak-free MFS wall: sources `offset_over_spacing * spacing` outside.
    pub fn mfs(
        radius_m: f64,
        x0_m: f64,
        x1_m: f64,
        spacing_m: f64,
        offset_over_spacing: f64,
        capped: bool,
    ) -> Wall {
        let d = offset_over_spacing * spacing_m;
        let cyl = surface::tube(radius_m, x0_m, x1_m, spacing_m, false);
        let mut collocation_m = cyl.points_m.clone();
        let mut normals: Vec<Vector3<f64>> = cyl.points_m.iter().map(radial).collect();
        let scale = (radius_m + d) / radius_m;
        let mut sources_m: Vec<Vector3<f64>> = cyl
            .points_m
            .iter()
            .map(|p| Vector3::new(p[0], p[1] * scale, p[2] * scale))
            .collect();
        if capped {
            for (x, out) in [(x0_m, -d), (x1_m, d)] {
                let cap = surface::disc(x, radius_m, spacing_m);
                sources_m.extend(cap.points_m.iter().map(|p| p + Vector3::new(out, 0.0, 0.0)));
                normals.extend(
                    cap.points_m
                        .iter()
                        .map(|_| Vector3::new(out.signum(), 0.0, 0.0)),
                );
                collocation_m.extend(cap.points_m);
                // The rim where cylinder meets cap is collocated too, its
                // sources pushed out along the bisector: without it the
                // corner is the one place the wall is free to leak.
                let n = ((2.0 * PI * radius_m / spacing_m).round() as usize).max(3);
                let s = std::f64::consts::FRAC_1_SQRT_2;
                let scale = (radius_m + s * d) / radius_m;
                for k in 0..n {
                    let th = 2.0 * PI * (k as f64 + 0.25) / n as f64;
                    let p = Vector3::new(x, radius_m * th.cos(), radius_m * th.sin());
                    collocation_m.push(p);
                    normals.push((radial(&p) + Vector3::new(out.signum(), 0.0, 0.0)) * s);
                    sources_m.push(Vector3::new(x + s * out, p[1] * scale, p[2] * scale));
                }
            }
        }
        Wall {
            radius_m,
            x0_m,
            x1_m,
            spacing_m,
            capped,
            collocation_m,
            sources_m,
            normals,
            kernel: WallKernel::Singular,
        }
    }

    /// The old wall of `super::super::confined`: regularized Stokeslets on
    /// the wall with blob `blob_over_spacing` times the mean point spacing.
    pub fn leaky(
        radius_m: f64,
        x0_m: f64,
        x1_m: f64,
        spacing_m: f64,
        blob_over_spacing: f64,
        capped: bool,
    ) -> Wall {
        let pts = surface::tube(radius_m, x0_m, x1_m, spacing_m, capped);
        let blob_m = blob_over_spacing * pts.spacing_m();
        let normals = pts
            .points_m
            .iter()
            .map(|p| {
                if p[0] <= x0_m + 1e-12 {
                    Vector3::new(-1.0, 0.0, 0.0)
                } else if p[0] >= x1_m - 1e-12 {
                    Vector3::new(1.0, 0.0, 0.0)
                } else {
                    radial(p)
                }
            })
            .collect();
        Wall {
            radius_m,
            x0_m,
            x1_m,
            spacing_m,
            capped,
            collocation_m: pts.points_m.clone(),
            sources_m: pts.points_m,
            normals,
            kernel: WallKernel::Regularized { blob_m },
        }
    }

    pub fn len(&self) -> usize {
        self.collocation_m.len()
    }

    pub fn is_empty(&self) -> bool {
        self.collocation_m.is_empty()
    }

    /// Velocity at `target` per unit force on wall source `j`.
    fn block(&self, target: &Vector3<f64>, j: usize, c: f64) -> Matrix3<f64> {
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

/// Velocity at `target` per unit force on source `k` of a moving object.
fn object_block(obj: &Object, target: &Vector3<f64>, k: usize, mu: f64) -> Matrix3<f64> {
    match obj {
        Object::Line(l) => l.block(target, k, mu),
        Object::Surface(s) => {
            let mut m = Matrix3::zeros();
            let c = 1.0 / (8.0 * PI * mu);
            add_regularized_stokeslet(&mut m, &(target - s.points.points_m[k]), s.blob_m, c);
            m
        }
    }
}

/// Bytes a solve with `n_points` source points needs at its peak: the
/// assembled matrix and faer's LU copy of it.
pub fn peak_bytes(n_points: usize) -> usize {
    2 * linalg::dense_bytes(n_points)
}

/// The solved forces of moving objects inside a wall.
pub struct Solution<'a> {
    pub moving: &'a [Object],
    pub wall: &'a Wall,
    pub viscosity_pa_s: f64,
    /// `3N x 6 n_moving`: column `6 q + k` is unit motion `k` of object `q`.
    pub forces: DMatrix<f64>,
    /// Start of each moving object's unknowns, then of the wall's, then N.
    pub starts: Vec<usize>,
}

/// Assemble and solve; refuses (before allocating) if the peak memory
/// would exceed `max_bytes`.
pub fn solve<'a>(
    moving: &'a [Object],
    wall: &'a Wall,
    viscosity_pa_s: f64,
    max_bytes: usize,
) -> Result<Solution<'a>, NonlocalError> {
    let mut starts = vec![0];
    for o in moving {
        starts.push(starts.last().unwrap() + o.len());
    }
    let n_moving_pts = *starts.last().unwrap();
    let n = n_moving_pts + wall.len();
    starts.push(n);
    let need = peak_bytes(n);
    if need > max_bytes {
        return Err(NonlocalError::Settings(format!(
            "the dense solve of {n} points ({} unknowns) needs {:.2} GB, above the limit of {:.2} GB; coarsen the wall spacing or shorten the tube",
            3 * n,
            need as f64 / 1e9,
            max_bytes as f64 / 1e9
        )));
    }
    let owner = |j: usize| -> (usize, usize) {
        let o = starts.partition_point(|&s| s <= j) - 1;
        (o, j - starts[o])
    };
    let targets: Vec<Vector3<f64>> = (0..n)
        .map(|i| {
            if i < n_moving_pts {
                let (o, k) = owner(i);
                moving[o].target(k)
            } else {
                wall.collocation_m[i - n_moving_pts]
            }
        })
        .collect();
    let c = 1.0 / (8.0 * PI * viscosity_pa_s);
    // A closed wall of Stokeslets has a null mode: a force density along
    // the normal makes a pure pressure and no velocity inside. The rank-one
    // completion `n_i (sum_j n_j . F_j)` on the wall rows removes it without
    // changing the flow: dotting the wall equations with `n` shows the
    // added sum must vanish, because the flow inside is divergence-free
    // (Power & Miranda 1987; Pozrikidis 1992, sec. 4.5). Scaled like a
    // Stokeslet seen from the tube radius.
    let completion = match (wall.kernel, wall.capped) {
        (WallKernel::Singular, true) => c / wall.radius_m,
        _ => 0.0,
    };
    let matrix = linalg::assemble(n, |i, j| {
        if j < n_moving_pts {
            let (o, k) = owner(j);
            object_block(&moving[o], &targets[i], k, viscosity_pa_s)
        } else {
            let jw = j - n_moving_pts;
            let mut b = wall.block(&targets[i], jw, c);
            if completion != 0.0 && i >= n_moving_pts {
                b += wall.normals[i - n_moving_pts] * wall.normals[jw].transpose() * completion;
            }
            b
        }
    });
    let mut rhs = DMatrix::zeros(3 * n, 6 * moving.len());
    for q in 0..moving.len() {
        let mask: Vec<bool> = (0..n)
            .map(|i| i >= starts[q] && i < starts[q + 1])
            .collect();
        rhs.columns_mut(6 * q, 6)
            .copy_from(&rigid::unit_motions(&targets, &mask));
    }
    let forces = linalg::solve(matrix, &rhs)?;
    Ok(Solution {
        moving,
        wall,
        viscosity_pa_s,
        forces,
        starts,
    })
}

impl Solution<'_> {
    /// Resistance block `B_pq`: load on moving object `p` per unit motion
    /// of moving object `q`, torques about the origin.
    pub fn block(&self, p: usize, q: usize) -> Matrix6<f64> {
        let levers: Vec<Vector3<f64>> = (0..self.starts[self.moving.len()])
            .map(|i| {
                let o = self.starts.partition_point(|&s| s <= i) - 1;
                self.moving[o].lever(i - self.starts[o])
            })
            .collect();
        rigid::loads(
            &self.forces,
            &levers,
            self.starts[p]..self.starts[p + 1],
            6 * q..6 * q + 6,
        )
    }

    /// Fluid velocity at every point of `points` for the solved motions
    /// `cols` (columns of `forces`): `out[i][c]`.
    pub fn velocities(&self, points: &[Vector3<f64>], cols: &[usize]) -> Vec<Vec<Vector3<f64>>> {
        let n_mov = self.starts[self.moving.len()];
        let n = *self.starts.last().unwrap();
        let c = 1.0 / (8.0 * PI * self.viscosity_pa_s);
        let f: Vec<Vec<Vector3<f64>>> = (0..n)
            .map(|j| {
                cols.iter()
                    .map(|&k| {
                        Vector3::new(
                            self.forces[(3 * j, k)],
                            self.forces[(3 * j + 1, k)],
                            self.forces[(3 * j + 2, k)],
                        )
                    })
                    .collect()
            })
            .collect();
        points
            .par_iter()
            .map(|x| {
                let mut u = vec![Vector3::zeros(); cols.len()];
                for (j, fj) in f.iter().enumerate() {
                    let b = if j < n_mov {
                        let o = self.starts.partition_point(|&s| s <= j) - 1;
                        object_block(&self.moving[o], x, j - self.starts[o], self.viscosity_pa_s)
                    } else {
                        self.wall.block(x, j - n_mov, c)
                    };
                    for (uk, fk) in u.iter_mut().zip(fj) {
                        *uk += b * fk;
                    }
                }
                u
            })
            .collect()
    }
}
