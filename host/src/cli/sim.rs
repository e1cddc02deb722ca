//! `swimbot sim`: the whole-robot simulation (remote script -> shared
//! controller -> PWM, motor, cell -> swimmer model -> climb), writing
//! `sim.csv` and `sim.svg` and printing the summary; `--fit-motor`
//! calibrates one motor against the observed tail rates instead.

use super::model_args::{load_data, ModelArgs};
use super::CliError;
use crate::physics::solve::Dofs;
use crate::provenance::Inputs;
use crate::runlog::{read_current, Source, Trace};
use crate::sim::{
    self, calibrate, log_overlay, output, rate_figure, replay, Options, RateRun, Robot, Script,
    SimError,
};
use clap::Args;
use std::path::PathBuf;

/// `--preset` in `sim`: the default is the robot file's model, not `base`.
const SIM_PRESET_HELP: &str = "Named model replacing the robot file's: base, paper, paper-lighthill, physics \
    [default: the robot file's [model]; the built-in robot's is gray-hancock + backflow + body-correction]";

#[derive(Args, Debug)]
#[command(mut_arg("preset", |a| a.help(SIM_PRESET_HELP)))]
#[command(mut_arg("coefficients", |a| a.help("Local drag coefficient set replacing the robot file's [default: the robot file's]")))]
pub struct SimArgs {
    /// Robot description (TOML, docs/robot-format.md) [default: the built-in paper robot].
    #[arg(long, value_name = "FILE.toml")]
    pub robot: Option<PathBuf>,
    /// Which of the robot's tails: its number (1-based) or its id.
    #[arg(long, default_value = "1")]
    pub tail: String,
    /// Remote commands, e.g. "on@0s,off@300s" or "nec:0x00:0x45@1s" [default: on@0s].
    #[arg(long, conflicts_with = "script_file")]
    pub script: Option<String>,
    /// The script from a file (one item per line or comma-separated, # comments) [default: --script].
    #[arg(long, value_name = "FILE")]
    pub script_file: Option<PathBuf>,
    /// Model options; --preset or --coefficients replace the robot file's model, --effect adds to it.
    #[command(flatten)]
    pub model: ModelArgs,
    // `--out`, `--max-time`, `--sample-every`: the old names, hidden, for old scripts.
    /// Output directory for sim.csv and sim.svg.
    #[arg(short, long, alias = "out", value_name = "DIR", default_value = super::output::DEFAULT_SIM_DIR)]
    pub output: PathBuf,
    /// Robot-time limit in s.
    #[arg(long, alias = "max-time", default_value_t = 1800.0)]
    pub max_time_s: f64,
    /// CSV sampling interval in s.
    #[arg(long, alias = "sample-every", default_value_t = 0.1)]
    pub sample_every_s: f64,
    /// Hold the motor's rate (tail relative to body, Hz) at set-points: 0.8, or 0.6@0s,0.9@20s; also writes rate.csv and rate.svg (the step responses) [default: none, the fixed motor voltage of the robot file].
    #[arg(long, value_name = "HZ[@TIME],...")]
    pub rate_hz: Option<String>,
    /// Replay a run log's set-points and On/Off (a saved image or the robot's port) and predict its trace with the model's tail load; also writes log-vs-sim.svg, the two overlaid, and prints their difference [default: none, --script and --rate-hz].
    #[arg(long, value_name = "LOG", conflicts_with_all = ["rate_hz", "script", "script_file"])]
    pub set_points_from: Option<String>,
    /// Also write the run's log image, taken by the firmware's own recorder (what `swimbot log` reads) [default: none].
    #[arg(long, value_name = "FILE")]
    pub write_log: Option<PathBuf>,
    /// Keep going past the channel's top (the height then exceeds the channel).
    #[arg(long)]
    pub no_stop_at_top: bool,
    /// Run a run sheet (the CSV `swimbot plan` wrote) row by row through the robot, --truth the world: writes SHEET-filled.csv (the camera's measurements) and each run's log ID.swlog [default: one run of --tail].
    #[arg(long, value_name = "SHEET", requires = "truth", conflicts_with_all = ["rate_hz", "script", "script_file", "set_points_from", "fit_motor", "write_log"])]
    pub plan: Option<PathBuf>,
    /// The world --plan runs in: a preset or coefficient set, then effects joined by `+`, as `synth --truth`, e.g. "base + backflow" [default: none; --plan needs it].
    #[arg(long, value_name = "MODEL", requires = "plan")]
    pub truth: Option<String>,
    /// --plan: relative noise (standard deviation) of one trial of a measured U or Omega_b, as a fraction [default: 0.02].
    #[arg(long, requires = "plan")]
    pub noise: Option<f64>,
    /// --plan: trials per run behind each measured mean [default: 5].
    #[arg(long, requires = "plan")]
    pub trials: Option<u32>,
    /// --plan: seed of the measurement noise (the same seed, the same sheet) [default: 1].
    #[arg(long, requires = "plan")]
    pub seed: Option<u64>,
    /// Fit one motor to the observed tail rates of all cases instead of simulating.
    #[arg(long)]
    pub fit_motor: bool,
    /// Dataset (TOML or CSV) for --fit-motor [default: the paper's built-in data].
    #[arg(long, value_name = "FILE", requires = "fit_motor")]
    pub data: Option<PathBuf>,
}

