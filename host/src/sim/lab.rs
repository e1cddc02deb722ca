//! The simulated lab: a run sheet (the one `swimbot plan` writes) run row
//! by row through the whole robot, with a truth model standing in for the
//! world, so that the loop plan -> runs -> study can be tried without a
//! robot.
//!
//! Each row is one run of the robot: its body, tube and oil are the row's,
//! its tail the row's geometry (the robot's first tail's moment of inertia:
//! a tail of the same wire, whose inertia matters to the start-up only),
//! the swimmer model the truth. The firmware's controller holds the row's
//! set-point (`labels.set_point_hz`, the motor's rate; else the row's
//! `frequency_hz`) from an On at 0 s until the run's expected duration
//! (`labels.duration_s`) or the tube's top, capped at
//! [`LabSettings::max_run_s`]. What a camera then records, over the steady
//! window (the motor's rate within 2 % of the set-point):
//!
//! - `frequency_hz`: the tail's mean rate in the lab frame;
//! - `u_mm_s`, `omega_body_hz`: the means of U and of the body's
//!   counter-rotation, each measured as `trials` trials with relative
//!   Gaussian noise ([`crate::workbench::synth::measure`]; seeded per row).
//!
//! The robot's run log is kept as the firmware keeps it (the shared
//! recorder fed every pass), so `swimbot log` reads the simulated runs as
//! it reads a robot's.

use super::dynamics::{simulate_with, Options};
use super::rate::RateRun;
use super::robot::{Robot, Tail};
use super::script::Script;
use crate::data::{Case, Dataset};
use crate::model::Model;
use crate::workbench::synth::{measure, SynthSettings};
use rand::rngs::StdRng;
use rand::SeedableRng;
use swimbot_shared::MotorState;

/// How the lab measures.
#[derive(Debug, Clone, Copy)]
pub struct LabSettings {
    /// Noise, trials, seed and confidence of each measured quantity.
    pub measurement: SynthSettings,
    /// The longest run (s): a camera needs a steady window, not the whole climb.
    pub max_run_s: f64,
}

impl Default for LabSettings {
    fn default() -> Self {
        LabSettings {
            measurement: SynthSettings::default(),
            max_run_s: 120.0,
        }
    }
}

/// The steady window must hold this long (s) for a run to be measured.
pub const MIN_STEADY_S: f64 = 5.0;

/// One simulated run: the row measured, its run log image, the window.
#[derive(Debug, Clone)]
pub struct LabRun {
    pub case: Case,
    pub log_image: Vec<u8>,
    pub set_point_hz: f64,
    pub steady_s: f64,
}

/// Why a row could not be run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("row {row} (case `{case}`): {message}")]
pub struct LabError {
    /// 1-based, among the sheet's rows.
    pub row: usize,
    pub case: String,
    pub message: String,
}

fn label_f64(c: &Case, key: &str) -> Option<f64> {
    c.recorded
        .labels
        .iter()
        .find(|(k, _)| k == key)
        .and_then(|(_, v)| v.trim().parse::<f64>().ok())
        .filter(|v| v.is_finite() && *v > 0.0)
}

/// The robot carrying the row's tail in the row's tube and oil, the truth
/// its swimmer model.
fn robot_for(robot: &Robot, truth: &Model, row: &Case) -> Robot {
    let inertia = robot.tails.first().map_or(0.0, |t| t.load_inertia_kg_m2);
    let mut r = robot.clone();
    r.setup = row.clone();
    r.start_height_mm = None;
    r.model = truth.clone();
    r.tails = vec![Tail {
        id: row.id.clone(),
        wavelength_mm: row.wavelength_mm,
        amplitude_mm: row.amplitude_mm,
        length_mm: row.tail_length_mm,
        wire_diameter_mm: row.wire_diameter_mm,
        handedness: row.handedness,
        load_inertia_kg_m2: inertia,
        observed_f_hz: None,
    }];
    r
}

/// Run one row (module docs); `row` numbers it in errors.
pub fn run_row(
    robot: &Robot,
    truth: &Model,
    case: &Case,
    row: usize,
    s: &LabSettings,
) -> Result<LabRun, LabError> {
    let fail = |message: String| LabError {
        row,
        case: case.id.clone(),
        message,
    };
    let set_hz = label_f64(case, "set_point_hz").unwrap_or(case.frequency_hz);
    let run_s = label_f64(case, "duration_s")
        .unwrap_or(s.max_run_s)
        .min(s.max_run_s);
    let r = robot_for(robot, truth, case);
    let rate = RateRun::new(vec![(0, set_hz)]);
    rate.check()
        .map_err(|e| fail(format!("set-point {set_hz} Hz: {e}")))?;
    let opts = Options {
        tail: 0,
        max_time_s: run_s,
        sample_every_s: 0.1,
        stop_at_top: true,
        ..Options::default()
    };
    let o = simulate_with(&r, &Script::on_at_zero(), &opts, Some(&rate))
        .map_err(|e| fail(e.to_string()))?;
    let steady: Vec<_> = o
        .samples
        .iter()
        .filter(|p| {
            p.state == MotorState::Running
                && ((p.motor_rate_hz - set_hz) / set_hz).abs() < 0.02
                && [p.u_mm_s, p.tail_rate_hz, p.body_rate_hz]
                    .iter()
                    .all(|x| x.is_finite())
        })
        .collect();
    let steady_s = steady.len() as f64 * opts.sample_every_s;
    if steady_s < MIN_STEADY_S {
        return Err(fail(format!(
            "the robot held {set_hz} Hz within 2 % for {steady_s:.1} s of the {run_s:.0} s run, under the {MIN_STEADY_S} s a measurement needs (the run ended: {:?})",
            o.end
        )));
    }
    let mean = |f: &dyn Fn(&super::outcome::Sample) -> f64| {
        steady.iter().map(|p| f(p)).sum::<f64>() / steady.len() as f64
    };
    let mut rng = StdRng::seed_from_u64(
        s.measurement
            .seed
            .wrapping_mul(1_000_003)
            .wrapping_add(row as u64),
    );
    let mut measured = case.clone();
    measured.frequency_hz = mean(&|p| p.tail_rate_hz);
    measured.u_mm_s = Some(measure(mean(&|p| p.u_mm_s), &s.measurement, &mut rng));
    measured.omega_body_hz = Some(measure(
        mean(&|p| -p.body_rate_hz),
        &s.measurement,
        &mut rng,
    ));
    let log_image =
        super::replay::log_image(&o.log_records).map_err(|e| fail(format!("the run log: {e}")))?;
    Ok(LabRun {
        case: measured,
        log_image,
        set_point_hz: set_hz,
        steady_s,
    })
}

/// Every row of `sheet` run (module docs), in order.
pub fn run_sheet(
    robot: &Robot,
    truth: &Model,
    sheet: &Dataset,
    s: &LabSettings,
) -> Result<Vec<LabRun>, LabError> {
    use rayon::prelude::*;
    sheet
        .cases
        .par_iter()
        .enumerate()
        .map(|(i, c)| run_row(robot, truth, c, i + 1, s))
        .collect()
}
