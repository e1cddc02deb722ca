//! The helical tail (and, for checks, a sphere or the whole robot) coaxial
//! in the circular tube, with a wall that cannot leak.
//!
//! # Why a new wall
//! The wall of `super::confined` is a surface of regularized Stokeslets ON
//! the wall. Between its points the velocity is not zero, so the pressure
//! difference that a closed tube builds across a translating tail drives
//! oil through the wall instead of back through the gap: measured here, the
//! net flux through a cross-section of the closed tube is 16-27 % of the
//! piston flux for the paper's tails (MFS: below 1 %) where it must vanish
//! (`docs/tail-in-tube.md`).
//!
//! # Method: the method of fundamental solutions (MFS), [`wall`], [`mfs`]
//! Singular Stokeslets outside the fluid, one per wall collocation point,
//! pushed out along the normal by `source_offset_over_spacing` times the
//! wall spacing; zero velocity collocated on the cylinder and on flat end
//! caps `cap_margin_over_radius * R` beyond the object (closed tube; an open
//! tube has no caps). The tail stays the regularized-Stokeslet centre-line
//! of `super::mrs_line` (validated in free space), the sphere and body the
//! surfaces of `super::surface`. Chosen over the Liron & Shahar (1978) pipe
//! Green's function because it treats the closed ends, the open tube and
//! several bodies alike; chosen over a boundary-element wall because the
//! tube is smooth and far (several wire spacings) from the tail, where MFS
//! converges exponentially.
//!
//! # Solver: the wall's rotational symmetry, [`rings`]
//! Every ring of wall points has the same number of equal stations, so in
//! each point's cylindrical frame the wall-wall matrix is block-circulant:
//! a discrete Fourier transform in the station index splits it into
//! independent small systems, one per azimuthal mode, and the moving
//! objects are coupled through a dense Schur complement. The forces equal
//! the dense LU's ([`mfs::solve_dense`], kept as the reference) to
//! round-off; memory and time are known from the counts before anything
//! is built ([`budget`]).
//!
//! # Diagnostics, [`diagnostics`]
//! Net flux through cross-sections and the wall velocity between
//! collocation points are returned with every matrix.
//!
//! # Conventions
//! As `super`: `F = -B V`, `V = [U; Omega]`, torques about the origin of the
//! swimmer frame, wire spin about the centre-line added as in free space.
//!
//! References: Fairweather & Karageorghis, Adv. Comput. Math. 9 (1998) 69;
//! Young et al., J. Comput. Phys. 211 (2006) 1; Haberman & Sayre, David
//! Taylor Model Basin Report 1143 (1958); Liron & Shahar, J. Fluid Mech. 86
//! (1978) 727.
pub mod budget;
pub mod diagnostics;
pub mod mfs;
pub mod rings;
pub mod settings;
pub mod wall;

use super::confined::RobotResistance;
use super::curve::{Centreline, Segments};
use super::mrs_line::LineSources;
use super::robot::{Object, Surface};
use super::{surface, validate_helix, NonlocalError, NonlocalSettings};
use crate::physics::geometry::{Body, Channel, Helix};
pub use diagnostics::Diagnostics;
use nalgebra::Matrix6;
pub use settings::{TubeSettings, WallModel, WallSolver, DEFAULT_MAX_PEAK_BYTES};
pub use wall::CapLayout;
use wall::Wall;