impl From<SimError> for CliError {
    fn from(e: SimError) -> Self {
        CliError::Input(e.to_string())
    }
}

fn robot_with_model(args: &SimArgs, inputs: &Inputs) -> Result<Robot, CliError> {
    // A robot file may name user effects: load them first.
    let catalogue = args.model.effect_files.load(inputs)?;
    let mut robot = match &args.robot {
        Some(p) => Robot::load_file(p, &catalogue, inputs).map_err(SimError::from)?,
        None => sim::default_robot(),
    };
    let m = &args.model;
    let replace = m.preset.is_some() || m.coefficients.is_some();
    let mut from_args = ModelArgs {
        effects: Vec::new(),
        ..m.clone()
    }
    .model_in(&catalogue)?;
    if !replace {
        from_args.coefficients = robot.model.coefficients;
        from_args.effects = robot.model.effects.clone();
    }
    for spec in &m.effects {
        let e = catalogue.parse_effect_spec(spec)?;
        if from_args.effects.iter().any(|x| x.name() == e.name()) {
            return Err(CliError::input(format!(
                "effect `{}` is already in the model ({}); give it once",
                e.name(),
                from_args.describe()
            )));
        }
        from_args.effects.push(e);
    }
    if from_args.dofs != Dofs::AXIAL {
        return Err(CliError::input("sim: only --dofs axial is supported (the lateral motion depends on the tail's phase, which the quasi-static coupling averages out)"));
    }
    robot.model = from_args;
    Ok(robot)
}

fn tail_index(robot: &Robot, tail: &str) -> Result<usize, CliError> {
    let by_number = tail
        .parse::<usize>()
        .ok()
        .filter(|n| (1..=robot.tails.len()).contains(n))
        .map(|n| n - 1);
    by_number
        .or_else(|| robot.tails.iter().position(|t| t.id == tail))
        .ok_or_else(|| {
            let ids: Vec<&str> = robot.tails.iter().map(|t| t.id.as_str()).collect();
            CliError::input(format!(
                "--tail `{tail}`: not a tail of the robot; give 1..={} or one of: {}",
                robot.tails.len(),
                ids.join(", ")
            ))
        })
}

/// Robot time is simulated in ticks of `tick_us` (1 ms by default): one
/// simulated day is 8.6e7 ticks, about a minute of computing.
const MAX_TIME_S: f64 = 86_400.0;
/// CSV rows of one run (~150 bytes each): bounds the output and memory.
const MAX_SAMPLES: f64 = 1e6;

fn check_times(args: &SimArgs) -> Result<(), CliError> {
    for (name, v) in [
        ("--max-time-s", args.max_time_s),
        ("--sample-every-s", args.sample_every_s),
    ] {
        if !(v.is_finite() && v > 0.0 && v <= MAX_TIME_S) {
            return Err(CliError::input(format!(
                "{name} must be a positive number of seconds up to {MAX_TIME_S} (one day), got {v}"
            )));
        }
    }
    if args.max_time_s / args.sample_every_s > MAX_SAMPLES {
        return Err(CliError::input(format!(
            "--max-time-s / --sample-every-s = {} samples; at most {} (sample less often)",
            crate::format::fmt_sig(args.max_time_s / args.sample_every_s, 3),
            crate::format::fmt_sig(MAX_SAMPLES, 1)
        )));
    }
    Ok(())
}

