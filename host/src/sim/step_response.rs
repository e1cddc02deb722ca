//! Step-response figures of merit of a rate-controlled run, from the true
//! motor rate of its trace: for each set-point change (the start counts as
//! a step from 0), the settling time into a band around the new set-point,
//! the overshoot as a fraction of the step, and the steady error (the mean
//! relative error over the last seconds of the step's window).
//!
//! Definitions follow the usual control-textbook ones (e.g. Ogata, *Modern
//! Control Engineering*, 5th ed., sec. 5-3), with the window of a step
//! ending at the next set-point change or when the motor stops running.

use super::rate::RatePoint;

/// Settled: within 2 % of the set-point.
pub const SETTLE_BAND: f64 = 0.02;
/// Length of the steady window at a step's end (s), or half the step's
/// window if that is shorter.
pub const STEADY_WINDOW_S: f64 = 5.0;

/// One set-point change and how the motor followed it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepMetrics {
    pub at_s: f64,
    pub from_hz: f64,
    pub to_hz: f64,
    /// Time after `at_s` from which the rate stays within the band until
    /// the window's end; `None` if it never does.
    pub settle_s: Option<f64>,
    /// Largest excursion beyond the new set-point, as a fraction of the
    /// step (`|to - from|`); 0 without one.
    pub overshoot: f64,
    /// Mean of `(rate - to) / to` over the steady window.
    pub steady_error: f64,
    /// Largest `|rate - to| / to` over the steady window (the ripple).
    pub steady_max_error: f64,
    /// The window's length (s).
    pub window_s: f64,
}

/// The figures of every step of `trace`.
pub fn step_metrics(trace: &[RatePoint]) -> Vec<StepMetrics> {
    let mut out = Vec::new();
    let mut i = 0;
    let mut from = 0.0;
    while i < trace.len() {
        let to = trace[i].set_hz;
        let start = i;
        while i < trace.len() && trace[i].set_hz == to {
            i += 1;
        }
        if to > 0.0 {
            // The window: while running, up to the next change.
            let w: Vec<&RatePoint> = trace[start..i]
                .iter()
                .skip_while(|p| !p.running)
                .take_while(|p| p.running)
                .collect();
            if let Some(m) = metrics(trace[start].t_s, from, to, &w) {
                out.push(m);
            }
        }
        from = to;
    }
    out
}

fn metrics(at_s: f64, from: f64, to: f64, w: &[&RatePoint]) -> Option<StepMetrics> {
    let (first, last) = (w.first()?, w.last()?);
    let err = |p: &RatePoint| (p.motor_rate_hz - to) / to;
    let settled_from = w
        .iter()
        .rposition(|p| err(p).abs() > SETTLE_BAND)
        .map_or(Some(0), |k| (k + 1 < w.len()).then_some(k + 1));
    let settle_s = settled_from.map(|k| w[k].t_s - at_s);
    let step = (to - from).abs().max(f64::MIN_POSITIVE);
    let overshoot = w
        .iter()
        .map(|p| {
            if to >= from {
                p.motor_rate_hz - to
            } else {
                to - p.motor_rate_hz
            }
        })
        .fold(0.0f64, f64::max)
        / step;
    let window_s = last.t_s - first.t_s;
    let steady_from = last.t_s - STEADY_WINDOW_S.min(0.5 * window_s);
    let steady: Vec<f64> = w
        .iter()
        .filter(|p| p.t_s >= steady_from)
        .map(|p| err(p))
        .collect();
    let steady_error = steady.iter().sum::<f64>() / steady.len().max(1) as f64;
    let steady_max_error = steady.iter().map(|e| e.abs()).fold(0.0, f64::max);
    Some(StepMetrics {
        at_s,
        from_hz: from,
        to_hz: to,
        settle_s,
        overshoot,
        steady_error,
        steady_max_error,
        window_s,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(t_s: f64, set_hz: f64, rate: f64) -> RatePoint {
        RatePoint {
            t_s,
            set_hz,
            reference_hz: set_hz,
            measured_hz: rate,
            motor_rate_hz: rate,
            duty: 0.5,
            battery_v: 4.0,
            running: true,
        }
    }

    #[test]
    fn a_first_order_step_has_its_textbook_figures() {
        // 1 - exp(-t / 1 s): 2 % band after ln(50) = 3.91 s, no overshoot.
        let trace: Vec<RatePoint> = (0..2_000)
            .map(|k| {
                let t = k as f64 * 0.01;
                point(t, 1.0, 1.0 - (-t).exp())
            })
            .collect();
        let m = step_metrics(&trace);
        assert_eq!(m.len(), 1);
        let settle = m[0].settle_s.expect("settles");
        assert!((settle - 50f64.ln()).abs() < 0.011, "{settle}");
        assert_eq!(m[0].overshoot, 0.0);
        assert!(m[0].steady_error.abs() < 1e-3);
    }

    #[test]
    fn overshoot_is_a_fraction_of_the_step_both_ways() {
        let mut trace = vec![point(0.0, 1.0, 1.0), point(1.0, 1.0, 1.0)];
        // Down from 1.0 to 0.5, dipping to 0.45: 10 % of the step.
        trace.extend([
            point(2.0, 0.5, 0.8),
            point(3.0, 0.5, 0.45),
            point(4.0, 0.5, 0.5),
            point(5.0, 0.5, 0.5),
        ]);
        let m = step_metrics(&trace);
        assert_eq!(m.len(), 2);
        assert!((m[1].overshoot - 0.1).abs() < 1e-12, "{:?}", m[1]);
        assert_eq!(m[1].settle_s, Some(2.0));
        assert_eq!(m[1].from_hz, 1.0);
    }
}