/// A resistance matrix with the leak diagnostics of its solve.
#[derive(Debug, Clone, PartialEq)]
pub struct TubeResistance {
    pub matrix: Matrix6<f64>,
    pub diagnostics: Diagnostics,
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

/// Radius and axial extent `(R, x0, x1)` of the wall around objects
/// spanning `[x_min, x_max]` and reaching `radial_m` from the axis. Caps
/// `margin` beyond the objects, nearer if the channel is shorter (the
/// objects then sit in its middle).
fn wall_extent(
    channel: &Channel,
    x_min: f64,
    x_max: f64,
    radial_m: f64,
    s: &TubeSettings,
) -> Result<(f64, f64, f64), NonlocalError> {
    let r = channel.radius_m();
    if !(r.is_finite() && r > 0.0) {
        return Err(NonlocalError::Geometry(format!(
            "channel diameter must be positive and finite, got {} m",
            channel.diameter_m
        )));
    }
    if radial_m >= r {
        return Err(NonlocalError::Geometry(format!(
            "object of radius {:.3} mm does not fit in the channel of radius {:.3} mm",
            radial_m * 1e3,
            r * 1e3
        )));
    }
    // The wall cannot resolve a gap narrower than its own spacing (and the
    // regularized tail would overlap it): refuse rather than predict.
    if r - radial_m < s.wall_spacing_m {
        return Err(NonlocalError::Geometry(format!(
            "the gap of {:.3} mm between the object (radius {:.3} mm) and the wall (radius {:.3} mm) is narrower than the wall spacing {:.3} mm, which cannot resolve it (a finer wall is `swimbot helix --wall-spacing-mm`; the model presets use the default spacing)",
            (r - radial_m) * 1e3,
            radial_m * 1e3,
            r * 1e3,
            s.wall_spacing_m * 1e3
        )));
    }
    let mut margin = s.cap_margin_over_radius * r;
    let len = x_max - x_min;
    if channel.length_m.is_finite() && channel.length_m > 0.0 {
        if channel.length_m <= len {
            return Err(NonlocalError::Geometry(format!(
                "object of length {:.2} mm does not fit in the channel of length {:.2} mm",
                len * 1e3,
                channel.length_m * 1e3
            )));
        }
        margin = margin.min(0.5 * (channel.length_m - len));
    } else if !channel.length_m.is_infinite() {
        return Err(NonlocalError::Geometry(format!(
            "channel length must be positive, got {} m",
            channel.length_m
        )));
    }
    Ok((r, x_min - margin, x_max + margin))
}

/// The wall of [`wall_extent`].
fn wall_for(
    channel: &Channel,
    x_min: f64,
    x_max: f64,
    radial_m: f64,
    s: &TubeSettings,
) -> Result<Wall, NonlocalError> {
    let (r, x0, x1) = wall_extent(channel, x_min, x_max, radial_m, s)?;
    Ok(match s.wall {
        WallModel::Mfs => Wall::mfs(
            r,
            (x0, x1),
            s.wall_spacing_m,
            s.source_offset_over_spacing,
            channel.closed.then_some(s.caps),
        ),
        WallModel::Leaky => Wall::leaky(
            r,
            (x0, x1),
            s.wall_spacing_m,
            s.tail.surface_blob_over_spacing,
            channel.closed,
        ),
    })
}

/// Solve with the chosen solver.
fn solve<'a>(
    moving: &'a [Object],
    wall: &'a Wall,
    viscosity_pa_s: f64,
    s: &TubeSettings,
) -> Result<mfs::Solution<'a>, NonlocalError> {
    match s.solver {
        WallSolver::Rings => rings::solve(moving, wall, viscosity_pa_s, s.max_peak_bytes),
        WallSolver::Dense => mfs::solve_dense(moving, wall, viscosity_pa_s, s.max_peak_bytes),
    }
}

fn tail_object(helix: &Helix, s: &NonlocalSettings) -> Object {
    let blob = s.blob_over_wire_radius * 0.5 * helix.wire_diameter_m;
    Object::Line(LineSources::new(
        Centreline::Helix(*helix),
        s.tail_segments(helix),
        blob,
    ))
}

fn surface_object(points: surface::SurfacePoints, s: &NonlocalSettings) -> Object {
    let blob_m = s.surface_blob_over_spacing * points.spacing_m();
    Object::Surface(Surface { points, blob_m })
}

fn helix_x_range(h: &Helix) -> (f64, f64) {
    (
        h.joint_x_m - h.axial_length_m - h.wire_diameter_m,
        h.joint_x_m + h.wire_diameter_m,
    )
}

/// Sections between each cap and the objects, and through their middle.
fn sections(wall: &Wall, x_min: f64, x_max: f64) -> [f64; 3] {
    [
        0.5 * (wall.x0_m + x_min),
        0.5 * (x_min + x_max),
        0.5 * (x_max + wall.x1_m),
    ]
}

fn add_spin(b: &mut Matrix6<f64>, helix: &Helix, mu: f64, s: &NonlocalSettings) {
    if s.wire_spin {
        let seg = Segments::new(Centreline::Helix(*helix), s.tail_segments(helix));
        super::sbt::add_wire_spin(b, &seg, 0.5 * helix.wire_diameter_m, mu);
    }
}

/// Counts and peak memory of the tail-in-tube solve, from the geometry
/// alone: nothing proportional to the wall is built, so absurd tubes are
/// refused before they cost anything.
pub fn tail_in_tube_budget(
    helix: &Helix,
    channel: &Channel,
    settings: &TubeSettings,
) -> Result<budget::Budget, NonlocalError> {
    validate_helix(helix)?;
    settings.validate()?;
    let (x0, x1) = helix_x_range(helix);
    let (r, x0, x1) = wall_extent(channel, x0, x1, helix.envelope_radius_m(), settings)?;
    let n_tail = settings.tail.tail_segments(helix);
    let n_tail = if n_tail < budget::MAX_COUNTED {
        tail_object(helix, &settings.tail).len()
    } else {
        n_tail
    };
    Ok(budget::Budget::new(
        n_tail,
        &budget::WallCounts::of(r, (x0, x1), channel.closed, settings),
        settings.solver,
    ))
}

/// The rigid tail alone, coaxial in the tube: its 6x6 resistance and the
/// leak diagnostics (rotation speeds referred to the envelope radius).
pub fn tail_resistance_in_tube(
    helix: &Helix,
    channel: &Channel,
    viscosity_pa_s: f64,
    settings: &TubeSettings,
) -> Result<TubeResistance, NonlocalError> {
    validate_helix(helix)?;
    settings.validate()?;
    check_mu(viscosity_pa_s)?;
    let (x0, x1) = helix_x_range(helix);
    let wall = wall_for(channel, x0, x1, helix.envelope_radius_m(), settings)?;
    let moving = [tail_object(helix, &settings.tail)];
    let sol = solve(&moving, &wall, viscosity_pa_s, settings)?;
    let mut matrix = sol.block(0, 0);
    add_spin(&mut matrix, helix, viscosity_pa_s, &settings.tail);
    let diagnostics =
        diagnostics::diagnose(&sol, 0, &sections(&wall, x0, x1), helix.envelope_radius_m());
    Ok(TubeResistance {
        matrix,
        diagnostics,
    })
}

