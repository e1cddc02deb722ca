//! `swimbot body`: the body's axial drag and axial rotational drag, exact
//! for its axisymmetric shape, in free space or on the axis of a closed or
//! open tube (`crate::nonlocal::axisym`), with the free-space and
//! annular-formula values beside them and the solver's diagnostics (mass
//! conservation error, elements, time).
//!
//! The body is `--profile length:diameter,...` (mm, nose first; flat ends,
//! rims rounded by `--rounded-mm`), `--spheroid length:diameter`, or the
//! body of a dataset case (`--data F --case ID`: its `body_profile` if
//! given, else its spheroid, and its channel and viscosity unless
//! overridden). Without a channel the body is in free space.
//!
//! References: the solver and its checks, `crate::nonlocal::axisym`
//! (Pozrikidis 1992); the annular closed forms, Chen, Lescarboura & Swift,
//! AIChE J. 14 (1968) 123.

use super::output::{print_json, TableOrJson};
use super::CliError;
use crate::nonlocal::axisym::{annular_formula, solve_body, AxisymSettings, Confinement};
use crate::physics::profile::BodyProfile;
use crate::provenance::Inputs;
use clap::Args;

#[derive(Args, Debug)]
pub struct BodyArgs {
    /// The body as cylindrical sections `length:diameter,...` in mm, nose first
    /// (give the body by one of --profile, --spheroid, --data with --case; none is the default).
    #[arg(long, conflicts_with_all = ["spheroid", "data"])]
    pub profile: Option<String>,
    /// Fillet radius of the profile's nose and tail rims (mm).
    #[arg(long, default_value_t = 0.0, requires = "profile")]
    pub rounded_mm: f64,
    /// The body as a prolate spheroid `length:diameter` in mm (one of the three ways; none is the default).
    #[arg(long, conflicts_with = "data")]
    pub spheroid: Option<String>,
    /// Dataset file whose case supplies body, channel and viscosity (with --case;
    /// one of the three ways to give the body, none is the default).
    #[arg(long, value_name = "FILE", requires = "case")]
    pub data: Option<std::path::PathBuf>,
    /// Case id in --data (required with --data, no default).
    #[arg(long, requires = "data")]
    pub case: Option<String>,
    /// Tube inner diameter in mm [default: the case's with --case, else none: free space].
    #[arg(long)]
    pub channel_diameter_mm: Option<f64>,
    /// Tube length in mm [default: the case's, else the body's length plus
    /// eight tube diameters (caps four diameters away from the body)].
    #[arg(long)]
    pub channel_length_mm: Option<f64>,
    /// Open tube (no end caps) instead of closed.
    #[arg(long)]
    pub open: bool,
    /// Fluid viscosity in Pa s [default: the case's, else 3.5, the paper's silicone oil].
    #[arg(long)]
    pub viscosity_pa_s: Option<f64>,
    /// Axial position of the body's centre from the tube's centre, in mm.
    #[arg(long, default_value_t = 0.0)]
    pub position_mm: f64,
    /// Boundary elements across the smaller of the body radius and the gap (mesh resolution).
    #[arg(long, default_value_t = AxisymSettings::default().resolution)]
    pub resolution: f64,
    #[arg(long, value_enum, default_value = "table", help = super::output::FORMAT_HELP)]
    pub format: TableOrJson,
}

#[derive(serde::Serialize)]
struct BodyOut {
    body: String,
    confinement: String,
    viscosity_pa_s: f64,
    drag_n_s_per_m: f64,
    rotational_drag_n_m_s: f64,
    free_drag_n_s_per_m: f64,
    free_rotational_drag_n_m_s: f64,
    annular_drag_n_s_per_m: Option<f64>,
    annular_rotational_drag_n_m_s: Option<f64>,
    flux_error: Option<f64>,
    body_elements: usize,
    wall_elements: usize,
    solve_seconds: f64,
}

fn pair(flag: &str, v: &str) -> Result<(f64, f64), CliError> {
    let bad = || CliError::input(format!("--{flag} `{v}`: expected `length_mm:diameter_mm`"));
    let (l, d) = v.split_once(':').ok_or_else(bad)?;
    let l: f64 = l.trim().parse().map_err(|_| bad())?;
    let d: f64 = d.trim().parse().map_err(|_| bad())?;
    Ok((l, d))
}

