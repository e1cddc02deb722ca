//! Several objects in one Stokes flow: the tail (regularized Stokeslet
//! segments), the body (a prolate spheroid surface of regularized
//! Stokeslets) and the channel wall (a cylinder with end caps, held still).
//!
//! One dense system couples them all; each moving object is driven through
//! its six unit rigid motions with the others held still, which yields the
//! grand resistance matrix `[[B_bb, B_bt], [B_tb, B_tt]]`: the load on object
//! `p` is `-sum_q B_pq V_q`. The wall's forces are unknowns but carry no
//! motion of their own. Closed channel: the end caps make the fluid volume
//! closed, so no net flux passes any cross-section (the back-flow of paper
//! eq. 9 comes out of the solution rather than being imposed). Disturbances
//! in a tube decay like `exp(-4.2 |x| / R)` (lowest Stokes eigenmode of a
//! pipe), so caps `tube_end_margin_over_radius * R` beyond the robot stand for
//! the far-away real ends.

use super::linalg;
use super::mrs_line::LineSources;
use super::rigid;
use super::stokeslet::add_regularized_stokeslet;
use super::surface::SurfacePoints;
use super::NonlocalError;
use nalgebra::{DMatrix, Matrix3, Matrix6, Vector3};
use std::f64::consts::PI;

/// A surface of regularized Stokeslets with a common blob.
#[derive(Debug, Clone)]
pub struct Surface {
    pub points: SurfacePoints,
    pub blob_m: f64,
}

/// One object of a multi-object problem.
#[derive(Debug, Clone)]
pub enum Object {
    Line(LineSources),
    Surface(Surface),
}

impl Object {
    pub(crate) fn len(&self) -> usize {
        match self {
            Object::Line(l) => l.seg.n,
            Object::Surface(s) => s.points.len(),
        }
    }

    pub(crate) fn target(&self, k: usize) -> Vector3<f64> {
        match self {
            Object::Line(l) => l.seg.mid_point_m[k],
            Object::Surface(s) => s.points.points_m[k],
        }
    }

    pub(crate) fn lever(&self, k: usize) -> Vector3<f64> {
        match self {
            Object::Line(l) => l.centroids[k],
            Object::Surface(s) => s.points.points_m[k],
        }
    }
}

/// Resistance blocks `B_pq` (load on moving object `p` per motion of moving
/// object `q`) for `moving` objects in the presence of `fixed` ones.
pub fn grand_resistance(
    moving: &[Object],
    fixed: &[Object],
    viscosity_pa_s: f64,
) -> Result<Vec<Vec<Matrix6<f64>>>, NonlocalError> {
    let objects: Vec<&Object> = moving.iter().chain(fixed).collect();
    // flat index -> (object, local index)
    let mut index = Vec::new();
    let mut starts = Vec::new();
    for (o, obj) in objects.iter().enumerate() {
        starts.push(index.len());
        index.extend((0..obj.len()).map(|k| (o, k)));
    }
    starts.push(index.len());
    let targets: Vec<Vector3<f64>> = index.iter().map(|&(o, k)| objects[o].target(k)).collect();
    let levers: Vec<Vector3<f64>> = index.iter().map(|&(o, k)| objects[o].lever(k)).collect();
    let c = 1.0 / (8.0 * PI * viscosity_pa_s);
    linalg::check_memory(index.len())?;
    let matrix = linalg::assemble(index.len(), |i, j| {
        let (o, k) = index[j];
        match objects[o] {
            Object::Line(l) => l.block(&targets[i], k, viscosity_pa_s),
            Object::Surface(s) => {
                let mut m = Matrix3::zeros();
                add_regularized_stokeslet(
                    &mut m,
                    &(targets[i] - s.points.points_m[k]),
                    s.blob_m,
                    c,
                );
                m
            }
        }
    });
    let n_moving = moving.len();
    let mut rhs = DMatrix::zeros(3 * index.len(), 6 * n_moving);
    for q in 0..n_moving {
        let mask: Vec<bool> = index.iter().map(|&(o, _)| o == q).collect();
        let cols = rigid::unit_motions(&targets, &mask);
        rhs.columns_mut(6 * q, 6).copy_from(&cols);
    }
    let forces = linalg::solve(matrix, &rhs)?;
    Ok((0..n_moving)
        .map(|p| {
            (0..n_moving)
                .map(|q| rigid::loads(&forces, &levers, starts[p]..starts[p + 1], 6 * q..6 * q + 6))
                .collect()
        })
        .collect())
}
