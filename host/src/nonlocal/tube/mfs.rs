//! The collocation system of moving objects (tail line, body or sphere
//! surface) inside a still tube wall ([`super::wall`]), its dense solve,
//! and the solved flow.
//!
//! One system `A F = U` holds all unknowns: the forces of the moving
//! objects' regularized Stokeslets (Cortez, Fauci & Medovikov 2005,
//! validated in free space in `mrs_line`) and of the wall's sources; the
//! right-hand sides are the six unit rigid motions of each moving object
//! with everything else still. [`solve_dense`] factors all of `A` (the
//! reference, and the solver for walls without ring symmetry);
//! `super::rings` gives the same forces from the wall's symmetry.
//!
//! A closed wall of Stokeslets has a null mode: a force density along the
//! normal makes a pure pressure and no velocity inside. The rank-one
//! completion `n_i (sum_j n_j . F_j)` on the wall rows removes it without
//! changing the flow: dotting the wall equations with `n` shows the added
//! sum must vanish, because the flow inside is divergence-free (Power &
//! Miranda 1987; Pozrikidis 1992, sec. 4.5). It is scaled like a Stokeslet
//! seen from the tube radius.
//!
//! References:
//! - R. Cortez, L. Fauci & A. Medovikov, Phys. Fluids 17 (2005) 031504.
//! - H. Power & G. Miranda, SIAM J. Appl. Math. 47 (1987) 689.
//! - C. Pozrikidis, Boundary Integral and Singularity Methods for
//!   Linearized Viscous Flow, Cambridge University Press (1992).

use super::super::linalg;
use super::super::rigid;
use super::super::robot::Object;
use super::super::stokeslet::add_regularized_stokeslet;
use super::super::NonlocalError;
use super::wall::{Wall, WallKernel};
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};
use rayon::prelude::*;
use std::f64::consts::PI;

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

/// Bytes the dense solve of `n_points` source points needs at its peak:
/// the assembled matrix and faer's LU copy of it, with the allocator's
/// slack of `super::rings::with_slack`.
pub fn dense_peak_bytes(n_points: usize) -> usize {
    super::rings::with_slack(linalg::dense_bytes(n_points).saturating_mul(2))
}

/// The collocation system: every point's target, and its 3x3 blocks.
pub struct System<'a> {
    pub moving: &'a [Object],
    pub wall: &'a Wall,
    pub viscosity_pa_s: f64,
    /// Start of each moving object's points, then of the wall's, then N.
    pub starts: Vec<usize>,
    pub targets: Vec<Vector3<f64>>,
    completion: f64,
}

impl<'a> System<'a> {
    pub fn new(moving: &'a [Object], wall: &'a Wall, viscosity_pa_s: f64) -> Self {
        let mut starts = vec![0];
        for o in moving {
            starts.push(starts.last().unwrap() + o.len());
        }
        let n_moving = *starts.last().unwrap();
        starts.push(n_moving + wall.len());
        let mut targets: Vec<Vector3<f64>> = Vec::with_capacity(n_moving + wall.len());
        for (q, o) in moving.iter().enumerate() {
            targets.extend((0..starts[q + 1] - starts[q]).map(|k| o.target(k)));
        }
        targets.extend(&wall.collocation_m);
        let c = 1.0 / (8.0 * PI * viscosity_pa_s);
        let completion = match (wall.kernel, wall.capped) {
            (WallKernel::Singular, true) => c / wall.radius_m,
            _ => 0.0,
        };
        System {
            moving,
            wall,
            viscosity_pa_s,
            starts,
            targets,
            completion,
        }
    }