fn positive(flag: &str, v: f64) -> Result<f64, CliError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(CliError::input(format!(
            "--{flag} must be a positive number, got {v}"
        )))
    }
}

/// The largest net flux (relative to the piston flux) a closed-tube solve
/// may let through and still be printed.
const FLUX_ERROR_LIMIT: f64 = 1e-2;

pub fn run(a: BodyArgs, inputs: &Inputs) -> Result<(), CliError> {
    let body = request(&a)?;
    let out = solve(&body, a.position_mm, a.resolution)?;
    // The solve's own check: in a closed tube the net flux through any
    // cross-section is zero, so what the discrete solve lets through
    // measures its error (1e-4 of the piston flux for the paper's body). A
    // failed check is not a result.
    if let Some(e) = out
        .flux_error
        .filter(|e| e.is_nan() || *e > FLUX_ERROR_LIMIT)
    {
        return Err(CliError::input(format!(
            "the solve's own check fails: the net flux through the tube is {} of the piston flux \
             (a resolved solve keeps it below {}; 1e-4 for the paper's body): the profile is too \
             thin or too sharp for the mesh (a neck or a section much smaller than its neighbours), \
             so no drag is printed",
            crate::format::fmt_sig(e, 2),
            crate::format::fmt_sig(FLUX_ERROR_LIMIT, 1)
        )));
    }
    match a.format {
        TableOrJson::Json => print_json(&out, inputs),
        TableOrJson::Table => print_table(&out),
    }
    Ok(())
}

/// The tube around the body: diameter and length in mm, closed or open.
#[derive(Clone, Copy)]
struct Tube {
    diameter_mm: f64,
    length_mm: f64,
    closed: bool,
}

/// What to solve, validated from the flags before any work.
struct BodyRequest {
    profile: BodyProfile,
    viscosity_pa_s: f64,
    tube: Option<Tube>,
}

/// The body from `--profile`, `--spheroid` or a dataset's case (which also
/// gives the oil and the tube), then the flags that override them.
fn request(a: &BodyArgs) -> Result<BodyRequest, CliError> {
    let (profile, mut mu, mut tube) = body_of(a)?;
    if let Some(v) = a.viscosity_pa_s {
        mu = positive("viscosity-pa-s", v)?;
    }
    if let Some(d) = a.channel_diameter_mm {
        let d = positive("channel-diameter-mm", d)?;
        let default_len = profile.length_mm() + 8.0 * d;
        tube = Some(Tube {
            diameter_mm: d,
            length_mm: tube.map_or(default_len, |t| t.length_mm),
            closed: true,
        });
    }
    if let Some(l) = a.channel_length_mm {
        let l = positive("channel-length-mm", l)?;
        let t = tube.as_mut().ok_or_else(|| {
            CliError::input("--channel-length-mm needs a channel (--channel-diameter-mm or --case)")
        })?;
        t.length_mm = l;
    }
    if a.open {
        let t = tube.as_mut().ok_or_else(|| {
            CliError::input("--open needs a channel (--channel-diameter-mm or --case)")
        })?;
        t.closed = false;
    }
    if !a.position_mm.is_finite() {
        return Err(CliError::input("--position-mm must be a finite number"));
    }
    Ok(BodyRequest {
        profile,
        viscosity_pa_s: mu,
        tube,
    })
}

/// The body's profile, with the oil (3.5 Pa s unless a case gives it) and
/// the case's tube.
fn body_of(a: &BodyArgs) -> Result<(BodyProfile, f64, Option<Tube>), CliError> {
    if let Some(spec) = &a.profile {
        if !(a.rounded_mm.is_finite() && a.rounded_mm >= 0.0) {
            return Err(CliError::input(format!(
                "--rounded-mm must be a number >= 0, got {}",
                a.rounded_mm
            )));
        }
        let p = BodyProfile::parse_sections(spec, a.rounded_mm)
            .map_err(|e| CliError::input(format!("--profile: {e}")))?;
        Ok((p, 3.5, None))
    } else if let Some(spec) = &a.spheroid {
        let (l, d) = pair("spheroid", spec)?;
        let p = BodyProfile::spheroid(l, d);
        p.validate()
            .map_err(|e| CliError::input(format!("--spheroid: {e}")))?;
        Ok((p, 3.5, None))
    } else if let (Some(path), Some(id)) = (&a.data, &a.case) {
        let data = crate::data::load_file(path)?;
        let case = data.cases.iter().find(|c| &c.id == id).ok_or_else(|| {
            let ids: Vec<&str> = data.cases.iter().map(|c| c.id.as_str()).collect();
            CliError::input(format!(
                "{}: no case `{id}` (cases: {})",
                path.display(),
                ids.join(", ")
            ))
        })?;
        let tube = Tube {
            diameter_mm: case.channel_diameter_mm,
            length_mm: case.channel_length_mm,
            closed: case.channel_closed,
        };
        Ok((case.body_profile(), case.viscosity_pa_s, Some(tube)))
    } else {
        Err(CliError::input(
            "give the body: --profile L:D,..., --spheroid L:D, or --data FILE --case ID",
        ))
    }
}

