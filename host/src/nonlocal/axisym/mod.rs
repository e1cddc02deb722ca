//! Exact axisymmetric Stokes flow past a body of revolution on the axis of
//! a circular tube: the body's axial drag and axial rotational drag by a
//! boundary-integral method with ring Stokeslets.
//!
//! The flow is represented by a first-kind single layer of ring Stokeslets
//! on every boundary: the body's surface, the tube wall and, for a closed
//! tube, its flat end caps. The no-slip condition holds on all of them, so
//! no fluid crosses the wall: the closed tube's displaced oil must return
//! through the gap (zero net flux), unlike a wall of free-space regularized
//! Stokeslets, which is porous (`crate::nonlocal::surface`). Axial
//! translation is the meridional problem (axial and radial tractions),
//! axial rotation the azimuthal (swirl) problem; both are exact for the
//! axisymmetric geometry up to discretisation.
//!
//! * [`elliptic`]: `K`, `E` by the arithmetic-geometric mean;
//! * [`kernels`]: the ring kernels (closed forms near the ring, periodic
//!   trapezoidal rule away from it);
//! * [`quadrature`]: element integrals with the logarithmic singularity;
//! * [`mesh`]: elements on the generating curves, graded to corners;
//! * [`solve`]: assembly, dense LU (faer), drag, torque, flux diagnostic;
//! * [`spin`]: a rotor spinning beside a stationary body (the coupler below
//!   the seal): the swirl problem alone, with the torques on every surface.
//!
//! Confinement: free space; a closed tube (length, flat caps); an open
//! tube (same wall, no caps: a thin pipe of that length in unbounded fluid
//! at rest far away). The body sits at a given axial position (default the
//! tube's centre).
//!
//! # Checks (`tests/axisym.rs`, `docs/body-in-tube.md`)
//! Sphere vs Stokes, spheroids vs Chwang & Wu (1975), sphere on a tube axis
//! vs Haberman & Sayre (1958) / Bohlin (1960), long cylinders vs the
//! annular Couette-Poiseuille and Couette closed forms, mass conservation.
//!
//! # Memory
//! [`solve::dense_bytes`] is estimated before assembly and refused above
//! [`AxisymSettings::max_dense_bytes`] (default [`MAX_DENSE_BYTES`],
//! 1 GB: about 5 000 elements, far beyond any converged setting here).
//!
//! References: C. Pozrikidis, *Boundary Integral and Singularity Methods
//! for Linearized Viscous Flow* (Cambridge, 1992); A. T. Chwang &
//! T. Y.-T. Wu, J. Fluid Mech. 67 (1975) 787; W. L. Haberman &
//! R. M. Sayre, David Taylor Model Basin Report 1143 (1958); T. Bohlin,
//! Trans. R. Inst. Technol. Stockholm 155 (1960).

pub mod elliptic;
pub mod kernels;
pub mod mesh;
pub mod quadrature;
pub mod solve;
pub mod spin;

use super::NonlocalError;
use crate::physics::profile::BodyProfile;

/// Default memory limit of the dense solve (bytes).
pub const MAX_DENSE_BYTES: usize = 1_000_000_000;

/// The boundary around the body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Confinement {
    Free,
    /// Tube with flat end caps: zero net flux through every section.
    Closed {
        diameter_m: f64,
        length_m: f64,
    },
    /// Tube without caps, in unbounded fluid.
    Open {
        diameter_m: f64,
        length_m: f64,
    },
}

impl Confinement {
    /// `(radius, length, closed)` of the tube, if any.
    pub fn tube(&self) -> Option<(f64, f64, bool)> {
        match *self {
            Confinement::Free => None,
            Confinement::Closed {
                diameter_m,
                length_m,
            } => Some((0.5 * diameter_m, length_m, true)),
            Confinement::Open {
                diameter_m,
                length_m,
            } => Some((0.5 * diameter_m, length_m, false)),
        }
    }

    /// The case's channel.
    pub fn of_channel(c: &crate::physics::geometry::Channel) -> Self {
        if c.closed {
            Confinement::Closed {
                diameter_m: c.diameter_m,
                length_m: c.length_m,
            }
        } else {
            Confinement::Open {
                diameter_m: c.diameter_m,
                length_m: c.length_m,
            }
        }
    }
}

