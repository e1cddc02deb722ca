//! Steady windows of a run log: where the rate can stand for "the tail's
//! rate" of a trial.
//!
//! Criterion, per stretch of consecutive records with the motor driven and
//! one set-point: the window begins at the first record from which every
//! measured rate of the stretch stays within [`STEADY_BAND`] (2 %, the
//! settling band, the same as `swimbot sim`'s step response) of
//! the set-point, and ends with the stretch (a set-point change, a stop,
//! the end of the log); it counts if it holds at least [`MIN_TURNS`]
//! whole turns.
//!
//! The estimate: each record's rate is the mean over the turn before it
//! (the firmware averages whole turns, which cancels the ring's pole
//! pattern), so records closer than a turn share edges and are correlated.
//! Records at least one turn apart are means over disjoint turns: those
//! "batch means" (Fishman 2001, section 6.6) are the samples of the mean
//! and its Student-t interval ([`crate::stats::mean_and_ci`], the same
//! statistic as a dataset's raw trials). The interval is the rate's
//! variation from turn to turn within the window; a bias of the sensor's
//! clock (the crystal: tens of ppm) is not in it.

use super::trace::{LogPoint, Trace};
use crate::stats::mean_and_ci;

/// Rate within 2 % of the set-point for good: settled.
pub const STEADY_BAND: f64 = 0.02;

/// Fewest turn means behind a window's interval.
pub const MIN_TURNS: usize = 3;

/// The confidence of the intervals written.
pub const CONFIDENCE: f64 = 0.95;

/// One steady window.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyWindow {
    pub from_s: f64,
    pub to_s: f64,
    pub set_hz: f64,
    /// Means over disjoint whole turns, in time order.
    pub turn_means_hz: Vec<f64>,
    pub mean_hz: f64,
    /// Half-width of the [`CONFIDENCE`] interval of the mean.
    pub ci_hz: f64,
    /// Mean duty and cell voltage over the window (what the rate cost).
    pub mean_duty: f64,
    pub mean_cell_v: Option<f64>,
}

/// The steady windows of a log, in time order.
pub fn steady_windows(trace: &Trace) -> Vec<SteadyWindow> {
    stretches(&trace.points)
        .into_iter()
        .filter_map(window)
        .collect()
}

/// Maximal runs of driven records at one set-point, with a rate.
fn stretches(points: &[LogPoint]) -> Vec<&[LogPoint]> {
    let key = |p: &LogPoint| p.running().then_some(p.set_hz).flatten();
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..=points.len() {
        let same =
            i < points.len() && key(&points[i]).is_some() && key(&points[i]) == key(&points[start]);
        if !same {
            if key(&points[start]).is_some() {
                out.push(&points[start..i]);
            }
            start = i;
        }
    }
    out
}

fn within(p: &LogPoint, set: f64) -> bool {
    p.rate_hz
        .is_some_and(|r| (r / set - 1.0).abs() <= STEADY_BAND)
}

fn window(stretch: &[LogPoint]) -> Option<SteadyWindow> {
    let set = stretch.first()?.set_hz?;
    let last_out = stretch.iter().rposition(|p| !within(p, set));
    let settled = &stretch[last_out.map_or(0, |i| i + 1)..];
    let turn_s = 1.0 / set;
    let mut turns = Vec::new();
    let mut next_s = f64::NEG_INFINITY;
    for p in settled {
        if let (Some(r), true) = (p.rate_hz, p.t_s >= next_s) {
            turns.push(r);
            next_s = p.t_s + turn_s;
        }
    }
    if turns.len() < MIN_TURNS {
        return None;
    }
    let (mean_hz, ci_hz) = mean_and_ci(&turns, CONFIDENCE);
    let n = settled.len() as f64;
    let cells: Vec<f64> = settled.iter().filter_map(|p| p.cell_v).collect();
    Some(SteadyWindow {
        from_s: settled[0].t_s,
        to_s: settled[settled.len() - 1].t_s,
        set_hz: set,
        turn_means_hz: turns,
        mean_hz,
        ci_hz,
        mean_duty: settled.iter().map(|p| p.duty).sum::<f64>() / n,
        mean_cell_v: (!cells.is_empty()).then(|| cells.iter().sum::<f64>() / cells.len() as f64),
    })
}

/// The windows at one set-point pooled: the mean and interval over all
/// their turn means (one trial per window).
#[derive(Debug, Clone, PartialEq)]
pub struct Pooled<'a> {
    pub set_hz: f64,
    pub windows: Vec<&'a SteadyWindow>,
    pub mean_hz: f64,
    pub ci_hz: f64,
    pub turns: usize,
}

