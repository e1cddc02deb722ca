//! What `swimbot sim` writes: the time series as CSV, the SVG figure
//! ([`super::figure`]) and the text summary (time to the
//! channel's top, mean U, f and Omega_b while running, battery left, the
//! energy ledger).

use super::dynamics::{End, Outcome, Sample};
pub use super::figure::{figure, svg, svg_with, Observed};
use super::robot::Robot;
use crate::format::fmt_sig;
use std::fmt::Write as _;
use swimbot_shared::MotorState as State;

/// Rates: the tail's in the lab frame, the motor's relative (tail - body),
/// and the body's as Omega_b, its counter-rotation, positive when it turns
/// against the tail (the paper's Table IV convention, as in every output).
pub const CSV_HEADER: &str = "time_s,duty,battery_v,current_a,motor_current_a,motor_rate_hz,tail_rate_hz,omega_body_counter_hz,u_mm_s,height_mm,soc,state";

fn state_name(s: State) -> &'static str {
    match s {
        State::Off => "off",
        State::Ramping => "ramping",
        State::Running => "running",
    }
}

/// The samples as CSV text (header first), numbers in the one CSV style
/// of `crate::format` (shortest round-trip decimals).
pub fn csv(samples: &[Sample]) -> String {
    let mut out = String::with_capacity(100 * (samples.len() + 1));
    out.push_str(CSV_HEADER);
    out.push('\n');
    for s in samples {
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{},{}",
            // Robot time is whole microsecond ticks: rounding there drops
            // the float sum's 0.09999999999999999.
            (s.t_s * 1e6).round() / 1e6,
            s.duty,
            s.battery_v,
            s.current_a,
            s.motor_current_a,
            s.motor_rate_hz,
            s.tail_rate_hz,
            // The lab-frame body rate is negative when the body counter-rotates
            // (`0.0 -` so that rest prints 0, not -0).
            0.0 - s.body_rate_hz,
            s.u_mm_s,
            s.height_mm,
            s.soc,
            state_name(s.state)
        );
    }
    out
}

