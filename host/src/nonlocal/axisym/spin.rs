//! A rotor spinning about the axis beside a stationary body of revolution
//! (the stator), both on the axis of a tube: the rotor's axial rotational
//! drag and the torques its swirl puts on the stator and the wall. The
//! robot's coupler is such a rotor: a 6 x 10 mm cylinder on the motor's
//! shaft, turning with the tail, its top face a small gap below the
//! body's seal (paper, Table I and Fig. 1).
//!
//! Only the azimuthal (swirl) problem of [`super::solve`] is posed: a
//! first-kind single layer of ring Stokeslets on the rotor, the stator and
//! the tube (wall and caps), `u_phi = Omega sigma` on the rotor and `0` on
//! every other surface. The rotor sits below the stator (at `-x`), its top
//! face `gap_m` from the stator's tail end. The swirl single layer has no
//! null vector (the pressure one, `f = p n`, has no azimuthal part), so a
//! closed stator needs no special treatment.
//!
//! The mesh sizes elements by the smaller of the rotor's radius and the
//! gap, so the gap is resolved across; the corner of a rotating face
//! abutting a stationary one is singular (the swirl jumps from `Omega a`
//! to 0 at a point: the torque diverges like `ln(1 / gap)` and then some),
//! so a gap below [`MIN_GAP_OVER_RADIUS`] of the rotor's radius is
//! refused rather than solved with a number that does not converge.
//!
//! In a closed tube the torques on all boundaries sum to zero (the fluid's
//! angular momentum is steady); [`SpinSolve::torque_balance`] measures the
//! discrete violation.
//!
//! References: C. Pozrikidis, *Boundary Integral and Singularity Methods
//! for Linearized Viscous Flow* (1992), §2.4 (the swirl ring kernel) and
//! §7.2; Tabak & Yesilyurt, *In-channel vertical swimming* (the coupler,
//! Table I).

use super::mesh::{discretize, Element, Part, Sizing};
use super::quadrature::{over_element, over_own_element};
use super::{AxisymSettings, Confinement};
use crate::nonlocal::{linalg, NonlocalError};
use crate::physics::profile::BodyProfile;
use nalgebra::DMatrix;
use rayon::prelude::*;
use std::f64::consts::PI;

/// The smallest gap between rotor and stator, as a fraction of the
/// rotor's largest radius (0.15 mm for the 6 mm coupler). The convergence
/// table at this gap is in docs/physics.md, section 4.
pub const MIN_GAP_OVER_RADIUS: f64 = 0.05;

/// Rotor below a stator with a gap, on the axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Stack {
    pub rotor: BodyProfile,
    /// The stationary body above the rotor, if any.
    pub stator: Option<BodyProfile>,
    /// Axial distance from the rotor's top face to the stator's tail (m).
    pub gap_m: f64,
}

/// The result of one swirl solve, per unit rotor rate.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SpinSolve {
    /// Torque the fluid exerts against the rotor per unit rate (N m s).
    pub rotational_drag_n_m_s: f64,
    /// Torque the fluid exerts on the stator along the rotor's rotation
    /// (N m s per rad/s of the rotor): the coupling a rotor's swirl puts
    /// on the body.
    pub stator_torque_n_m_s: f64,
    /// The same on the tube wall and caps.
    pub wall_torque_n_m_s: f64,
    pub rotor_elements: usize,
    pub stator_elements: usize,
    pub wall_elements: usize,
    pub seconds: f64,
}

impl SpinSolve {
    /// `|T_rotor - T_stator - T_wall| / T_rotor`: zero in a closed tube.
    pub fn torque_balance(&self) -> f64 {
        (self.rotational_drag_n_m_s - self.stator_torque_n_m_s - self.wall_torque_n_m_s).abs()
            / self.rotational_drag_n_m_s
    }
}

/// Which surface an element lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Surface {
    Rotor,
    Stator,
    Wall,
}

fn geometry(msg: String) -> NonlocalError {
    NonlocalError::Geometry(msg)
}

