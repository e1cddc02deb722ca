//! A logged run against its simulation (`swimbot sim --set-points-from
//! LOG`): the same set-points and commands, the model's tail load in place
//! of the real tail. The simulation's side is its own run log, taken by
//! the firmware's recorder from the simulated passes, so both sides are
//! the same quantities (the turn-averaged rate, the duty, the battery
//! monitor's loaded cell voltage) at the same 10 Hz. The difference is stated where both hold a set-point
//! steadily (the log's steady windows) and over every record where both
//! measured a rate: there the controller holds both rates at the
//! set-point, so the rate difference is the loop's, and the model's tail
//! load shows in the duty each needed; and in the first start, where the
//! loop is still learning the line, the rates differ by the load.

use crate::chart::{stack, Chart, Series, PALETTE};
use crate::runlog::figure::curve;
use crate::runlog::{LogPoint, SteadyWindow, Trace};

/// Simulation minus log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Difference {
    /// Records compared.
    pub records: usize,
    pub rate_mean_hz: f64,
    pub rate_rms_hz: f64,
    /// Mean of (sim - log) / log over the records whose logged rate is
    /// not 0; `None` when every logged rate is 0 (a relative difference to
    /// 0 is no number: printing it gave "+inf %").
    pub rate_mean_rel: Option<f64>,
    pub duty_mean: f64,
}

/// The simulated record nearest `t_s`, if within one sample period.
fn sim_at(sim: &Trace, t_s: f64) -> Option<&LogPoint> {
    let i = sim.points.partition_point(|p| p.t_s < t_s);
    [i.checked_sub(1), Some(i)]
        .into_iter()
        .flatten()
        .filter_map(|i| sim.points.get(i))
        .filter(|p| (p.t_s - t_s).abs() <= sim.sample_period_s)
        .min_by(|a, b| (a.t_s - t_s).abs().total_cmp(&(b.t_s - t_s).abs()))
}

fn difference<'a>(pairs: impl Iterator<Item = (&'a LogPoint, &'a LogPoint)>) -> Option<Difference> {
    let (mut n, mut d, mut d2, mut dd) = (0usize, 0.0, 0.0, 0.0);
    let (mut n_rel, mut rel) = (0usize, 0.0);
    for (l, s) in pairs {
        let (Some(lr), Some(sr)) = (l.rate_hz, s.rate_hz) else {
            continue;
        };
        n += 1;
        d += sr - lr;
        d2 += (sr - lr).powi(2);
        if lr != 0.0 {
            n_rel += 1;
            rel += (sr - lr) / lr;
        }
        dd += s.duty - l.duty;
    }
    (n > 0).then(|| {
        let n_f = n as f64;
        Difference {
            records: n,
            rate_mean_hz: d / n_f,
            rate_rms_hz: (d2 / n_f).sqrt(),
            rate_mean_rel: (n_rel > 0).then(|| rel / n_rel as f64),
            duty_mean: dd / n_f,
        }
    })
}

/// In the steady windows, and over every record with both rates.
pub fn compare(
    log: &Trace,
    windows: &[SteadyWindow],
    sim: &Trace,
) -> (Option<Difference>, Option<Difference>) {
    let pairs = |steady: bool| {
        log.points
            .iter()
            .filter(move |p| {
                !steady || windows.iter().any(|w| p.t_s >= w.from_s && p.t_s <= w.to_s)
            })
            .filter_map(|p| sim_at(sim, p.t_s).map(|s| (p, s)))
    };
    (difference(pairs(true)), difference(pairs(false)))
}

/// One line per comparison, for the summary and the figure's note.
pub fn describe(what: &str, d: &Option<Difference>) -> String {
    match d {
        None => format!("{what}: no record where both measured a rate"),
        Some(d) => format!(
            "{what} ({} records): rate sim - log {:+.4} Hz ({}), RMS {:.4} Hz; duty sim - log {:+.1} points",
            d.records,
            d.rate_mean_hz,
            d.rate_mean_rel.map_or("the log's rate is 0 Hz: no relative difference".into(), |r| {
                format!("{:+.2} %", 100.0 * r)
            }),
            d.rate_rms_hz,
            100.0 * d.duty_mean
        ),
    }
}

/// Log and simulation overlaid: rates with the set-point, duty, cell.
pub fn overlay_svg(
    log: &Trace,
    sim: &Trace,
    tail: &str,
    notes: &[String],
) -> crate::chart::PlotResult {
    let [c0, c1, _, c3, ..] = PALETTE;
    let (pts, spts) = (&log.points, &sim.points);
    let t_end = pts.iter().chain(spts).map(|p| p.t_s).fold(1e-3, f64::max);
    let panel = |y: &str, x: &str| Chart::new("", x, y).size(760, 190).x_range(0.0, t_end);
    let mut rate_panel = panel("motor rate (Hz)", "").size(760, 340);
    for n in notes {
        rate_panel = rate_panel.note(n.clone());
    }
    let panels = vec![
        (
            rate_panel,
            curve("set-point (log)", c3, pts, &|p| p.set_hz)
                .into_iter()
                .map(Series::dashed)
                .chain(curve("log: measured", c0, pts, &|p| p.rate_hz))
                .chain(curve("sim: measured", c1, spts, &|p| p.rate_hz))
                .collect(),
        ),
        (
            panel("duty", ""),
            [
                curve("log", c0, pts, &|p| Some(p.duty)),
                curve("sim", c1, spts, &|p| Some(p.duty)),
            ]
            .concat(),
        ),
        (
            panel("cell, loaded (V)", "time since power-up (s)"),
            [
                curve("log", c0, pts, &|p| p.cell_v),
                curve("sim", c1, spts, &|p| p.cell_v),
            ]
            .concat(),
        ),
    ];
    stack(
        &format!("run log against swimbot sim ({tail}, the model's tail load)"),
        &panels,
    )
}
