//! `swimbot helix`: the tail's 6x6 resistance matrix (eq. 3) for one helix,
//! in free space or, with `--channel-diameter-mm`, coaxial in the tube by
//! the leak-free solver of `crate::nonlocal::tube` (regularized Stokeslets
//! on the centre-line, MFS wall), with its leak diagnostics.

use super::model_args::TailModelArg;
use super::output::{print_json, TableOrJson};
use super::CliError;
use crate::format::fmt_sig;
use crate::physics::coefficients::CoefficientSet;
use crate::physics::geometry::{Handedness, Helix};
use crate::physics::tail;
use crate::provenance::Inputs;
use clap::{Args, ValueEnum};

#[derive(Args, Debug)]
pub struct HelixArgs {
    /// Helix wavelength lambda in mm.
    #[arg(long)]
    pub wavelength_mm: f64,
    /// Helix amplitude B (radius of the helix's centre-line) in mm.
    #[arg(long)]
    pub amplitude_mm: f64,
    // `--length-mm`: its old name, hidden, for old scripts.
    /// Axial tail length L_t in mm.
    #[arg(long, alias = "length-mm")]
    pub tail_length_mm: f64,
    /// Wire diameter D_t in mm.
    #[arg(long, default_value_t = 1.0)]
    pub wire_diameter_mm: f64,
    /// Fluid viscosity mu in Pa s (the paper's silicone oil: 3.5).
    #[arg(long, default_value_t = 3.5)]
    pub viscosity_pa_s: f64,
    /// Local drag coefficient set of eq. 3.
    #[arg(long, value_enum, default_value = "gray-hancock")]
    pub coefficients: super::model_args::CoefficientsArg,
    /// How eq. 3 is integrated along the tail (with --tail-model rft) [default: exact].
    #[arg(long, value_enum)]
    pub method: Option<HelixMethod>,
    /// Quadrature nodes per wavelength (with --method quadrature; the paper used 100).
    #[arg(long, default_value_t = 100, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<usize>)]
    pub nodes_per_wavelength: usize,
    /// Tail hydrodynamics: local RFT (eq. 3), or non-local slender-body theory /
    /// regularized Stokeslets [default: rft in free space, stokeslets in a channel, the
    /// only model the tube solver has].
    #[arg(long, value_enum)]
    pub tail_model: Option<TailModelArg>,
    /// Segments per helix turn of the non-local tail models, sbt and stokeslets (12 is converged to 1 %).
    #[arg(long, default_value_t = 12, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<usize>)]
    pub segments_per_turn: usize,
    /// Left-handed helix instead of the paper's right-handed one.
    #[arg(long)]
    pub left_handed: bool,
    /// Put the helix coaxially in a tube of this inner diameter in mm (leak-free
    /// MFS wall, closed by end caps unless --open) [default: free space].
    #[arg(long)]
    pub channel_diameter_mm: Option<f64>,
    /// Tube length in mm: caps (or open ends) at most half the spare length beyond
    /// the helix [default: a long tube, caps 1.5 radii beyond the helix].
    #[arg(long, requires = "channel_diameter_mm")]
    pub channel_length_mm: Option<f64>,
    /// Open tube ends (no caps, net flux allowed).
    #[arg(long, requires = "channel_diameter_mm")]
    pub open: bool,
    /// Tube wall collocation spacing in mm.
    #[arg(long, default_value_t = 3.0, requires = "channel_diameter_mm")]
    pub wall_spacing_mm: f64,
    /// Refuse a tube solve whose memory, estimated before it starts, exceeds
    /// this, in GB (at most the machine's memory).
    #[arg(long, default_value_t = 4.0)]
    pub max_memory_gb: f64,
    #[arg(long, value_enum, default_value = "table", help = super::output::FORMAT_HELP)]
    pub format: TableOrJson,
}

/// `--method` of `helix`: the integration of eq. 3, as in the other
/// commands. `sbt` and `stokeslets` were values of this flag before
/// `--tail-model` took them; they are accepted, hidden, for old scripts.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum HelixMethod {
    /// Closed form.
    Exact,
    /// Numerical, --nodes-per-wavelength nodes.
    Quadrature,
    #[value(hide = true)]
    Sbt,
    #[value(hide = true)]
    Stokeslets,
}

