//! `swimbot helix`: the tail's 6x6 resistance matrix (eq. 3) for one helix,
//! in free space or, with `--channel-diameter-mm`, coaxial in the tube by
//! the leak-free solver of `crate::nonlocal::tube` (regularized Stokeslets
//! on the centre-line, MFS wall), with its leak diagnostics.

use super::output::{print_json, Format};
use super::CliError;
use crate::physics::coefficients::CoefficientSet;
use crate::physics::geometry::{Handedness, Helix};
use crate::physics::tail;
use clap::{Args, ValueEnum};

#[derive(Args, Debug)]
pub struct HelixArgs {
    #[arg(long)]
    pub wavelength_mm: f64,
    #[arg(long)]
    pub amplitude_mm: f64,
    /// Axial length L_t.
    #[arg(long)]
    pub length_mm: f64,
    #[arg(long, default_value_t = 1.0)]
    pub wire_diameter_mm: f64,
    #[arg(long, default_value_t = 3.5)]
    pub viscosity_pa_s: f64,
    #[arg(long, value_enum, default_value = "gray-hancock")]
    pub coefficients: super::model_args::CoefficientsArg,
    /// Default: exact (RFT) in free space, stokeslets in a channel (the
    /// only method the tube solver has).
    #[arg(long, value_enum)]
    pub method: Option<HelixMethod>,
    /// Quadrature nodes per wavelength (with --method quadrature).
    #[arg(long, default_value_t = 100)]
    pub nodes_per_wavelength: usize,
    /// Segments per turn (with --method sbt|stokeslets).
    #[arg(long, default_value_t = 12)]
    pub segments_per_turn: usize,
    /// Left-handed helix instead of the paper's right-handed one.
    #[arg(long)]
    pub left_handed: bool,
    /// Put the helix coaxially in a tube of this inner diameter (leak-free
    /// MFS wall, closed by end caps unless --open).
    #[arg(long)]
    pub channel_diameter_mm: Option<f64>,
    /// Tube length: caps (or open ends) at most half the spare length beyond
    /// the helix. Default: a long tube (caps 1.5 radii beyond the helix).
    #[arg(long, requires = "channel_diameter_mm")]
    pub channel_length_mm: Option<f64>,
    /// Open tube ends (no caps, net flux allowed).
    #[arg(long, requires = "channel_diameter_mm")]
    pub open: bool,
    /// Tube wall collocation spacing.
    #[arg(long, default_value_t = 3.0, requires = "channel_diameter_mm")]
    pub wall_spacing_mm: f64,
    /// Refuse a dense tube solve needing more memory than this.
    #[arg(long, default_value_t = 4.0)]
    pub max_memory_gb: f64,
    #[arg(long, value_enum, default_value = "table")]
    pub format: Format,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum HelixMethod {
    Exact,
    Quadrature,
    /// Johnson's slender-body theory (non-local).
    Sbt,
    /// Regularized Stokeslets (non-local).
    Stokeslets,
}

#[derive(serde::Serialize)]
struct HelixOut {
    method: &'static str,
    coefficients: String,
    /// Row-major 6x6, SI: [force; torque about the joint] = -matrix [U; Omega].
    matrix: Vec<Vec<f64>>,
    drag_n_s_per_m: f64,
    thrust_n_s: f64,
    torque_n_m_s: f64,
    arc_length_mm: f64,
    n_waves: f64,
    c_t_pa_s: f64,
    c_n_pa_s: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    tube: Option<TubeOut>,
}

#[derive(serde::Serialize)]
struct TubeOut {
    diameter_mm: f64,
    /// `null` for a long tube.
    length_mm: Option<f64>,
    closed: bool,
    wall_spacing_mm: f64,
    diagnostics: crate::nonlocal::tube::Diagnostics,
}

fn positive(name: &str, v: f64) -> Result<f64, CliError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(CliError::input(format!(
            "--{name} must be a positive number, got {v}"
        )))
    }
}

/// The documented ranges (`data::limits`) of the helix's fields.
fn helix_limits(a: &HelixArgs) -> Result<(), CliError> {
    use crate::data::limits::{check_value, MAX_TURNS};
    for (flag, field, v) in [
        ("wavelength-mm", "wavelength_mm", a.wavelength_mm),
        ("amplitude-mm", "amplitude_mm", a.amplitude_mm),
        ("length-mm", "tail_length_mm", a.length_mm),
        ("wire-diameter-mm", "wire_diameter_mm", a.wire_diameter_mm),
        ("viscosity-pa-s", "viscosity_pa_s", a.viscosity_pa_s),
    ] {
        check_value(field, v).map_err(|e| CliError::input(format!("--{flag}: {e}")))?;
    }
    if a.length_mm / a.wavelength_mm > MAX_TURNS {
        return Err(CliError::input(format!(
            "--length-mm / --wavelength-mm: {} turns, at most {MAX_TURNS}",
            a.length_mm / a.wavelength_mm
        )));
    }
    Ok(())
}

