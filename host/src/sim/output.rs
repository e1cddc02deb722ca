//! What `swimbot sim` writes: the time series as CSV, a five-panel SVG
//! (height; U; tail, motor and body rates; cell voltage; cell current) drawn
//! with the report's chart engine, observed values as dashed reference lines, and the text summary (time to the
//! channel's top, mean U, f and Omega_b while running, battery left, the
//! energy ledger).

use super::dynamics::{End, Outcome, Sample};
use super::robot::Robot;
use crate::format::fmt_sig;
use crate::report::plots::{stack, Chart, Series, PALETTE};
use std::fmt::Write as _;
use swimbot_shared::MotorState as State;

pub const CSV_HEADER: &str = "time_s,duty,battery_v,current_a,motor_current_a,motor_rate_hz,tail_rate_hz,body_rate_hz,u_mm_s,height_mm,soc,state";

fn state_name(s: State) -> &'static str {
    match s {
        State::Off => "off",
        State::Ramping => "ramping",
        State::Running => "running",
    }
}

/// The samples as CSV text (header first).
pub fn csv(samples: &[Sample]) -> String {
    let mut out = String::with_capacity(100 * (samples.len() + 1));
    out.push_str(CSV_HEADER);
    out.push('\n');
    for s in samples {
        let _ = writeln!(
            out,
            "{:.3},{:.5},{:.5},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.4},{:.6},{}",
            s.t_s,
            s.duty,
            s.battery_v,
            s.current_a,
            s.motor_current_a,
            s.motor_rate_hz,
            s.tail_rate_hz,
            s.body_rate_hz,
            s.u_mm_s,
            s.height_mm,
            s.soc,
            state_name(s.state)
        );
    }
    out
}

/// Observed values of the simulated tail, drawn as dashed reference lines.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Observed {
    pub f_hz: Option<f64>,
    pub u_mm_s: Option<f64>,
    pub omega_b_hz: Option<f64>,
    /// Where U and Omega_b come from (legend text), e.g. "paper, tail-1".
    pub source: String,
}

impl Observed {
    /// The robot file's observed f for the simulated tail, and the paper's
    /// measured U and Omega_b when the built-in data has a case with the
    /// same id, tail geometry, channel and oil (the paper's own robot).
    pub fn of(robot: &Robot, tail_id: &str) -> Self {
        let Some((i, tail)) = robot.tails.iter().enumerate().find(|(_, t)| t.id == tail_id) else {
            return Self::default();
        };
        let mine = robot.case(i, tail.observed_f_hz.unwrap_or(1.0));
        let same = |a: f64, b: f64| (a - b).abs() <= 1e-6 * a.abs().max(b.abs()).max(1e-12);
        let paper = crate::data::paper();
        let case = paper.cases.iter().find(|c| {
            c.id == mine.id
                && same(c.wavelength_mm, mine.wavelength_mm)
                && same(c.amplitude_mm, mine.amplitude_mm)
                && same(c.tail_length_mm, mine.tail_length_mm)
                && same(c.wire_diameter_mm, mine.wire_diameter_mm)
                && same(c.channel_diameter_mm, mine.channel_diameter_mm)
                && same(c.viscosity_pa_s, mine.viscosity_pa_s)
        });
        Self {
            f_hz: tail.observed_f_hz,
            u_mm_s: case.and_then(|c| c.u_mm_s).map(|m| m.mean),
            omega_b_hz: case.and_then(|c| c.omega_body_hz).map(|m| m.mean),
            source: case.map_or(String::new(), |c| format!("paper, {}", c.id)),
        }
    }
}

/// The run as an SVG of stacked panels sharing the time axis, without
/// observed reference values.
pub fn svg(o: &Outcome) -> Result<String, String> {
    svg_with(o, &Observed::default())
}

/// The run as an SVG with the robot's and the paper's observed f, U and
/// Omega_b for this tail drawn as reference lines.
pub fn figure(robot: &Robot, o: &Outcome) -> Result<String, String> {
    svg_with(o, &Observed::of(robot, &o.tail_id))
}