    /// Total number of points (3 unknowns each).
    pub fn len(&self) -> usize {
        *self.starts.last().unwrap()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Points of the moving objects (they come first).
    pub fn n_moving(&self) -> usize {
        self.starts[self.moving.len()]
    }

    /// Moving object and local index of point `j < n_moving`.
    fn owner(&self, j: usize) -> (usize, usize) {
        let o = self.starts.partition_point(|&s| s <= j) - 1;
        (o, j - self.starts[o])
    }

    /// Velocity at `x` per unit force on source `j`.
    pub fn kernel(&self, x: &Vector3<f64>, j: usize) -> Matrix3<f64> {
        let n_mov = self.n_moving();
        if j < n_mov {
            let (o, k) = self.owner(j);
            object_block(&self.moving[o], x, k, self.viscosity_pa_s)
        } else {
            let c = 1.0 / (8.0 * PI * self.viscosity_pa_s);
            self.wall.block(x, j - n_mov, c)
        }
    }

    /// Block `(i, j)` of `A`: velocity at target `i` per unit force on
    /// source `j`, with the wall's null-mode completion.
    pub fn block(&self, i: usize, j: usize) -> Matrix3<f64> {
        let mut b = self.kernel(&self.targets[i], j);
        let n_mov = self.n_moving();
        if self.completion != 0.0 && i >= n_mov && j >= n_mov {
            let n = &self.wall.normals;
            b += n[i - n_mov] * n[j - n_mov].transpose() * self.completion;
        }
        b
    }

    /// Right-hand sides of the points `rows`: `3 rows.len() x 6 n_moving`,
    /// the unit rigid motions of each moving object (zero on the wall).
    pub fn rhs(&self, rows: &[usize]) -> DMatrix<f64> {
        let pts: Vec<Vector3<f64>> = rows.iter().map(|&i| self.targets[i]).collect();
        let mut rhs = DMatrix::zeros(3 * rows.len(), 6 * self.moving.len());
        for q in 0..self.moving.len() {
            let mask: Vec<bool> = rows
                .iter()
                .map(|&i| i >= self.starts[q] && i < self.starts[q + 1])
                .collect();
            rhs.columns_mut(6 * q, 6)
                .copy_from(&rigid::unit_motions(&pts, &mask));
        }
        rhs
    }
}

/// The solved forces of moving objects inside a wall.
pub struct Solution<'a> {
    pub system: System<'a>,
    /// `3N x 6 n_moving`: column `6 q + k` is unit motion `k` of object `q`.
    pub forces: DMatrix<f64>,
    /// Peak memory of the solve as estimated before it (bytes).
    pub peak_bytes: usize,
    /// Wall-clock time of assembly and solve (s).
    pub seconds: f64,
}

pub(super) fn refuse_above(
    need: usize,
    max_bytes: usize,
    n: usize,
    what: &str,
) -> Result<(), NonlocalError> {
    if need > max_bytes {
        return Err(NonlocalError::Settings(format!(
            "the {what} of {n} points ({} unknowns) needs {:.2} GB, above the limit of {:.2} GB; coarsen the wall spacing or shorten the tube",
            3 * n,
            need as f64 / 1e9,
            max_bytes as f64 / 1e9
        )));
    }
    Ok(())
}

/// Assemble and solve all of `A` densely; refuses (before allocating) if
/// the peak memory would exceed `max_bytes`.
pub fn solve_dense<'a>(
    moving: &'a [Object],
    wall: &'a Wall,
    viscosity_pa_s: f64,
    max_bytes: usize,
) -> Result<Solution<'a>, NonlocalError> {
    let t0 = std::time::Instant::now();
    let system = System::new(moving, wall, viscosity_pa_s);
    let n = system.len();
    let need = dense_peak_bytes(n);
    refuse_above(need, max_bytes, n, "dense solve")?;
    let matrix = linalg::assemble(n, |i, j| system.block(i, j));
    let all: Vec<usize> = (0..n).collect();
    let forces = linalg::solve(matrix, &system.rhs(&all))?;
    Ok(Solution {
        system,
        forces,
        peak_bytes: need,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

impl Solution<'_> {
    /// Resistance block `B_pq`: load on moving object `p` per unit motion
    /// of moving object `q`, torques about the origin.
    pub fn block(&self, p: usize, q: usize) -> Matrix6<f64> {
        let sys = &self.system;
        let levers: Vec<Vector3<f64>> = (0..sys.n_moving())
            .map(|i| {
                let (o, k) = sys.owner(i);
                sys.moving[o].lever(k)
            })
            .collect();
        rigid::loads(
            &self.forces,
            &levers,
            sys.starts[p]..sys.starts[p + 1],
            6 * q..6 * q + 6,
        )
    }

    /// Fluid velocity at every point of `points` for the solved motions
    /// `cols` (columns of `forces`): `out[i][c]`.
    pub fn velocities(&self, points: &[Vector3<f64>], cols: &[usize]) -> Vec<Vec<Vector3<f64>>> {
        let n = self.system.len();
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
        let n_mov = self.system.n_moving();
        let wall = self.system.wall;
        let c = 1.0 / (8.0 * PI * self.system.viscosity_pa_s);
        points
            .par_iter()
            .map(|x| {
                let mut u = vec![Vector3::zeros(); cols.len()];
                for (j, fj) in f.iter().enumerate().take(n_mov) {
                    let b = self.system.kernel(x, j);
                    for (uk, fk) in u.iter_mut().zip(fj) {
                        *uk += b * fk;
                    }
                }
                // The singular Stokeslet applied directly, without its 3x3
                // matrix: most of the diagnostics' time is spent here.
                for (jw, fj) in f[n_mov..].iter().enumerate() {
                    if wall.kernel != WallKernel::Singular {
                        let b = wall.block(x, jw, c);
                        for (uk, fk) in u.iter_mut().zip(fj) {
                            *uk += b * fk;
                        }
                        continue;
                    }
                    let d = x - wall.sources_m[jw];
                    let r2 = d.norm_squared();
                    let inv_r = c / r2.sqrt();
                    for (uk, fk) in u.iter_mut().zip(fj) {
                        *uk += (fk + d * (d.dot(fk) / r2)) * inv_r;
                    }
                }
                u
            })
            .collect()
    }
}
