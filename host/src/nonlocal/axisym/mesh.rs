//! Boundary elements on the generating curves: straight chords between
//! nodes on the exact curves (a polygon of revolution: conical frustums),
//! one constant traction per element, collocation at the chord midpoint.
//!
//! Element sizes follow a sizing function, so one resolution number sets
//! the whole mesh: `h0` on the body and on the wall beside it, growing
//! linearly (`h0 + growth * distance`) away from the body's axial extent
//! up to `h_max`, and refined towards sharp corners (`h0 / 4` at the
//! body's, `h0 / 2` at the tube's rims), where the traction is singular.
//! Nodes are placed by marching along each piece with the local size and
//! then rescaled to land on its end.
//!
//! Frustum areas `pi (s_a + s_b) l` make the discrete `int n_x dA` over a
//! closed body telescope to exactly zero, so the pressure null vector of
//! the first-kind single layer (`f = p n`) cannot leak into the force.
//!
//! References: C. Pozrikidis, *A Practical Guide to Boundary Element
//! Methods* (Chapman & Hall, 2002), ch. 6 (axisymmetric Stokes flow).

use crate::physics::profile::Piece;
use std::f64::consts::PI;

/// Which boundary an element belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    Body,
    /// Tube wall or end cap: held still.
    Wall,
}

/// One straight element of a generating curve, `[x, sigma]` in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Element {
    pub a: [f64; 2],
    pub b: [f64; 2],
    pub part: Part,
}

impl Element {
    pub fn length(&self) -> f64 {
        (self.b[0] - self.a[0]).hypot(self.b[1] - self.a[1])
    }
    pub fn mid(&self) -> [f64; 2] {
        [0.5 * (self.a[0] + self.b[0]), 0.5 * (self.a[1] + self.b[1])]
    }
    /// Area of the frustum.
    pub fn area(&self) -> f64 {
        PI * (self.a[1] + self.b[1]) * self.length()
    }
    /// `int sigma dA` of the frustum (torque of a unit swirl traction).
    pub fn moment_area(&self) -> f64 {
        let (p, q) = (self.a[1], self.b[1]);
        2.0 * PI * self.length() * (p * p + p * q + q * q) / 3.0
    }
}

/// Local element size as a function of position.
#[derive(Debug, Clone, PartialEq)]
pub struct Sizing {
    pub h0: f64,
    pub growth: f64,
    pub h_max: f64,
    /// Axial extent of the body `(tail, nose)`.
    pub body_x: (f64, f64),
    /// Refinement points and their local size.
    pub corners: Vec<([f64; 2], f64)>,
}

impl Sizing {
    pub fn at(&self, p: [f64; 2]) -> f64 {
        let dx = (self.body_x.0 - p[0]).max(p[0] - self.body_x.1).max(0.0);
        let mut h = (self.h0 + self.growth * dx).min(self.h_max);
        for &(c, hc) in &self.corners {
            h = h.min(hc + self.growth * (p[0] - c[0]).hypot(p[1] - c[1]));
        }
        h
    }
}

/// A piece of the surface that cannot be cut into elements.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum MeshError {
    /// The sizing asked for an element of this (non-finite or non-positive) size.
    #[error("element size {0} along a piece")]
    ElementSize(f64),
    /// The piece needs more elements than this bound.
    #[error("more than {0} elements on one piece of the surface")]
    TooManyElements(usize),
}

/// Elements along one piece; `max_elements` guards against a runaway size.
pub fn discretize(
    piece: &Piece,
    sizing: &Sizing,
    part: Part,
    max_elements: usize,
) -> Result<Vec<Element>, MeshError> {
    let mut ts = vec![0.0];
    let mut t = 0.0;
    while t < 1.0 {
        let speed = piece.speed(t).max(1e-300);
        let dt = sizing.at(piece.point(t)) / speed;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(MeshError::ElementSize(dt));
        }
        t += dt;
        ts.push(t);
        if ts.len() > max_elements + 1 {
            return Err(MeshError::TooManyElements(max_elements));
        }
    }
    // Rescale so the last node is the piece's end; at least two elements
    // so that every piece has an interior node.
    if ts.len() < 3 {
        ts = vec![0.0, 0.5, 1.0];
    }
    let scale = *ts.last().unwrap_or(&1.0);
    let nodes: Vec<[f64; 2]> = ts.iter().map(|t| piece.point(t / scale)).collect();
    Ok(nodes
        .windows(2)
        .map(|w| Element {
            a: w[0],
            b: w[1],
            part,
        })
        .collect())
}