pub fn run(a: HelixArgs) -> Result<(), CliError> {
    let mut h = Helix::from_mm(
        positive("wavelength-mm", a.wavelength_mm)?,
        positive("amplitude-mm", a.amplitude_mm)?,
        positive("length-mm", a.length_mm)?,
        positive("wire-diameter-mm", a.wire_diameter_mm)?,
    );
    helix_limits(&a)?;
    if a.left_handed {
        h.handedness = Handedness::Left;
    }
    let mu = positive("viscosity-pa-s", a.viscosity_pa_s)?;
    let set = match a.coefficients {
        super::model_args::CoefficientsArg::GrayHancock => CoefficientSet::GrayHancock,
        super::model_args::CoefficientsArg::Lighthill => CoefficientSet::Lighthill,
    };
    let drag = set.local_drag(&h, mu).map_err(CliError::input)?;
    if let Some(d_mm) = a.channel_diameter_mm {
        if let Some(m) = a.method {
            if !matches!(m, HelixMethod::Stokeslets) {
                return Err(CliError::input(format!(
                    "--method {m:?} is not available in a channel: the tube solver uses stokeslets"
                )));
            }
        }
        let (m, tube) = tube_matrix(&a, &h, mu, d_mm)?;
        let method = "regularized Stokeslets in the tube (MFS wall)";
        return print(&a, &h, drag, set, m, method, Some(tube));
    }
    let (m, method) = match a.method.unwrap_or(HelixMethod::Exact) {
        HelixMethod::Exact => (tail::matrix_exact(&h, drag), "exact"),
        HelixMethod::Quadrature => {
            crate::data::limits::check_quadrature(a.nodes_per_wavelength, h.n_waves())
                .map_err(|e| CliError::input(format!("--nodes-per-wavelength: {e}")))?;
            (
                tail::matrix_quadrature(&h, drag, a.nodes_per_wavelength),
                "quadrature",
            )
        }
        HelixMethod::Sbt | HelixMethod::Stokeslets => {
            let (method, name) = if matches!(a.method, Some(HelixMethod::Sbt)) {
                (
                    crate::nonlocal::TailMethod::SlenderBody,
                    "slender-body theory",
                )
            } else {
                (
                    crate::nonlocal::TailMethod::RegularizedStokeslets,
                    "regularized Stokeslets",
                )
            };
            let settings = crate::nonlocal::NonlocalSettings::default()
                .with_method(method)
                .with_segments_per_turn(a.segments_per_turn);
            let m = crate::nonlocal::tail_resistance(&h, mu, &settings).map_err(CliError::input)?;
            (m, name)
        }
    };
    print(&a, &h, drag, set, m, method, None)
}

fn tube_matrix(
    a: &HelixArgs,
    h: &Helix,
    mu: f64,
    d_mm: f64,
) -> Result<(nalgebra::Matrix6<f64>, TubeOut), CliError> {
    use crate::nonlocal::tube::{tail_resistance_in_tube, TubeSettings};
    let d_mm = positive("channel-diameter-mm", d_mm)?;
    let length_mm = match a.channel_length_mm {
        Some(l) => Some(positive("channel-length-mm", l)?),
        None => None,
    };
    let max_gb = positive("max-memory-gb", a.max_memory_gb)?;
    let settings = TubeSettings {
        tail: crate::nonlocal::NonlocalSettings::default()
            .with_segments_per_turn(a.segments_per_turn),
        wall_spacing_m: positive("wall-spacing-mm", a.wall_spacing_mm)? * 1e-3,
        max_peak_bytes: (max_gb * 1e9).min(usize::MAX as f64) as usize,
        ..TubeSettings::default()
    };
    if a.wall_spacing_mm >= 0.5 * d_mm {
        return Err(CliError::input(format!(
            "--wall-spacing-mm {} must be below the tube radius {} mm",
            a.wall_spacing_mm,
            0.5 * d_mm
        )));
    }
    let channel = crate::physics::geometry::Channel {
        diameter_m: d_mm * 1e-3,
        length_m: length_mm.map_or(f64::INFINITY, |l| l * 1e-3),
        closed: !a.open,
        vertical: true,
    };
    // Memory estimated before anything dense is built.
    let points = crate::nonlocal::tube::tail_in_tube_points(h, &channel, &settings)
        .map_err(CliError::input)?;
    let need = crate::nonlocal::tube::mfs::peak_bytes(points);
    if need > settings.max_peak_bytes {
        return Err(CliError::input(format!(
            "the tube solve has {} unknowns and needs {:.2} GB, above --max-memory-gb {max_gb}: raise --wall-spacing-mm or lower --segments-per-turn",
            3 * points,
            need as f64 / 1e9
        )));
    }
    let r = tail_resistance_in_tube(h, &channel, mu, &settings).map_err(CliError::input)?;
    Ok((
        r.matrix,
        TubeOut {
            diameter_mm: d_mm,
            length_mm,
            closed: channel.closed,
            wall_spacing_mm: a.wall_spacing_mm,
            diagnostics: r.diagnostics,
        },
    ))
}

