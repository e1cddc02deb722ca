//! What `swimbot sim` writes: the time series as CSV, a four-panel SVG
//! (height; tail, motor and body rates; cell voltage; cell current) drawn
//! with plotters in the report's style, and the text summary (time to the
//! channel's top, mean U, f and Omega_b while running, battery left, the
//! energy ledger).

use super::dynamics::{End, Outcome, Sample};
use super::robot::Robot;
use crate::format::fmt_sig;
use crate::report::plots::PALETTE;
use plotters::prelude::*;
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

type Panel<'a> = (&'a str, Vec<(&'a str, Vec<(f64, f64)>)>);

/// The run as an SVG of four stacked panels sharing the time axis.
pub fn svg(o: &Outcome) -> Result<String, String> {
    let t: Vec<f64> = o.samples.iter().map(|s| s.t_s).collect();
    let series = |f: fn(&Sample) -> f64| -> Vec<(f64, f64)> {
        t.iter().zip(&o.samples).map(|(t, s)| (*t, f(s))).collect()
    };
    let panels: Vec<Panel> = vec![
        (
            "height (mm)",
            vec![("nose height", series(|s| s.height_mm))],
        ),
        (
            "rate (Hz)",
            vec![
                ("tail f (lab)", series(|s| s.tail_rate_hz)),
                ("motor (tail - body)", series(|s| s.motor_rate_hz)),
                ("body counter-rotation", series(|s| -s.body_rate_hz)),
            ],
        ),
        ("cell (V)", vec![("terminal", series(|s| s.battery_v))]),
        (
            "current (A)",
            vec![
                ("cell", series(|s| s.current_a)),
                ("motor", series(|s| s.motor_current_a)),
            ],
        ),
    ];
    let t_end = t.last().copied().unwrap_or(1.0).max(1e-3);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 760)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let root = root
            .titled(&format!("swimbot sim: {}", o.tail_id), ("sans-serif", 17))
            .map_err(|e| e.to_string())?;
        for (area, (y_desc, lines)) in root.split_evenly((panels.len(), 1)).iter().zip(&panels) {
            let ys = lines
                .iter()
                .flat_map(|l| l.1.iter().map(|p| p.1))
                .filter(|v| v.is_finite());
            let (lo, hi) = ys.fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
            let (lo, hi) = if lo > hi { (0.0, 1.0) } else { (lo, hi) };
            let pad = 0.08 * (hi - lo).max(1e-9 * hi.abs().max(1.0));
            let mut c = ChartBuilder::on(area)
                .margin(8)
                .x_label_area_size(28)
                .y_label_area_size(62)
                .build_cartesian_2d(0.0..t_end, (lo - pad)..(hi + pad))
                .map_err(|e| e.to_string())?;
            c.configure_mesh()
                .x_desc("time (s)")
                .y_desc(*y_desc)
                .light_line_style(WHITE.mix(0.0))
                .draw()
                .map_err(|e| e.to_string())?;
            for (k, (label, pts)) in lines.iter().enumerate() {
                let color = PALETTE[k % PALETTE.len()];
                c.draw_series(LineSeries::new(pts.iter().copied(), color.stroke_width(2)))
                    .map_err(|e| e.to_string())?
                    .label(*label)
                    .legend(move |(x, y)| {
                        PathElement::new([(x, y), (x + 16, y)], color.stroke_width(2))
                    });
            }
            c.configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.3))
                .label_font(("sans-serif", 11))
                .draw()
                .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
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