/// The tail model and integration a command line asks for, with the old
/// `--method sbt|stokeslets` spellings folded into `--tail-model`.
fn tail_choice(a: &HelixArgs, in_channel: bool) -> Result<(TailModelArg, bool), CliError> {
    let from_method = match a.method {
        Some(HelixMethod::Sbt) => Some(TailModelArg::Sbt),
        Some(HelixMethod::Stokeslets) => Some(TailModelArg::Stokeslets),
        _ => None,
    };
    let tail = match (a.tail_model, from_method) {
        (Some(t), Some(m)) if t != m => {
            return Err(CliError::input(format!(
            "--tail-model {} and --method {} disagree: give the tail model once, with --tail-model",
            t.name(),
            m.name()
        )))
        }
        (Some(t), _) | (None, Some(t)) => t,
        (None, None) if in_channel => TailModelArg::Stokeslets,
        (None, None) => TailModelArg::Rft,
    };
    let quadrature = a.method == Some(HelixMethod::Quadrature);
    if quadrature && tail != TailModelArg::Rft {
        return Err(CliError::input(format!(
            "--method quadrature integrates eq. 3 (--tail-model rft), not --tail-model {}",
            tail.name()
        )));
    }
    Ok((tail, quadrature))
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
    /// This process's own high-water resident memory (bytes), to set
    /// against the tube's estimated `peak_bytes`; `null` where the system
    /// does not say (it is read from Linux's `/proc/self/status`).
    process_peak_rss_bytes: Option<u64>,
}

/// The process's resident-memory high-water mark, `VmHWM` (KiB) in
/// `/proc/self/status`. A parent's `wait4` cannot measure it: the child's
/// `ru_maxrss` keeps the parent's high-water mark from before the exec.
fn process_peak_rss_bytes() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[derive(serde::Serialize)]
struct TubeOut {
    diameter_mm: f64,
    /// `null` for a long tube.
    length_mm: Option<f64>,
    closed: bool,
    wall_spacing_mm: f64,
    /// The time estimated before the solve (s), to set against the
    /// diagnostics' measured `solve_seconds + diagnostics_seconds`.
    estimated_seconds: f64,
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
        ("tail-length-mm", "tail_length_mm", a.tail_length_mm),
        ("wire-diameter-mm", "wire_diameter_mm", a.wire_diameter_mm),
        ("viscosity-pa-s", "viscosity_pa_s", a.viscosity_pa_s),
    ] {
        check_value(field, v).map_err(|e| CliError::input(format!("--{flag}: {e}")))?;
    }
    if a.tail_length_mm / a.wavelength_mm > MAX_TURNS {
        return Err(CliError::input(format!(
            "--tail-length-mm / --wavelength-mm: {} turns, at most {MAX_TURNS}",
            crate::format::fmt_sig(a.tail_length_mm / a.wavelength_mm, 3)
        )));
    }
    Ok(())
}