/// The rigid tail's 6x6 in the tube without the leak diagnostics, which
/// cost as much as the solve: for models that re-solve many perturbed
/// geometries (uncertainty bands) once [`tail_resistance_in_tube`] has
/// shown the wall tight at the same settings.
pub fn tail_matrix_in_tube(
    helix: &Helix,
    channel: &Channel,
    viscosity_pa_s: f64,
    settings: &TubeSettings,
) -> Result<Matrix6<f64>, NonlocalError> {
    validate_helix(helix)?;
    settings.validate()?;
    check_mu(viscosity_pa_s)?;
    let (x0, x1) = helix_x_range(helix);
    let wall = wall_for(channel, x0, x1, helix.envelope_radius_m(), settings)?;
    let moving = [tail_object(helix, &settings.tail)];
    let mut matrix = solve(&moving, &wall, viscosity_pa_s, settings)?.block(0, 0);
    add_spin(&mut matrix, helix, viscosity_pa_s, &settings.tail);
    Ok(matrix)
}

/// A sphere of radius `radius_m` (regularized Stokeslets `spacing_m`
/// apart) centred on the tube axis at the origin: the Haberman & Sayre
/// check of the wall.
pub fn sphere_resistance_in_tube(
    radius_m: f64,
    spacing_m: f64,
    channel: &Channel,
    viscosity_pa_s: f64,
    settings: &TubeSettings,
) -> Result<TubeResistance, NonlocalError> {
    settings.validate()?;
    check_mu(viscosity_pa_s)?;
    if !(radius_m > 0.0 && spacing_m > 0.0 && spacing_m < radius_m) {
        return Err(NonlocalError::Geometry(format!(
            "sphere radius {radius_m} m and spacing {spacing_m} m must be positive, spacing smaller"
        )));
    }
    let wall = wall_for(channel, -radius_m, radius_m, radius_m, settings)?;
    let pts = surface::spheroid(0.0, radius_m, radius_m, spacing_m);
    let moving = [surface_object(pts, &settings.tail)];
    let sol = solve(&moving, &wall, viscosity_pa_s, settings)?;
    let diagnostics =
        diagnostics::diagnose(&sol, 0, &sections(&wall, -radius_m, radius_m), radius_m);
    Ok(TubeResistance {
        matrix: sol.block(0, 0),
        diagnostics,
    })
}

/// Body (prolate spheroid centred at the origin) and tail together in the
/// tube, with their hydrodynamic interaction; diagnostics of the tail's
/// motions. The helix must lie behind the body.
pub fn robot_resistance_in_tube(
    body: &Body,
    helix: &Helix,
    channel: &Channel,
    viscosity_pa_s: f64,
    settings: &TubeSettings,
) -> Result<(RobotResistance, Diagnostics), NonlocalError> {
    validate_helix(helix)?;
    settings.validate()?;
    check_mu(viscosity_pa_s)?;
    let rear = -0.5 * body.length_m;
    if !(body.length_m > 0.0 && body.diameter_m > 0.0) {
        return Err(NonlocalError::Geometry(format!(
            "body length and diameter must be positive, got {} m and {} m",
            body.length_m, body.diameter_m
        )));
    }
    if helix.joint_x_m > rear - 0.5 * helix.wire_diameter_m {
        return Err(NonlocalError::Geometry(format!(
            "tail joint at x = {:.2} mm overlaps the body, whose rear end is at {:.2} mm",
            helix.joint_x_m * 1e3,
            rear * 1e3
        )));
    }
    let (x0, _) = helix_x_range(helix);
    let radial = body.radius_m().max(helix.envelope_radius_m());
    let wall = wall_for(channel, x0, -rear, radial, settings)?;
    let pts = surface::spheroid(
        0.0,
        0.5 * body.length_m,
        body.radius_m(),
        settings.tail.body_spacing_m,
    );
    let moving = [
        surface_object(pts, &settings.tail),
        tail_object(helix, &settings.tail),
    ];
    let sol = solve(&moving, &wall, viscosity_pa_s, settings)?;
    let mut tail_tail = sol.block(1, 1);
    add_spin(&mut tail_tail, helix, viscosity_pa_s, &settings.tail);
    let r = RobotResistance {
        body_body: sol.block(0, 0),
        body_tail: sol.block(0, 1),
        tail_body: sol.block(1, 0),
        tail_tail,
    };
    let diag = diagnostics::diagnose(
        &sol,
        1,
        &sections(&wall, x0, -rear),
        helix.envelope_radius_m(),
    );
    Ok((r, diag))
}