/// Discretisation settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisymSettings {
    /// Elements across the smaller of the body's largest radius and the
    /// gap to the wall: the element size beside the body.
    pub resolution: f64,
    /// Linear growth rate of the element size away from the body and from
    /// corners (size per distance).
    pub growth: f64,
    pub max_elements: usize,
    pub max_dense_bytes: usize,
}

impl Default for AxisymSettings {
    /// 8 elements per gap: within 0.1 % of resolution 32 on the paper's
    /// spheroid in the paper's tube (convergence table in docs/body-in-tube.md), about
    /// 200 elements.
    fn default() -> Self {
        AxisymSettings {
            resolution: 8.0,
            growth: 0.25,
            max_elements: 20_000,
            max_dense_bytes: MAX_DENSE_BYTES,
        }
    }
}

/// Volume fluxes (per unit body speed, m^3/s per m/s) of the diagnostic.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct FluxCheck {
    pub closed: bool,
    /// `pi a^2` of the body's section at its centre.
    pub displaced: f64,
    /// Flux through the gap beside the body's centre section.
    pub gap: f64,
    /// Flux through the full section midway between nose and tube end.
    pub ahead: f64,
}

impl FluxCheck {
    /// Relative violation of mass conservation: `|Q_gap + pi a^2 U -
    /// Q_ahead|` and, in a closed tube, `|Q_ahead|`, over `pi a^2 U`.
    pub fn error(&self) -> f64 {
        let balance = (self.gap + self.displaced - self.ahead).abs();
        let leak = if self.closed { self.ahead.abs() } else { 0.0 };
        balance.max(leak) / self.displaced
    }
}

/// The result of one body solve.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BodySolve {
    /// Axial translational resistance `F / U` (N s / m).
    pub drag_n_s_per_m: f64,
    /// Axial rotational resistance `T / Omega` (N m s).
    pub rotational_drag_n_m_s: f64,
    pub body_elements: usize,
    /// Tube wall and caps.
    pub wall_elements: usize,
    pub flux: Option<FluxCheck>,
    /// Wall-clock time of assembly, solves and diagnostics.
    pub seconds: f64,
    /// Of which the flux diagnostic.
    pub flux_seconds: f64,
}

impl BodySolve {
    /// Mass-conservation error of the solution (none in free space).
    pub fn flux_error(&self) -> Option<f64> {
        self.flux.map(|f| f.error())
    }
}

/// Axial drag and torque of `profile` centred at `centre_m` (axial
/// position relative to the tube's centre) in `confinement`.
pub fn solve_body(
    profile: &BodyProfile,
    confinement: &Confinement,
    centre_m: f64,
    mu_pa_s: f64,
    settings: &AxisymSettings,
) -> Result<BodySolve, NonlocalError> {
    if !(mu_pa_s.is_finite() && mu_pa_s > 0.0) {
        return Err(NonlocalError::Geometry(format!(
            "viscosity must be positive and finite, got {mu_pa_s} Pa s"
        )));
    }
    let mesh = solve::build_mesh(profile, confinement, centre_m, settings)?;
    solve::solve_mesh(&mesh, confinement, mu_pa_s, settings)
}

/// The annular-gap closed forms for a coaxial cylinder of radius `a` and
/// length `l` in a tube of radius `b`, end effects neglected: axial drag
/// `2 pi mu l / [ln(1/k) - (1-k^2)/(1+k^2)]` closed (zero net flux),
/// `2 pi mu l / ln(1/k)` open (no pressure gradient), and the Couette
/// torque `4 pi mu l a^2 b^2 / (b^2 - a^2)`; `k = a / b`. Returns
/// `(drag N s/m, rotational drag N m s)`.
pub fn annular_formula(a_m: f64, b_m: f64, l_m: f64, mu: f64, closed: bool) -> (f64, f64) {
    let k = a_m / b_m;
    let ln = (1.0 / k).ln();
    let den = if closed {
        ln - (1.0 - k * k) / (1.0 + k * k)
    } else {
        ln
    };
    let pi = std::f64::consts::PI;
    (
        2.0 * pi * mu * l_m / den,
        4.0 * pi * mu * l_m * a_m * a_m * b_m * b_m / (b_m * b_m - a_m * a_m),
    )
}