/// Stacked panels: height, U, rates, cell voltage, currents.
pub fn svg_with(o: &Outcome, obs: &Observed) -> Result<String, String> {
    let line = |label: &str, color, f: fn(&Sample) -> f64| {
        Series::curve(
            label,
            color,
            o.samples.iter().map(|s| (s.t_s, f(s), 0.0)).collect(),
        )
    };
    let [c0, c1, c2, ..] = PALETTE;
    let t_end = o.samples.last().map_or(1.0, |s| s.t_s).max(1e-3);
    let panel = |y: &str, x: &str| Chart::new("", x, y).size(760, 175).x_range(0.0, t_end);
    let source = |q: &str| match obs.source.as_str() {
        "" => format!("observed {q}"),
        s => format!("observed {q} ({s})"),
    };
    let mut u = panel("U (mm/s)", "");
    if let Some(v) = obs.u_mm_s {
        u = u.hline(v, source("U"), c1);
    }
    // Taller: five legend entries must fit between the lines.
    let mut rates = panel("rate (Hz)", "").size(760, 250);
    if let Some(v) = obs.f_hz {
        rates = rates.hline(v, "observed tail f (robot file)", c0);
    }
    if let Some(v) = obs.omega_b_hz {
        rates = rates.hline(v, source("Omega_b"), c2);
    }
    let panels = vec![
        (
            panel("height (mm)", "").hline(o.channel_length_mm, "channel top", c1),
            vec![line("nose height", c0, |s| s.height_mm)],
        ),
        (u, vec![line("U simulated", c0, |s| s.u_mm_s)]),
        (
            rates,
            vec![
                line("tail f (lab)", c0, |s| s.tail_rate_hz),
                line("motor (tail - body)", c1, |s| s.motor_rate_hz),
                line("body counter-rotation Omega_b", c2, |s| -s.body_rate_hz),
            ],
        ),
        (
            panel("cell (V)", ""),
            vec![line("terminal voltage", c0, |s| s.battery_v)],
        ),
        (
            panel("current (A)", "time (s)"),
            vec![
                line("cell", c0, |s| s.current_a),
                line("motor", c1, |s| s.motor_current_a),
            ],
        ),
    ];
    stack(&format!("swimbot sim: {}", o.tail_id), &panels)
}

#[cfg(test)]
mod figure_tests {
    use super::*;
    use crate::report::plots::legend_clear;
    use crate::sim::{default_robot, simulate, Options, Script};

    fn run(robot: &Robot) -> Outcome {
        let script = Script::parse("on@0s,off@20s").expect("script");
        let opts = Options {
            max_time_s: 25.0,
            ..Options::default()
        };
        simulate(robot, &script, &opts).expect("simulation")
    }

    #[test]
    fn the_sim_figure_shows_observed_values_and_legends_cover_nothing() {
        let robot = default_robot();
        let o = run(&robot);
        let obs = Observed::of(&robot, &o.tail_id);
        assert_eq!(obs.f_hz, robot.tails[0].observed_f_hz);
        let paper = crate::data::paper();
        let case = paper.cases.iter().find(|c| c.id == o.tail_id).expect("paper case");
        assert_eq!(obs.u_mm_s, case.u_mm_s.map(|m| m.mean));
        assert_eq!(obs.omega_b_hz, case.omega_body_hz.map(|m| m.mean));
        let svg = figure(&robot, &o).expect("figure");
        legend_clear(&svg).expect("legends clear");
        for needle in ["observed U (paper, tail-1)", "observed tail f (robot file)", "time (s)"] {
            assert!(svg.contains(needle), "{needle}");
        }
        // One time-axis title (the bottom panel's), so none collides.
        assert_eq!(svg.matches("time (s)").count(), 1);
    }

    #[test]
    fn a_tail_unlike_the_papers_gets_no_paper_values() {
        let mut robot = default_robot();
        robot.tails[0].wavelength_mm *= 1.1;
        let obs = Observed::of(&robot, &robot.tails[0].id.clone());
        assert_eq!(obs.u_mm_s, None);
        assert_eq!(obs.omega_b_hz, None);
        assert_eq!(obs.f_hz, robot.tails[0].observed_f_hz);
        assert_eq!(Observed::of(&robot, "no-such-tail"), Observed::default());
    }
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
        "motor load from the model: {} N m + {} N m s x motor rate  (tail torque per tail rate; body turns {} rad/s per rad/s)",
        fmt_sig(h.tau0_n_m, 3),
        fmt_sig(h.damping_n_m_s, 4),
        fmt_sig(h.dv[3], 3)
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