/// Windows grouped by set-point, in order of first appearance.
pub fn pool(windows: &[SteadyWindow]) -> Vec<Pooled<'_>> {
    let mut sets: Vec<f64> = Vec::new();
    for w in windows {
        if !sets.contains(&w.set_hz) {
            sets.push(w.set_hz);
        }
    }
    sets.into_iter()
        .map(|set| {
            let ws: Vec<&SteadyWindow> = windows.iter().filter(|w| w.set_hz == set).collect();
            let all: Vec<f64> = ws
                .iter()
                .flat_map(|w| w.turn_means_hz.iter().copied())
                .collect();
            let (mean_hz, ci_hz) = mean_and_ci(&all, CONFIDENCE);
            Pooled {
                set_hz: set,
                windows: ws,
                mean_hz,
                ci_hz,
                turns: all.len(),
            }
        })
        .collect()
}

/// `mean +- ci Hz`: the interval to two significant figures and the mean
/// to the interval's last digit (at least 0.1 mHz), so a small interval
/// never reads as a zero one.
pub fn show_rate(mean_hz: f64, ci_hz: f64) -> String {
    let decimals = if ci_hz > 0.0 && ci_hz.is_finite() {
        (1 - ci_hz.log10().floor() as i32).clamp(4, 9) as usize
    } else {
        4
    };
    format!(
        "{mean_hz:.decimals$} +- {} Hz",
        crate::format::fmt_sig(ci_hz, 2)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(t_s: f64, set: Option<f64>, rate: Option<f64>, duty: f64) -> LogPoint {
        LogPoint {
            t_s,
            set_hz: set,
            rate_hz: rate,
            duty,
            cell_v: Some(3.9),
            events: Vec::new(),
        }
    }

    fn trace(points: Vec<LogPoint>) -> Trace {
        Trace {
            points,
            dropped_records: 0,
            sample_period_s: 0.1,
        }
    }

    /// A start from rest to 1 Hz (in the band from 2 s on), a step to
    /// 0.5 Hz at 10 s (in the band from 13 s), an Off at 20 s.
    fn run() -> Trace {
        let mut pts = Vec::new();
        for k in 0..220 {
            let t = k as f64 * 0.1;
            let (set, rate, duty) = if t < 10.0 {
                (
                    1.0,
                    if t < 2.0 {
                        0.5 * t
                    } else {
                        1.0 + 0.005 * (k % 3) as f64
                    },
                    0.4,
                )
            } else if t < 20.0 {
                (0.5, if t < 13.0 { 0.7 } else { 0.5 }, 0.2)
            } else {
                (0.5, 0.0, 0.0)
            };
            pts.push(point(t, Some(set), (t >= 0.3).then_some(rate), duty));
        }
        trace(pts)
    }

    #[test]
    fn windows_begin_where_the_rate_settles_and_end_at_the_change() {
        let w = steady_windows(&run());
        assert_eq!(w.len(), 2);
        assert!(
            (w[0].from_s - 2.0).abs() < 0.051 && (w[0].to_s - 9.9).abs() < 1e-9,
            "{w:?}"
        );
        assert!((w[1].from_s - 13.0).abs() < 0.051 && (w[1].to_s - 19.9).abs() < 1e-9);
        // Turn means one turn apart: 8 s at 1 Hz, 7 s at 0.5 Hz.
        assert_eq!(w[0].turn_means_hz.len(), 8);
        assert_eq!(w[1].turn_means_hz.len(), 4);
        assert!((w[1].mean_hz - 0.5).abs() < 1e-12 && w[1].ci_hz == 0.0);
        assert!((w[0].mean_duty - 0.4).abs() < 1e-12);
    }

    #[test]
    fn the_interval_is_the_t_interval_of_the_turn_means() {
        let w = &steady_windows(&run())[0];
        let (m, ci) = mean_and_ci(&w.turn_means_hz, CONFIDENCE);
        assert_eq!((w.mean_hz, w.ci_hz), (m, ci));
        assert!(ci > 0.0 && ci < 0.01, "{ci}");
    }

    #[test]
    fn no_window_without_enough_settled_turns_or_a_set_point() {
        // 2.5 s at 0.5 Hz: one turn and a bit.
        let short: Vec<_> = (0..25)
            .map(|k| point(k as f64 * 0.1, Some(0.5), Some(0.5), 0.3))
            .collect();
        assert!(steady_windows(&trace(short)).is_empty());
        // Never within 2 %.
        let off: Vec<_> = (0..100)
            .map(|k| point(k as f64 * 0.1, Some(1.0), Some(1.05), 0.3))
            .collect();
        assert!(steady_windows(&trace(off)).is_empty());
        let none: Vec<_> = (0..100)
            .map(|k| point(k as f64 * 0.1, None, Some(1.0), 0.0))
            .collect();
        assert!(steady_windows(&trace(none)).is_empty());
    }

    #[test]
    fn pooling_keeps_each_set_point_apart() {
        let mut t = run();
        let again = run().points.into_iter().map(|mut p| {
            p.t_s += 30.0;
            p
        });
        t.points.extend(again);
        let w = steady_windows(&t);
        let pooled = pool(&w);
        assert_eq!(pooled.len(), 2);
        assert_eq!(pooled[0].windows.len(), 2);
        assert_eq!(pooled[0].turns, 16);
        assert_eq!(pooled[1].set_hz, 0.5);
    }
}
