//! Public entry points with the body, in free space, and the old tail in
//! a channel wall of regularized Stokeslets (`tail_resistance_in_channel`,
//! kept only as the contrast that shows the leak; `super::tube` is the
//! leak-free wall).

use super::curve::Centreline;
use super::mrs_line::LineSources;
use super::robot::{grand_resistance, Object, Surface};
use super::surface::{self, SurfacePoints};
use super::{validate_helix, NonlocalError, NonlocalSettings};
use crate::physics::geometry::{Body, Channel, Helix};
use nalgebra::{Matrix6, SMatrix};

/// Resistance of body and tail as two rigid bodies: the load on the body is
/// `-(body_body V_b + body_tail V_t)`, on the tail `-(tail_body V_b +
/// tail_tail V_t)`, all about the origin (body centre).
///
/// The robot moving as one rigid body has `rigid()`; the tail spinning at
/// `omega` relative to the body is `V_t = V_b + [0; omega e_x]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RobotResistance {
    pub body_body: Matrix6<f64>,
    pub body_tail: Matrix6<f64>,
    pub tail_body: Matrix6<f64>,
    pub tail_tail: Matrix6<f64>,
}

impl RobotResistance {
    /// The whole robot translating and rotating rigidly.
    pub fn rigid(&self) -> Matrix6<f64> {
        self.body_body + self.body_tail + self.tail_body + self.tail_tail
    }

    /// The 12x12 grand resistance matrix, unknowns ordered `[V_b; V_t]`.
    pub fn grand(&self) -> SMatrix<f64, 12, 12> {
        let mut g = SMatrix::<f64, 12, 12>::zeros();
        g.fixed_view_mut::<6, 6>(0, 0).copy_from(&self.body_body);
        g.fixed_view_mut::<6, 6>(0, 6).copy_from(&self.body_tail);
        g.fixed_view_mut::<6, 6>(6, 0).copy_from(&self.tail_body);
        g.fixed_view_mut::<6, 6>(6, 6).copy_from(&self.tail_tail);
        g
    }
}

fn check_mu(mu: f64) -> Result<(), NonlocalError> {
    if mu.is_finite() && mu > 0.0 {
        Ok(())
    } else {
        Err(NonlocalError::Settings(format!(
            "viscosity must be positive, got {mu} Pa s"
        )))
    }
}

fn tail_object(helix: &Helix, settings: &NonlocalSettings) -> Object {
    let n = settings.tail_segments(helix);
    let blob = settings.blob_over_wire_radius * 0.5 * helix.wire_diameter_m;
    Object::Line(LineSources::new(Centreline::Helix(*helix), n, blob))
}

fn body_object(body: &Body, settings: &NonlocalSettings) -> Result<Object, NonlocalError> {
    if !(body.length_m > 0.0
        && body.diameter_m > 0.0
        && body.length_m.is_finite()
        && body.diameter_m.is_finite())
    {
        return Err(NonlocalError::Geometry(format!(
            "body length and diameter must be positive, got {} m and {} m",
            body.length_m, body.diameter_m
        )));
    }
    let h = settings.body_spacing_m;
    let pts = surface::spheroid(0.0, 0.5 * body.length_m, body.radius_m(), h);
    Ok(surface_object(pts, settings))
}

fn surface_object(points: SurfacePoints, settings: &NonlocalSettings) -> Object {
    let blob_m = settings.surface_blob_over_spacing * points.spacing_m();
    Object::Surface(Surface { points, blob_m })
}

/// The still channel wall around the axial extent `[x_min, x_max]` of the
/// robot, closed by end caps if the channel is closed.
fn wall_object(
    channel: &Channel,
    x_min: f64,
    x_max: f64,
    radial_extent_m: f64,
    settings: &NonlocalSettings,
) -> Result<Object, NonlocalError> {
    let r = channel.radius_m();
    if !(r.is_finite() && r > 0.0) {
        return Err(NonlocalError::Geometry(format!(
            "channel diameter must be positive, got {} m",
            channel.diameter_m
        )));
    }
    if radial_extent_m + 0.5 * settings.wall_spacing_m >= r {
        return Err(NonlocalError::Geometry(format!(
            "object of radius {:.2} mm does not fit in the {:.2} mm channel at wall spacing {:.2} mm",
            radial_extent_m * 1e3,
            r * 1e3,
            settings.wall_spacing_m * 1e3
        )));
    }
    let margin = settings.tube_end_margin_over_radius * r;
    let pts = surface::tube(
        r,
        x_min - margin,
        x_max + margin,
        settings.wall_spacing_m,
        channel.closed,
    );
    Ok(surface_object(pts, settings))
}