/// The run in a few lines.
pub fn summary(robot: &Robot, o: &Outcome) -> String {
    let mut s = String::new();
    let h = &o.hydro;
    let last = &o.last;
    let _ = writeln!(
        s,
        "robot: {}\ntail:  {}   model: {}",
        robot.name,
        o.tail_id,
        robot.model.describe()
    );
    let _ = writeln!(
        s,
        "motor load from the model: {} N m + {} N m s x motor rate  (tail torque per tail rate; the body counter-rotates {} rad/s per rad/s of motor rate)",
        fmt_sig(h.tau0_n_m, 3),
        fmt_sig(h.damping_n_m_s, 4),
        fmt_sig(0.0 - h.dv[3], 3)
    );
    let end = match o.end {
        End::TopReached => "the nose reached the channel's top".to_string(),
        End::Stopped(r) => format!("the controller stopped the motor ({r:?})"),
        End::SensorFault(f) => format!("the rate sensor showed a fault ({f:?}): motor stopped"),
        End::Idle => "script done, robot at rest".to_string(),
        End::TimeLimit => "time limit".to_string(),
    };
    let _ = writeln!(
        s,
        "end:   {end} at {} s ({} ticks)",
        fmt_sig(last.t_s, 5),
        o.ticks
    );
    let climb = o.channel_length_mm - o.start_height_mm;
    match o.top_reached_s {
        Some(t) => {
            let _ = writeln!(
                s,
                "time to the top of the {} mm channel: {} s (climb of {} mm from {} mm)",
                fmt_sig(o.channel_length_mm, 4),
                fmt_sig(t, 4),
                fmt_sig(climb, 4),
                fmt_sig(o.start_height_mm, 4)
            );
        }
        None => {
            let _ = writeln!(
                s,
                "top of the {} mm channel not reached: nose at {} mm (started at {} mm)",
                fmt_sig(o.channel_length_mm, 4),
                fmt_sig(last.height_mm, 4),
                fmt_sig(o.start_height_mm, 4)
            );
        }
    }
    if o.running_s <= 0.0 {
        let _ = writeln!(
            s,
            "the motor never ran (no valid On command took effect): no mean U, f or Omega_b"
        );
    } else {
        let _ = writeln!(
        s,
        "while running ({} s): mean U {} mm/s, tail f {} Hz (lab), body counter-rotation Omega_b {} Hz",
        fmt_sig(o.running_s, 4),
        fmt_sig(o.mean_u_mm_s, 4),
        fmt_sig(o.mean_f_hz, 4),
        fmt_sig(o.mean_omega_b_hz, 4)
    );
    }
    if let Some(f) = robot
        .tails
        .iter()
        .find(|t| t.id == o.tail_id)
        .and_then(|t| t.observed_f_hz)
        .filter(|_| o.running_s > 0.0)
    {
        let _ = writeln!(
            s,
            "observed f with this tail (paper): {} Hz -> simulated/observed = {}",
            fmt_sig(f, 3),
            fmt_sig(o.mean_f_hz / f, 3)
        );
    }
    let _ = writeln!(
        s,
        "battery left: {:.1} % ({} mAh of {}), terminal {} V",
        100.0 * last.soc,
        fmt_sig(last.soc * robot.cell.capacity_mah, 3),
        fmt_sig(robot.cell.capacity_mah, 3),
        fmt_sig(last.battery_v, 4)
    );
    let e = &o.energy;
    let _ = writeln!(
        s,
        "energy (J): cell {} = internal {} + winding {} + diode {} + friction {} + hydrodynamic {} + stored {} - external {}; residual {}",
        fmt_sig(e.cell_j, 4),
        fmt_sig(e.internal_j, 3),
        fmt_sig(e.winding_j, 3),
        fmt_sig(e.diode_j, 3),
        fmt_sig(e.friction_j, 3),
        fmt_sig(e.hydro_j, 3),
        fmt_sig(e.stored_j, 3),
        fmt_sig(e.external_j, 3),
        fmt_sig(e.residual_j(), 3)
    );
    s
}

/// The step responses of a rate-controlled run, one line each, and the
/// lab-frame rate the set-point means for this tail (the sensor sees the
/// motor's rate, tail relative to body; a camera sees the tail's).
pub fn rate_summary(o: &Outcome) -> String {
    use super::step_response::{step_metrics, SETTLE_BAND};
    let mut s = String::new();
    let lab_per_motor = 1.0 + o.hydro.dv[3];
    let _ = writeln!(
        s,
        "rate control: set-points are the motor's rate; the tail turns {} times that in the lab",
        fmt_sig(lab_per_motor, 3)
    );
    for m in step_metrics(&o.rate_trace) {
        let settle = m.settle_s.map_or_else(
            || format!("not within {} %", 100.0 * SETTLE_BAND),
            |t| {
                format!(
                    "settled within {} % in {} s",
                    100.0 * SETTLE_BAND,
                    fmt_sig(t, 3)
                )
            },
        );
        let step = if m.from_hz == 0.0 {
            format!("start to {} Hz", fmt_sig(m.to_hz, 3))
        } else {
            format!(
                "step {} -> {} Hz at {} s",
                fmt_sig(m.from_hz, 3),
                fmt_sig(m.to_hz, 3),
                fmt_sig(m.at_s, 4)
            )
        };
        let _ = writeln!(
            s,
            "  {step}: {settle}, overshoot {} % of the step, steady error {} %",
            fmt_sig(100.0 * m.overshoot, 2),
            fmt_sig(100.0 * m.steady_error, 2),
        );
    }
    for (t, e) in &o.rate_faults {
        let _ = writeln!(s, "  at {} s: {e:?}", fmt_sig(*t, 4));
    }
    s
}