/// A non-finite state means the motor and cell constants make the motor
/// equations diverge at this time step: an input problem, never NaN output.
fn check_finite(o: &sim::Outcome) -> Result<(), CliError> {
    let bad = o.samples.iter().chain([&o.last]).find(|s| {
        ![
            s.t_s,
            s.battery_v,
            s.current_a,
            s.motor_current_a,
            s.motor_rate_hz,
            s.u_mm_s,
            s.height_mm,
            s.soc,
        ]
        .iter()
        .all(|x| x.is_finite())
    });
    match bad {
        Some(s) => Err(CliError::input(format!(
            "the simulation diverged at t = {} s (a non-finite motor or cell state): check the robot file's [motor], [battery] and [controller] values",
            s.t_s
        ))),
        None => Ok(()),
    }
}

pub fn run(args: SimArgs, inputs: &Inputs) -> Result<(), CliError> {
    let robot = robot_with_model(&args, inputs)?;
    if args.plan.is_some() {
        return super::sim_plan::run(&args, &robot, inputs);
    }
    if args.fit_motor {
        let data = load_data(&args.data, inputs)?;
        let fit = calibrate::fit_motor(&robot, &data)?;
        print!("{}", calibrate::report(&robot, &data, &fit));
        return Ok(());
    }
    let tail = tail_index(&robot, &args.tail)?;
    let replayed = match &args.set_points_from {
        Some(src) => Some(replayed_log(src, &robot, inputs)?),
        None => None,
    };
    let script = match &replayed {
        Some((_, script, _)) => script.clone(),
        None => script_of(&args, inputs)?,
    };
    if script.items.is_empty() {
        return Err(CliError::input(
            "the script is empty: give at least one item, e.g. on@0s",
        ));
    }
    check_times(&args)?;
    check_outputs(&args, inputs)?;
    // A replay ends with the log (a second after its last record) unless
    // the simulated robot stops first.
    let max_time_s = replayed.as_ref().map_or(args.max_time_s, |(log, _, _)| {
        let end = log.points.last().map_or(0.0, |p| p.t_s) + 1.0;
        args.max_time_s.min(end)
    });
    let opts = Options {
        tail,
        max_time_s,
        sample_every_s: args.sample_every_s,
        stop_at_top: !args.no_stop_at_top,
        ..Options::default()
    };
    let rate = match &replayed {
        Some(r) => Some(r.2.clone()),
        None => rate_run(&args)?,
    };
    let outcome = sim::simulate_with(&robot, &script, &opts, rate.as_ref())?;
    check_finite(&outcome)?;
    let log = replayed.as_ref().map(|r| &r.0);
    let (files, notes) = output_files(&args, &robot, &outcome, rate.is_some(), log, inputs)?;
    super::output::write_all_atomically(&files, inputs)?;
    print!("{}", output::summary(&robot, &outcome));
    for n in &notes {
        println!("log vs sim, {n}");
    }
    if rate.is_some() {
        print!("{}", output::rate_summary(&outcome));
    }
    let names: Vec<String> = files.iter().map(|f| f.0.display().to_string()).collect();
    println!("wrote {}", names.join(", "));
    Ok(())
}

/// The script from `--script` or `--script-file` (recorded as an input),
/// else the motor on at time zero.
fn script_of(args: &SimArgs, inputs: &Inputs) -> Result<Script, CliError> {
    Ok(match (&args.script, &args.script_file) {
        (Some(s), _) => Script::parse(s).map_err(SimError::from)?,
        (None, Some(p)) => {
            let text = crate::input_file::read_text(p, crate::input_file::cap::SCRIPT, "a script")
                .map_err(|e| CliError::input(format!("{}: the script: {e}", p.display())))?;
            inputs.record(p, text.as_bytes());
            Script::parse(&text).map_err(|e| CliError::input(format!("{}: {e}", p.display())))?
        }
        (None, None) => Script::on_at_zero(),
    })
}

/// The output folder and `--write-log` file, checked before the run.
fn check_outputs(args: &SimArgs, inputs: &Inputs) -> Result<(), CliError> {
    if let Some(p) = &args.write_log {
        // An earlier --write-log file in the folder is an output, not an input.
        super::output_guard::declare_output_file(p);
    }
    super::output::check_output_dir(&args.output, "sim", inputs)?;
    if let Some(p) = &args.write_log {
        super::output::check_output_file(p, inputs)?;
    }
    Ok(())
}

