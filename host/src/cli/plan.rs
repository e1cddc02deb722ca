//! `swimbot plan`: inside a study, the runs that best separate what
//! `diagnose` cannot tell apart (or sharpen what it located), written as a
//! run sheet for the lab ([`crate::workbench::plan`]).

use super::CliError;
use crate::format::fmt_sig;
use crate::provenance::Inputs;
use crate::study::{Study, DEFAULT_FILE};
use crate::workbench::diagnose::DiagnoseSettings;
use crate::workbench::plan::{plan_for, rivals::Rivals, sheet, Plan, PlanError, PlanRig};
use clap::Args;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct PlanArgs {
    /// Runs to plan.
    #[arg(long, default_value_t = 6, allow_negative_numbers = true, value_parser = crate::cli::count::whole::<usize>)]
    pub runs: usize,
    /// The run sheet to write (a dataset CSV, measurements empty).
    #[arg(short, long, value_name = "FILE", default_value = "plan.csv")]
    pub output: PathBuf,
    /// Also plan tails not yet built, inside the data's geometry ranges [default: the data's tails only].
    #[arg(long)]
    pub new_tails: bool,
    /// The tubes on hand, inner diameters in mm, e.g. 26,35,45 [default: the data's (or its [rig])].
    #[arg(long, value_name = "MM,...", value_delimiter = ',')]
    pub tubes_mm: Option<Vec<f64>>,
    /// The oils on hand, viscosities in Pa s, e.g. 1.0,3.5 [default: the data's].
    #[arg(long, value_name = "PA_S,...", value_delimiter = ',')]
    pub oils_pa_s: Option<Vec<f64>>,
    /// The robot whose motor and cell bound the set-points it can hold (TOML, docs/robot-format.md) [default: the built-in paper robot].
    #[arg(long, value_name = "FILE.toml")]
    pub robot: Option<PathBuf>,
}

/// A plan made for a study: the rivals, the plan, the sheet's text.
pub struct Planned {
    pub rivals: Rivals,
    pub plan: Option<Plan>,
}

/// Plan `a.runs` runs on the study's data and current model.
pub fn plan_study(s: &Study, a: &PlanArgs, inputs: &Inputs) -> Result<Planned, CliError> {
    let data = s.dataset();
    let rig = PlanRig::of(data, a.tubes_mm.clone(), a.oils_pa_s.clone(), a.new_tails);
    let settings = DiagnoseSettings {
        likelihood: s.likelihood()?,
        catalogue: s.catalogue()?,
        ..DiagnoseSettings::default()
    };
    let robot = match &a.robot {
        Some(p) => crate::sim::Robot::load_file(p, &settings.catalogue, inputs)
            .map_err(|e| CliError::input(format!("--robot: {e}")))?,
        None => crate::sim::default_robot(),
    };
    let plan_on = |model| {
        plan_for(&model, data, &settings, &rig, a.runs, &robot).map_err(|e| match e {
            PlanError::Rig(e) => CliError::input(e),
            PlanError::Fit(e) => CliError::failure(e),
        })
    };
    let (rivals, plan) = plan_on(s.model()?)?;
    let n = s.steps().len();
    if plan.is_some() || n == 0 {
        return Ok(Planned { rivals, plan });
    }
    // Nothing left on the model now: test its last step against what the
    // data did not rule out in its place, on the model before it.
    let (mut before, plan) = plan_on(s.model_upto(n - 1)?)?;
    if plan.is_none() {
        return Ok(Planned { rivals, plan: None });
    }
    before.why = "nothing is missing now; the last step's place, on the model before it: the effects the data do not rule out (within 10 AICc of the best)";
    Ok(Planned {
        rivals: before,
        plan,
    })
}

fn open(study: &Option<PathBuf>, inputs: &Inputs) -> Result<Study, CliError> {
    let path = Study::locate(study.as_deref(), Path::new(".")).ok_or_else(|| {
        CliError::input(format!(
            "plan works inside a study: no {DEFAULT_FILE} here; start one with `swimbot init --data FILE`, or give --study FILE"
        ))
    })?;
    let s = Study::open(&path)?;
    inputs.record_all(s.inputs());
    Ok(s)
}