/// Rotational drag of the stack's rotor, the stator centred at `centre_m`
/// (the rotor centred there if there is no stator), in `confinement`.
pub fn solve_spin(
    stack: &Stack,
    confinement: &Confinement,
    centre_m: f64,
    mu_pa_s: f64,
    s: &AxisymSettings,
) -> Result<SpinSolve, NonlocalError> {
    if !(mu_pa_s.is_finite() && mu_pa_s > 0.0) {
        return Err(geometry(format!(
            "viscosity must be positive and finite, got {mu_pa_s} Pa s"
        )));
    }
    let start = std::time::Instant::now();
    let (els, kinds) = build(stack, confinement, centre_m, s)?;
    let n = els.len();
    super::solve::within_dense_limit(n, 2 * 8 * n * n, "the swirl solve", s)?;
    let rows: Vec<Vec<f64>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let t = els[i].mid();
            (0..n)
                .map(|j| {
                    let k = if i == j {
                        over_own_element(&els[j])
                    } else {
                        over_element(t, &els[j])
                    };
                    k.pp / (8.0 * PI)
                })
                .collect()
        })
        .collect();
    let a = DMatrix::from_fn(n, n, |r, c| rows[r][c]);
    drop(rows);
    let rhs = DMatrix::from_fn(n, 1, |r, _| {
        if kinds[r] == Surface::Rotor {
            els[r].mid()[1]
        } else {
            0.0
        }
    });
    let f = linalg::solve(a, &rhs)?;
    let torque_on = |which: Surface| -> f64 {
        (0..n)
            .filter(|&j| kinds[j] == which)
            .map(|j| f[(j, 0)] * els[j].moment_area())
            .sum::<f64>()
            * mu_pa_s
    };
    let count = |which: Surface| kinds.iter().filter(|k| **k == which).count();
    // The layer's density is the force the boundary exerts on the fluid:
    // the rotor's drag is its own sum, the others feel minus theirs.
    Ok(SpinSolve {
        rotational_drag_n_m_s: torque_on(Surface::Rotor),
        stator_torque_n_m_s: -torque_on(Surface::Stator),
        wall_torque_n_m_s: -torque_on(Surface::Wall),
        rotor_elements: count(Surface::Rotor),
        stator_elements: count(Surface::Stator),
        wall_elements: count(Surface::Wall),
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Check the geometry and mesh rotor, stator and tube.
fn build(
    stack: &Stack,
    confinement: &Confinement,
    centre_m: f64,
    s: &AxisymSettings,
) -> Result<(Vec<Element>, Vec<Surface>), NonlocalError> {
    stack.rotor.validate()?;
    if let Some(st) = &stack.stator {
        st.validate()?;
    }
    super::solve::check_settings(s)?;
    let a_rotor = 0.5e-3 * stack.rotor.max_diameter_mm();
    let rotor_len = 1e-3 * stack.rotor.length_mm();
    let min_gap = MIN_GAP_OVER_RADIUS * a_rotor;
    if stack.stator.is_some() && !(stack.gap_m.is_finite() && stack.gap_m >= min_gap * (1.0 - 1e-9))
    {
        return Err(geometry(format!(
            "gap between rotor and stator {} mm is below the limit of {} mm ({MIN_GAP_OVER_RADIUS} rotor radii): the rotating/stationary corner is singular",
            1e3 * stack.gap_m,
            1e3 * min_gap
        )));
    }
    if !centre_m.is_finite() {
        return Err(geometry(format!("position {centre_m} m")));
    }
    let (rotor_centre, stator_tail) = match &stack.stator {
        Some(st) => {
            let tail = centre_m - 0.5e-3 * st.length_mm();
            (tail - stack.gap_m - 0.5 * rotor_len, tail)
        }
        None => (centre_m, centre_m + 0.5 * rotor_len),
    };
    let rotor_bottom = rotor_centre - 0.5 * rotor_len;
    let top = match &stack.stator {
        Some(st) => centre_m + 0.5e-3 * st.length_mm(),
        None => stator_tail,
    };
    let a_max = stack
        .stator
        .as_ref()
        .map_or(a_rotor, |st| a_rotor.max(0.5e-3 * st.max_diameter_mm()));
    let near = if stack.stator.is_some() {
        a_rotor.min(stack.gap_m)
    } else {
        a_rotor
    };
    let mut h0 = near / s.resolution;
    let mut h_max = 2.0 * a_max;
    let mut wall_pieces = Vec::new();
    let mut corners = Vec::new();
    if let Some((radius, length, closed)) = confinement.tube() {
        let (lo, hi) = (-0.5 * length, 0.5 * length);
        if !(radius.is_finite() && radius > a_max && length.is_finite()) {
            return Err(geometry(format!(
                "rotor and stator (largest diameter {} mm) do not fit in the {} mm tube",
                2e3 * a_max,
                2e3 * radius
            )));
        }
        if rotor_bottom <= lo || top >= hi {
            return Err(geometry(format!(
                "rotor and stator ({} to {} mm) do not fit between the tube ends at +-{} mm",
                1e3 * rotor_bottom,
                1e3 * top,
                1e3 * hi
            )));
        }
        h0 = h0.min((radius - a_max) / s.resolution);
        h_max = if closed { 0.5 * radius } else { 0.25 * radius };
        super::solve::tube_wall(lo, hi, radius, closed, h0, &mut corners, &mut wall_pieces);
    }
    let rotor = stack.rotor.meridian(rotor_centre);
    let stator = stack.stator.as_ref().map(|st| st.meridian(centre_m));
    for c in rotor
        .corners
        .iter()
        .chain(stator.iter().flat_map(|m| m.corners.iter()))
    {
        corners.push((*c, 0.25 * h0));
    }
    let sizing = Sizing {
        h0,
        growth: s.growth,
        h_max,
        body_x: (rotor_bottom, stator_tail),
        corners,
    };
    let mut els = Vec::new();
    let mut kinds = Vec::new();
    let groups = [
        (rotor.pieces, Surface::Rotor),
        (
            stator.map(|m| m.pieces).unwrap_or_default(),
            Surface::Stator,
        ),
        (wall_pieces, Surface::Wall),
    ];
    for (pieces, kind) in groups {
        let part = if kind == Surface::Rotor {
            Part::Body
        } else {
            Part::Wall
        };
        for p in &pieces {
            let e = discretize(p, &sizing, part, s.max_elements)?;
            kinds.extend(std::iter::repeat_n(kind, e.len()));
            els.extend(e);
            if els.len() > s.max_elements {
                return Err(NonlocalError::Settings(format!(
                    "the mesh needs more than {} elements; lower the resolution",
                    s.max_elements
                )));
            }
        }
    }
    Ok((els, kinds))
}