fn helix_x_range(h: &Helix) -> (f64, f64) {
    (
        h.joint_x_m - h.axial_length_m - h.wire_diameter_m,
        h.joint_x_m + h.wire_diameter_m,
    )
}

/// The tail alone inside the channel (wall of regularized Stokeslets).
pub fn tail_resistance_in_channel(
    helix: &Helix,
    channel: &Channel,
    viscosity_pa_s: f64,
    settings: &NonlocalSettings,
) -> Result<Matrix6<f64>, NonlocalError> {
    validate_helix(helix)?;
    settings.validate()?;
    check_mu(viscosity_pa_s)?;
    let (x0, x1) = helix_x_range(helix);
    let wall = wall_object(channel, x0, x1, helix.envelope_radius_m(), settings)?;
    super::linalg::check_memory(settings.tail_segments(helix))?;
    let b = grand_resistance(&[tail_object(helix, settings)], &[wall], viscosity_pa_s)?;
    Ok(with_spin(b[0][0], helix, viscosity_pa_s, settings))
}

/// The body (prolate spheroid surface of regularized Stokeslets) alone in
/// free space. In a tube use `super::axisym::solve_body` (exact, leak-free)
/// or `super::tube::robot_resistance_in_tube`: the wall of regularized
/// Stokeslets this function once accepted leaked 30-65 % of the confinement
/// and is retired.
pub fn free_body_resistance(
    body: &Body,
    viscosity_pa_s: f64,
    settings: &NonlocalSettings,
) -> Result<Matrix6<f64>, NonlocalError> {
    settings.validate()?;
    check_mu(viscosity_pa_s)?;
    let b = body_object(body, settings)?;
    Ok(grand_resistance(&[b], &[], viscosity_pa_s)?[0][0])
}

/// Body and tail together in free space, with their hydrodynamic
/// interaction (in the tube: `super::tube::robot_resistance_in_tube`). The
/// helix must lie behind the body: `joint_x_m <= -body.length_m / 2 - wire
/// radius`.
pub fn robot_resistance(
    body: &Body,
    helix: &Helix,
    viscosity_pa_s: f64,
    settings: &NonlocalSettings,
) -> Result<RobotResistance, NonlocalError> {
    validate_helix(helix)?;
    settings.validate()?;
    check_mu(viscosity_pa_s)?;
    let rear = -0.5 * body.length_m;
    if helix.joint_x_m > rear - 0.5 * helix.wire_diameter_m {
        return Err(NonlocalError::Geometry(format!(
            "tail joint at x = {:.2} mm overlaps the body, whose rear end is at {:.2} mm",
            helix.joint_x_m * 1e3,
            rear * 1e3
        )));
    }
    super::linalg::check_memory(settings.tail_segments(helix))?;
    let moving = [body_object(body, settings)?, tail_object(helix, settings)];
    let b = grand_resistance(&moving, &[], viscosity_pa_s)?;
    Ok(RobotResistance {
        body_body: b[0][0],
        body_tail: b[0][1],
        tail_body: b[1][0],
        tail_tail: with_spin(b[1][1], helix, viscosity_pa_s, settings),
    })
}

fn with_spin(
    mut b: Matrix6<f64>,
    helix: &Helix,
    mu: f64,
    settings: &NonlocalSettings,
) -> Matrix6<f64> {
    if settings.wire_spin {
        let seg =
            super::curve::Segments::new(Centreline::Helix(*helix), settings.tail_segments(helix));
        super::sbt::add_wire_spin(&mut b, &seg, 0.5 * helix.wire_diameter_m, mu);
    }
    b
}
