//! The figure and table of a rate-controlled `swimbot sim` run
//! (`rate.svg`, `rate.csv`): the step responses, i.e. the set-point with
//! its 2 % band, the true motor rate and the sensor's turn-averaged
//! reading, above the duty and the cell voltage that produced them.

use super::dynamics::Outcome;
use super::rate::RatePoint;
use super::step_response::SETTLE_BAND;
use crate::chart::{stack, Chart, Series, PALETTE};
use std::fmt::Write as _;

pub const RATE_CSV_HEADER: &str =
    "time_s,set_hz,reference_hz,measured_hz,motor_rate_hz,duty,battery_v,running";

/// Points drawn per curve at most: the trace is every 10 ms.
const MAX_POINTS: usize = 3_000;

/// The trace as CSV (empty `measured_hz` before the sensor's first rate).
pub fn rate_csv(trace: &[RatePoint]) -> String {
    let mut out = String::with_capacity(80 * (trace.len() + 1));
    out.push_str(RATE_CSV_HEADER);
    out.push('\n');
    for p in trace {
        let measured = if p.measured_hz.is_finite() {
            p.measured_hz.to_string()
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            "{},{},{},{},{},{},{},{}",
            (p.t_s * 1e6).round() / 1e6,
            p.set_hz,
            p.reference_hz,
            measured,
            p.motor_rate_hz,
            p.duty,
            p.battery_v,
            p.running
        );
    }
    out
}

/// Stacked panels: rates with the set-point band, duty, cell voltage.
pub fn rate_svg(o: &Outcome) -> crate::chart::PlotResult {
    let step = o.rate_trace.len().div_ceil(MAX_POINTS).max(1);
    let pts: Vec<&RatePoint> = o.rate_trace.iter().step_by(step).collect();
    let curve = |label: &str, color, f: &dyn Fn(&RatePoint) -> f64| {
        let points = pts
            .iter()
            .map(|p| (p.t_s, f(p), 0.0))
            .filter(|p| p.1.is_finite())
            .collect();
        Series::curve(label, color, points)
    };
    let [c0, c1, c2, c3, ..] = PALETTE;
    let t_end = pts.last().map_or(1.0, |p| p.t_s).max(1e-3);
    let panel = |y: &str, x: &str| Chart::new("", x, y).size(760, 190).x_range(0.0, t_end);
    let band = format!("set-point +-{} %", 100.0 * SETTLE_BAND);
    let panels = vec![
        (
            panel("motor rate (Hz)", "").size(760, 300),
            vec![
                curve("set-point", c3, &|p| p.set_hz).dashed(),
                curve(&band, c2, &|p| p.set_hz * (1.0 + SETTLE_BAND)).dashed(),
                curve("", c2, &|p| p.set_hz * (1.0 - SETTLE_BAND)).dashed(),
                curve("motor rate (true)", c0, &|p| p.motor_rate_hz),
                curve("sensor, one-turn mean", c1, &|p| p.measured_hz),
            ],
        ),
        (panel("duty", ""), vec![curve("PWM duty", c0, &|p| p.duty)]),
        (
            panel("cell (V)", "time (s)"),
            vec![curve("terminal voltage", c0, &|p| p.battery_v)],
        ),
    ];
    stack(
        &format!("swimbot sim: rate control, {}", o.tail_id),
        &panels,
    )
}