pub fn run(a: HelixArgs) -> Result<(), CliError> {
    let mut h = Helix::from_mm(
        positive("wavelength-mm", a.wavelength_mm)?,
        positive("amplitude-mm", a.amplitude_mm)?,
        positive("tail-length-mm", a.tail_length_mm)?,
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
    let (tail_model, quadrature) = tail_choice(&a, a.channel_diameter_mm.is_some())?;
    if let Some(d_mm) = a.channel_diameter_mm {
        if tail_model != TailModelArg::Stokeslets {
            return Err(CliError::input(format!(
                "--tail-model {} is not available in a channel: the tube solver uses stokeslets",
                tail_model.name()
            )));
        }
        let spinner = crate::progress::spinner(
            "helix: the tail in the tube (regularized Stokeslets, MFS wall)",
        );
        let (m, tube) = tube_matrix(&a, &h, mu, d_mm)?;
        spinner.finish_and_clear();
        let method = "regularized Stokeslets in the tube (MFS wall)";
        return print(&a, &h, drag, set, m, method, Some(tube));
    }
    let (m, method) = match tail_model {
        TailModelArg::Rft if !quadrature => (tail::matrix_exact(&h, drag), "exact"),
        TailModelArg::Rft => {
            crate::data::limits::check_quadrature(a.nodes_per_wavelength, h.n_waves())
                .map_err(|e| CliError::input(format!("--nodes-per-wavelength: {e}")))?;
            (
                tail::matrix_quadrature(&h, drag, a.nodes_per_wavelength),
                "quadrature",
            )
        }
        TailModelArg::Sbt | TailModelArg::Stokeslets => {
            let (method, name) = if tail_model == TailModelArg::Sbt {
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

/// A tube solve estimated to take longer than this is announced first (s).
const LONG_SOLVE_S: f64 = 5.0;

/// Physical memory of the machine (`MemTotal` of `/proc/meminfo`), bytes.
fn machine_memory_bytes() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

fn tube_matrix(
    a: &HelixArgs,
    h: &Helix,
    mu: f64,
    d_mm: f64,
) -> Result<(nalgebra::Matrix6<f64>, TubeOut), CliError> {
    use crate::nonlocal::tube::{tail_resistance_in_tube, TubeSettings};
    let d_mm = positive("channel-diameter-mm", d_mm)?;
    crate::data::limits::check_value("channel_diameter_mm", d_mm)
        .map_err(|e| CliError::input(format!("--channel-diameter-mm: {e}")))?;
    let length_mm = match a.channel_length_mm {
        Some(l) => Some(positive("channel-length-mm", l)?),
        None => None,
    };
    let max_gb = positive("max-memory-gb", a.max_memory_gb)?;
    if let Some(total) = machine_memory_bytes() {
        if max_gb * 1e9 > total as f64 {
            return Err(CliError::input(format!(
                "--max-memory-gb {max_gb} is more than this machine has ({:.1} GB)",
                total as f64 / 1e9
            )));
        }
    }
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
    // Memory estimated from the counts, before anything is built.
    let budget = crate::nonlocal::tube::tail_in_tube_budget(h, &channel, &settings)
        .map_err(CliError::input)?;
    if budget.peak_bytes > settings.max_peak_bytes {
        return Err(CliError::input(format!(
            "the tube solve has {} unknowns and needs {:.2} GB, above --max-memory-gb {max_gb}: raise --wall-spacing-mm or lower --segments-per-turn",
            budget.n_points().saturating_mul(3),
            budget.peak_bytes as f64 / 1e9
        )));
    }
    if budget.seconds > LONG_SOLVE_S {
        eprintln!(
            "note: the tube solve has {} unknowns; estimated {:.0} s and {:.2} GB before it starts",
            budget.n_points().saturating_mul(3),
            budget.seconds,
            budget.peak_bytes as f64 / 1e9
        );
    }
    let r = tail_resistance_in_tube(h, &channel, mu, &settings).map_err(CliError::input)?;
    Ok((
        r.matrix,
        TubeOut {
            diameter_mm: d_mm,
            length_mm,
            closed: channel.closed,
            wall_spacing_mm: a.wall_spacing_mm,
            estimated_seconds: budget.seconds,
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
        process_peak_rss_bytes: process_peak_rss_bytes(),
    };
    super::output::check_finite("resistance matrix", &out)?;
    match a.format {
        // The helix is all flags: no file is read, none is named.
        TableOrJson::Json => print_json(&out, &Inputs::new()),
        TableOrJson::Table => print_table(&out),
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
        let cells: Vec<String> = row
            .iter()
            .map(|v| format!("{:>11}", fmt_sig(*v, 5)))
            .collect();
        println!("  {}", cells.join(" "));
    }
    println!(
        "axial drag        B(1,1) = {} N s/m",
        fmt_sig(o.drag_n_s_per_m, 6)
    );
    println!(
        "thrust per rate   B(1,4) = {} N s",
        fmt_sig(o.thrust_n_s, 6)
    );
    println!(
        "torque per rate   B(4,4) = {} N m s",
        fmt_sig(o.torque_n_m_s, 6)
    );
    println!(
        "arc length {} mm, {} waves, c_t = {} Pa s, c_n = {} Pa s",
        fmt_sig(o.arc_length_mm, 4),
        fmt_sig(o.n_waves, 4),
        fmt_sig(o.c_t_pa_s, 4),
        fmt_sig(o.c_n_pa_s, 4)
    );
    if let Some(t) = &o.tube {
        let d = &t.diagnostics;
        println!(
            "tube: diameter {} mm, {}, {}; wall spacing {} mm; {} unknowns, {} GB peak",
            t.diameter_mm,
            t.length_mm
                .map_or("long".to_string(), |l| format!("length {l} mm")),
            if t.closed { "closed" } else { "open" },
            t.wall_spacing_mm,
            3 * d.n_points,
            fmt_sig(d.peak_bytes as f64 / 1e9, 3)
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