pub fn run(a: PlanArgs, study: &Option<PathBuf>, inputs: &Inputs) -> Result<(), CliError> {
    if a.runs == 0 {
        return Err(CliError::input("--runs: give at least one run"));
    }
    let s = open(study, inputs)?;
    let spinner = crate::progress::spinner("diagnosing the study's model for its rivals");
    let planned = plan_study(&s, &a, inputs);
    spinner.finish_and_clear();
    let Planned { rivals, plan } = planned?;
    let Some(plan) = plan else {
        println!(
            "nothing to plan: diagnose finds no rival explanations and no fitted law with an interval to sharpen; no sheet written"
        );
        return Ok(());
    };
    print_rivals(&rivals);
    for &(i, j) in &plan.ties {
        println!(
            "no run separates {} from {}: their predictions agree to round-off on every run the rig can make (the same model)",
            rivals.models[i].name, rivals.models[j].name
        );
    }
    if plan.reachable == 0 {
        return Err(CliError::input(format!(
            "--robot: of the {} runs the rig offers, the robot's motor holds none: every set-point is above {:.0} % of its full-drive rate against the tail's load (a weaker motor or cell, or a more viscous oil, than the data's); give a rig it can run (--oils-pa-s, --tubes-mm) or another --robot",
            plan.offered,
            100.0 * crate::workbench::plan::reach::HEADROOM
        )));
    }
    if plan.runs.is_empty() {
        println!("nothing can be separated inside this rig; no sheet written");
        return Ok(());
    }
    let header = vec![
        format!("plan for the study {}", s.path().display()),
        "expected separation: T-optimal (Atkinson & Fedorov 1975), rivals held at their fits, sigma from the data's median relative standard error".into(),
    ];
    let text = sheet::to_csv(&plan, &rivals, &header).map_err(CliError::failure)?;
    super::output::check_output_file(&a.output, inputs)?;
    super::output::write_all_atomically(&[(a.output.clone(), text.into_bytes())], inputs)?;
    print_plan(&plan, &rivals);
    println!("wrote {} (fill in the measurements)", a.output.display());
    Ok(())
}

fn print_rivals(r: &Rivals) {
    println!("{}:", r.why);
    for (i, m) in r.models.iter().enumerate() {
        println!("  ({}) {}", i + 1, m.name);
    }
}

fn print_plan(p: &Plan, r: &Rivals) {
    println!(
        "{} run{} chosen of the {} the robot can hold ({} offered by the rig's tubes, oils, tails and set-points), in the order to run them:",
        p.runs.len(),
        if p.runs.len() == 1 { "" } else { "s" },
        p.reachable,
        p.offered
    );
    for run in sheet::ordered(p) {
        let c = &run.candidate.case;
        let (i, j) = run.separates;
        println!(
            "  {}: tail {} in the {} mm tube, {} Pa s, motor at {} Hz (tail {} Hz in the lab); keys {}; about {} s; separates ({}) from ({}) by {} sd",
            c.id,
            run.candidate.tail,
            fmt_sig(c.channel_diameter_mm, 3),
            fmt_sig(c.viscosity_pa_s, 3),
            fmt_sig(run.candidate.set_point_hz, 3),
            fmt_sig(c.frequency_hz, 3),
            crate::workbench::plan::keys::run_keys(run.candidate.set_point_hz).unwrap_or_default(),
            crate::workbench::plan::keys::duration_s(c, run.expected.u_mm_s)
                .map_or("?".into(), |t| format!("{t:.0}")),
            i + 1,
            j + 1,
            fmt_sig(run.separation_sigma, 2)
        );
    }
    println!("expected separation of each pair over the plan:");
    for ((i, j), s) in &p.pair_sigma {
        println!(
            "  ({}) vs ({}): {} sd{}",
            i + 1,
            j + 1,
            fmt_sig(*s, 2),
            if *s < 2.0 {
                " (not enough: more runs, or a wider rig)"
            } else {
                ""
            }
        );
    }
    let _ = r;
}