/// Output files in memory: each path with its bytes.
type Files = Vec<(PathBuf, Vec<u8>)>;

/// Every output file in memory (so that they are renamed into place
/// together and a failure leaves none), the rate plot when the rate
/// controller ran, and the log-vs-sim notes of a replay.
fn output_files(
    args: &SimArgs,
    robot: &Robot,
    outcome: &sim::Outcome,
    rated: bool,
    log: Option<&Trace>,
    inputs: &Inputs,
) -> Result<(Files, Vec<String>), CliError> {
    let svg = output::figure(robot, outcome)
        .map_err(|e| CliError::failure(format!("drawing the plot: {e}")))?;
    let provenance = crate::provenance::Provenance::capture(inputs);
    let mut files = vec![
        (
            args.output.join("sim.csv"),
            (provenance.comment_block() + &output::csv(&outcome.samples)).into_bytes(),
        ),
        (
            args.output.join("sim.svg"),
            provenance.into_svg(&svg).into_bytes(),
        ),
    ];
    if rated {
        let rate_svg = rate_figure::rate_svg(outcome)
            .map_err(|e| CliError::failure(format!("drawing the rate plot: {e}")))?;
        files.push((
            args.output.join("rate.csv"),
            (provenance.comment_block() + &rate_figure::rate_csv(&outcome.rate_trace)).into_bytes(),
        ));
        files.push((
            args.output.join("rate.svg"),
            provenance.into_svg(&rate_svg).into_bytes(),
        ));
    }
    let mut notes = Vec::new();
    if let Some(log) = log {
        let svg;
        (svg, notes) = overlay(log, outcome)?;
        files.push((
            args.output.join("log-vs-sim.svg"),
            provenance.into_svg(&svg).into_bytes(),
        ));
    }
    if let Some(p) = &args.write_log {
        let image = replay::log_image(&outcome.log_records).map_err(CliError::failure)?;
        files.push((p.clone(), image));
    }
    Ok((files, notes))
}

/// The `--rate-hz` schedule with the board's controller and sensor.
fn rate_run(args: &SimArgs) -> Result<Option<RateRun>, CliError> {
    let Some(text) = &args.rate_hz else {
        return Ok(None);
    };
    let points = RateRun::parse_schedule(text).map_err(CliError::input)?;
    let run = RateRun::new(points);
    run.check()
        .and_then(|()| run.check_reached(args.max_time_s))
        .map_err(|e| CliError::input(format!("--rate-hz: {e}")))?;
    Ok(Some(run))
}

/// A run log's trace, and its commands and set-points as a script and a
/// schedule for the board's controller.
fn replayed_log(
    src: &str,
    robot: &Robot,
    inputs: &Inputs,
) -> Result<(Trace, Script, RateRun), CliError> {
    let source = Source::of(src);
    // Replaying an earlier power-up's set-points is a legitimate choice
    // here (the set-points, not the record of today's run, are wanted), so
    // a dropped run does not refuse; it is said, as `swimbot log` says it.
    let (log, _, warnings) = read_current(&source, true, inputs).map_err(CliError::input)?;
    for w in &warnings {
        eprintln!("warning: {}: {w}", source.name());
    }
    let trace = Trace::of(&log);
    let (script, run) = replay::replay(&trace, &robot.keys)
        .map_err(|e| CliError::input(format!("{}: {e}", source.name())))?;
    run.check()
        .map_err(|e| CliError::input(format!("--set-points-from {}: {e}", source.name())))?;
    Ok((trace, script, run))
}

/// The logged run and its simulation overlaid, and their differences.
fn overlay(log: &Trace, outcome: &sim::Outcome) -> Result<(String, Vec<String>), CliError> {
    let sim_trace = replay::log_trace(&outcome.log_records);
    let windows = crate::runlog::steady_windows(log);
    let (steady, all) = log_overlay::compare(log, &windows, &sim_trace);
    let notes = vec![
        log_overlay::describe("in the log's steady windows", &steady),
        log_overlay::describe("every record with both rates", &all),
    ];
    let svg = log_overlay::overlay_svg(log, &sim_trace, &outcome.tail_id, &notes)
        .map_err(|e| CliError::failure(format!("drawing the overlay: {e}")))?;
    Ok((svg, notes))
}
