//! `swimbot helix`: the tail's 6x6 resistance matrix (eq. 3) for one helix.

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
    #[arg(long, value_enum, default_value = "exact")]
    pub method: HelixMethod,
    /// Quadrature nodes per wavelength (with --method quadrature).
    #[arg(long, default_value_t = 100)]
    pub nodes_per_wavelength: usize,
    /// Segments per turn (with --method sbt|stokeslets).
    #[arg(long, default_value_t = 12)]
    pub segments_per_turn: usize,
    /// Left-handed helix instead of the paper's right-handed one.
    #[arg(long)]
    pub left_handed: bool,
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
    let (m, method) = match a.method {
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
            let (method, name) = if matches!(a.method, HelixMethod::Sbt) {
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
}