fn print(
    a: &HelixArgs,
    h: &Helix,
    drag: crate::physics::coefficients::LocalDrag,
    set: CoefficientSet,
    m: nalgebra::Matrix6<f64>,
    method: &'static str,
    tube: Option<TubeOut>,
) -> Result<(), CliError> {
    let out = HelixOut {
        method,
        coefficients: set.to_string(),
        matrix: (0..6)
            .map(|i| (0..6).map(|j| m[(i, j)]).collect())
            .collect(),
        drag_n_s_per_m: m[(0, 0)],
        thrust_n_s: m[(0, 3)],
        torque_n_m_s: m[(3, 3)],
        arc_length_mm: h.arc_length_m() * 1e3,
        n_waves: h.n_waves(),
        c_t_pa_s: drag.tangential,
        c_n_pa_s: drag.normal,
        tube,
    };
    super::output::check_finite("resistance matrix", &out)?;
    match a.format {
        Format::Json => print_json(&out),
        _ => print_table(&out),
    }
    Ok(())
}

fn print_table(o: &HelixOut) {
    println!(
        "tail resistance matrix ({}, {}), SI units, about the helix joint:",
        o.method, o.coefficients
    );
    println!("rows/cols: Fx Fy Fz Tx Ty Tz / Ux Uy Uz Ωx Ωy Ωz");
    for row in &o.matrix {
        let cells: Vec<String> = row.iter().map(|v| format!("{v:>12.4e}")).collect();
        println!("  {}", cells.join(" "));
    }
    println!("axial drag        B(1,1) = {:.6e} N s/m", o.drag_n_s_per_m);
    println!("thrust per rate   B(1,4) = {:.6e} N s", o.thrust_n_s);
    println!("torque per rate   B(4,4) = {:.6e} N m s", o.torque_n_m_s);
    println!(
        "arc length {:.2} mm, {:.3} waves, c_t = {:.4} Pa s, c_n = {:.4} Pa s",
        o.arc_length_mm, o.n_waves, o.c_t_pa_s, o.c_n_pa_s
    );
    if let Some(t) = &o.tube {
        let d = &t.diagnostics;
        println!(
            "tube: diameter {} mm, {}, {}; wall spacing {} mm; {} unknowns, {:.2} GB peak",
            t.diameter_mm,
            t.length_mm
                .map_or("long".to_string(), |l| format!("length {l} mm")),
            if t.closed { "closed" } else { "open" },
            t.wall_spacing_mm,
            3 * d.n_points,
            d.peak_bytes as f64 / 1e9
        );
        let pct = |v: &[f64]| {
            v.iter()
                .map(|q| format!("{:+.3} %", 100.0 * q))
                .collect::<Vec<_>>()
                .join(", ")
        };
        println!(
            "net flux / piston flux at x = {} mm ({}): translation {}; rotation {}",
            d.sections_x_m
                .iter()
                .map(|x| format!("{:.1}", x * 1e3))
                .collect::<Vec<_>>()
                .join(", "),
            if t.closed {
                "must vanish"
            } else {
                "pumped flux"
            },
            pct(&d.flux_over_piston_translation),
            pct(&d.flux_over_piston_rotation)
        );
        println!(
            "wall speed between collocation points: {:.3} % of U, {:.3} % of Omega r_env",
            100.0 * d.wall_slip_over_u,
            100.0 * d.wall_slip_over_omega_r
        );
    }
}
