//! The figure `swimbot sim` writes: stacked panels sharing the time axis
//! (nose height with the channel's top; U; tail, motor and body rates; cell
//! voltage; cell and motor current), drawn with the report's chart engine,
//! with the observed f, U and Omega_b of the simulated tail as dashed
//! reference lines when the robot file or the paper's data give them.

use super::dynamics::{Outcome, Sample};
use super::robot::Robot;
use crate::chart::{stack, Chart, Series, PALETTE};

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
        let Some((i, tail)) = robot
            .tails
            .iter()
            .enumerate()
            .find(|(_, t)| t.id == tail_id)
        else {
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
pub fn svg(o: &Outcome) -> crate::chart::PlotResult {
    svg_with(o, &Observed::default())
}

/// The run as an SVG with the robot's and the paper's observed f, U and
/// Omega_b for this tail drawn as reference lines.
pub fn figure(robot: &Robot, o: &Outcome) -> crate::chart::PlotResult {
    svg_with(o, &Observed::of(robot, &o.tail_id))
}

/// Stacked panels: height, U, rates, cell voltage, currents.
pub fn svg_with(o: &Outcome, obs: &Observed) -> crate::chart::PlotResult {
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
    // The channel's top is drawn when the climb gets near it; far away it
    // would squash the height curve flat.
    let (h0, h1) = o.samples.iter().fold((f64::MAX, f64::MIN), |(a, b), s| {
        (a.min(s.height_mm), b.max(s.height_mm))
    });
    let mut height = panel("height (mm)", "");
    if o.top_reached_s.is_some() || o.channel_length_mm - h1 < (h1 - h0).max(0.0) {
        height = height.hline(o.channel_length_mm, "channel top", c1);
    }
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
        (height, vec![line("nose height", c0, |s| s.height_mm)]),
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
    use crate::chart::legend_clear;
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
        let case = paper
            .cases
            .iter()
            .find(|c| c.id == o.tail_id)
            .expect("paper case");
        assert_eq!(obs.u_mm_s, case.u_mm_s.map(|m| m.mean));
        assert_eq!(obs.omega_b_hz, case.omega_body_hz.map(|m| m.mean));
        let svg = figure(&robot, &o).expect("figure");
        legend_clear(&svg).expect("legends clear");
        for needle in [
            "observed U (paper, tail-1)",
            "observed tail f (robot file)",
            "time (s)",
        ] {
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
