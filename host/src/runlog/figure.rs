//! The trace figure of a run log (`log.svg`): the set-point with its 2 %
//! band, the measured rate and the steady windows, the events marked and
//! named; the duty and the cell voltage below, on the same time axis.
//! Drawn with the report's chart engine, as `swimbot sim`'s figures are.

use super::steady::{SteadyWindow, STEADY_BAND};
use super::trace::{LogPoint, Trace};
use crate::chart::{stack, Chart, Series, PALETTE};

/// Events drawn on the figure; the rest (ramp done, started, the battery
/// level's every reading) would bury them.
const MARKED: [&str; 16] = [
    "On",
    "Off",
    "stopped (run-time limit)",
    "stopped (low battery)",
    "stopped (battery fault)",
    "start refused",
    "set-point key",
    "On without set-point",
    "cut-off latched",
    "remote paired",
    "edges dropped",
    "USB connected",
    "fault: stalled",
    "fault: reversed",
    "fault: sensor disconnected",
    "fault: overspeed",
];

/// At most this many event labels (a key held down repeats).
const MAX_MARKS: usize = 40;

/// `(t_s, words)` of the events worth marking. A new set-point is marked
/// too: the robot's keys flag it, a log written by `swimbot sim`
/// (set-points from a schedule) does not.
pub fn marks(points: &[LogPoint]) -> Vec<(f64, String)> {
    let mut before = None;
    points
        .iter()
        .filter_map(|p| {
            let mut w: Vec<String> = p
                .events
                .iter()
                .filter(|e| MARKED.contains(e))
                .map(|e| e.to_string())
                .collect();
            if let (Some(f), Some(b)) = (p.set_hz, before) {
                if f != b {
                    w.push(format!("set {f} Hz"));
                }
            }
            before = p.set_hz.or(before);
            (!w.is_empty()).then(|| (p.t_s, w.join(", ")))
        })
        .take(MAX_MARKS)
        .collect()
}

/// Lines through the points where `f` has a value, broken where it has
/// none and across gaps in the log (the robot records only while the motor
/// may run: a line across an Off would show values nobody measured). Only
/// the first piece carries the legend label.
pub fn curve(
    label: &str,
    color: crate::chart::Rgb,
    points: &[LogPoint],
    f: &dyn Fn(&LogPoint) -> Option<f64>,
) -> Vec<Series> {
    let gap_s = 2.5 * sample_period_s(points);
    let mut pieces: Vec<Vec<(f64, f64, f64)>> = Vec::new();
    let mut last_t = f64::NEG_INFINITY;
    let mut open = false;
    for p in points {
        match f(p).filter(|y| y.is_finite()) {
            Some(y) => {
                if !open || p.t_s - last_t > gap_s {
                    pieces.push(Vec::new());
                }
                if let Some(piece) = pieces.last_mut() {
                    piece.push((p.t_s, y, 0.0));
                }
                (open, last_t) = (true, p.t_s);
            }
            None => open = false,
        }
    }
    pieces
        .into_iter()
        .enumerate()
        .map(|(k, pts)| Series::curve(if k == 0 { label } else { "" }, color, pts))
        .collect()
}

/// The log's usual spacing: the median interval between records.
fn sample_period_s(points: &[LogPoint]) -> f64 {
    let mut d: Vec<f64> = points.windows(2).map(|w| w[1].t_s - w[0].t_s).collect();
    d.sort_by(f64::total_cmp);
    d.get(d.len() / 2).copied().unwrap_or(0.1).max(1e-3)
}

/// The rate panel's series: set-point and band, measured rate, windows,
/// events (at the set-point's height, or the rate's).
pub fn rate_series(trace: &Trace, windows: &[SteadyWindow], label: &str) -> Vec<Series> {
    let [c0, _, c2, c3, c4, ..] = PALETTE;
    let pts = &trace.points;
    let band = format!("set-point +-{} %", 100.0 * STEADY_BAND);
    let dashed = |v: Vec<Series>| v.into_iter().map(Series::dashed);
    let upper = |p: &LogPoint| p.set_hz.map(|f| f * (1.0 + STEADY_BAND));
    let lower = |p: &LogPoint| p.set_hz.map(|f| f * (1.0 - STEADY_BAND));
    let mut out: Vec<Series> = dashed(curve("set-point", c3, pts, &|p| p.set_hz))
        .chain(dashed(curve(&band, c2, pts, &upper)))
        .chain(dashed(curve("", c2, pts, &lower)))
        .chain(curve(label, c0, pts, &|p| p.rate_hz))
        .collect();
    for (k, w) in windows.iter().enumerate() {
        let name = if k == 0 { "steady window (mean)" } else { "" };
        out.push(Series::curve(
            name,
            c4,
            vec![(w.from_s, w.mean_hz, 0.0), (w.to_s, w.mean_hz, 0.0)],
        ));
    }
    let m = marks(pts);
    if !m.is_empty() {
        let y_at = |t: f64| {
            pts.iter()
                .find(|p| p.t_s >= t)
                .and_then(|p| p.set_hz.or(p.rate_hz))
                .unwrap_or(0.0)
        };
        let points = m.iter().map(|(t, _)| (*t, y_at(*t), 0.0)).collect();
        let labels = m.into_iter().map(|(_, w)| w).collect();
        out.push(Series::measured("event", c3, points).labels(labels));
    }
    out
}

/// The whole figure.
pub fn svg(trace: &Trace, windows: &[SteadyWindow], title: &str) -> crate::chart::PlotResult {
    let [c0, ..] = PALETTE;
    let pts = &trace.points;
    let t_end = pts.last().map_or(1.0, |p| p.t_s).max(1e-3);
    let t0 = pts.first().map_or(0.0, |p| p.t_s).min(t_end - 1e-3);
    let panel = |y: &str, x: &str| Chart::new("", x, y).size(760, 190).x_range(t0, t_end);
    let panels = vec![
        (
            panel("motor rate (Hz)", "").size(760, 320),
            rate_series(trace, windows, "measured, one-turn mean"),
        ),
        (
            panel("duty", ""),
            curve("PWM duty", c0, pts, &|p| Some(p.duty)),
        ),
        (
            panel("cell, loaded (V)", "time since power-up (s)"),
            curve("battery monitor", c0, pts, &|p| p.cell_v),
        ),
    ];
    stack(title, &panels)
}
