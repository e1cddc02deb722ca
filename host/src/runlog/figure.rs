//! The trace figure of a run log (`log.svg`): the set-point with its 2 %
//! band, the measured rate and the steady windows, the events marked and
//! named; the duty and the cell voltage below, on the same time axis.
//! Drawn with the report's chart engine, as `swimbot sim`'s figures are.

use super::steady::{SteadyWindow, STEADY_BAND};
use super::trace::{LogPoint, Trace};
use crate::report::plots::{stack, Chart, Series, PALETTE};

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

/// `(t_s, words)` of the events worth marking.
pub fn marks(points: &[LogPoint]) -> Vec<(f64, String)> {
    points
        .iter()
        .filter_map(|p| {
            let w: Vec<&str> = p
                .events
                .iter()
                .copied()
                .filter(|e| MARKED.contains(e))
                .collect();
            (!w.is_empty()).then(|| (p.t_s, w.join(", ")))
        })
        .take(MAX_MARKS)
        .collect()
}

/// A line through the points where `f` has a value.
pub fn curve(
    label: &str,
    color: plotters::style::RGBColor,
    points: &[LogPoint],
    f: &dyn Fn(&LogPoint) -> Option<f64>,
) -> Series {
    let pts = points
        .iter()
        .filter_map(|p| f(p).filter(|y| y.is_finite()).map(|y| (p.t_s, y, 0.0)))
        .collect();
    Series::curve(label, color, pts)
}

/// The rate panel's series: set-point and band, measured rate, windows,
/// events (at the set-point's height, or the rate's).
pub fn rate_series(trace: &Trace, windows: &[SteadyWindow], label: &str) -> Vec<Series> {
    let [c0, _, c2, c3, c4, ..] = PALETTE;
    let pts = &trace.points;
    let band = format!("set-point +-{} %", 100.0 * STEADY_BAND);
    let mut out = vec![
        curve("set-point", c3, pts, &|p| p.set_hz).dashed(),
        curve(&band, c2, pts, &|p| {
            p.set_hz.map(|f| f * (1.0 + STEADY_BAND))
        })
        .dashed(),
        curve("", c2, pts, &|p| p.set_hz.map(|f| f * (1.0 - STEADY_BAND))).dashed(),
        curve(label, c0, pts, &|p| p.rate_hz),
    ];
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
pub fn svg(trace: &Trace, windows: &[SteadyWindow], title: &str) -> Result<String, String> {
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
            vec![curve("PWM duty", c0, pts, &|p| Some(p.duty))],
        ),
        (
            panel("cell (V)", "time since power-up (s)"),
            vec![curve("cell, loaded", c0, pts, &|p| p.cell_v)],
        ),
    ];
    stack(title, &panels)
}