/// The exact axisymmetric solve in the tube and in free space, with the
/// annular formula beside them.
fn solve(r: &BodyRequest, position_mm: f64, resolution: f64) -> Result<BodyOut, CliError> {
    let (profile, mu) = (&r.profile, r.viscosity_pa_s);
    let confinement = match r.tube {
        None => Confinement::Free,
        Some(t) if t.closed => Confinement::Closed {
            diameter_m: t.diameter_mm * 1e-3,
            length_m: t.length_mm * 1e-3,
        },
        Some(t) => Confinement::Open {
            diameter_m: t.diameter_mm * 1e-3,
            length_m: t.length_mm * 1e-3,
        },
    };
    let settings = AxisymSettings {
        resolution,
        ..AxisymSettings::default()
    };
    let solved = solve_body(profile, &confinement, position_mm * 1e-3, mu, &settings)
        .map_err(CliError::input)?;
    let free =
        solve_body(profile, &Confinement::Free, 0.0, mu, &settings).map_err(CliError::input)?;
    let annular = r.tube.map(|t| {
        annular_formula(
            0.5e-3 * profile.max_diameter_mm(),
            0.5e-3 * t.diameter_mm,
            1e-3 * profile.length_mm(),
            mu,
            t.closed,
        )
    });
    Ok(BodyOut {
        body: profile.describe(),
        confinement: match r.tube {
            None => "free space".into(),
            Some(t) => format!(
                "{} tube, {} mm x {} mm, body centre at {position_mm} mm",
                if t.closed { "closed" } else { "open" },
                t.diameter_mm,
                t.length_mm
            ),
        },
        viscosity_pa_s: mu,
        drag_n_s_per_m: solved.drag_n_s_per_m,
        rotational_drag_n_m_s: solved.rotational_drag_n_m_s,
        free_drag_n_s_per_m: free.drag_n_s_per_m,
        free_rotational_drag_n_m_s: free.rotational_drag_n_m_s,
        annular_drag_n_s_per_m: annular.map(|a| a.0),
        annular_rotational_drag_n_m_s: annular.map(|a| a.1),
        flux_error: solved.flux_error(),
        body_elements: solved.body_elements,
        wall_elements: solved.wall_elements,
        solve_seconds: solved.seconds,
    })
}

fn print_table(o: &BodyOut) {
    let num = |v: f64| crate::format::fmt_sig(v, 6);
    let opt = |v: Option<f64>| v.map_or("-".to_string(), num);
    println!("body: {}", o.body);
    println!("in: {}, viscosity {} Pa s", o.confinement, o.viscosity_pa_s);
    println!(
        "{:<24} {:>14} {:>14} {:>16}",
        "", "solver", "free space", "annular formula"
    );
    println!(
        "{:<24} {:>14} {:>14} {:>16}",
        "drag_n_s_per_m",
        num(o.drag_n_s_per_m),
        num(o.free_drag_n_s_per_m),
        opt(o.annular_drag_n_s_per_m)
    );
    println!(
        "{:<24} {:>14} {:>14} {:>16}",
        "rotational_drag_n_m_s",
        num(o.rotational_drag_n_m_s),
        num(o.free_rotational_drag_n_m_s),
        opt(o.annular_rotational_drag_n_m_s)
    );
    println!(
        "flux error {}, elements {} body + {} wall, solve {} ms",
        o.flux_error
            .map_or("- (free space)".into(), |e| crate::format::fmt_sig(e, 2)),
        o.body_elements,
        o.wall_elements,
        crate::format::fmt_sig(1e3 * o.solve_seconds, 2)
    );
}
