//! Work that will take long says so before it starts, with an estimate,
//! and is refused when the estimate is over the user's budget
//! (`--max-seconds`). The estimates time a small sample of the work
//! itself (a few predictions of the model the run uses) and multiply by
//! the count of such steps the command makes, divided over the cores; they
//! are meant to be right within a factor of a few, which is what deciding
//! "start it now or narrow it" needs.
//!
//! Work whose count of steps has no formula (the diagnosis's search, whose
//! design changes) is estimated by [`extrapolate`]: the work itself, timed
//! on evenly spaced subsets of the cases ([`subset_sizes`]: 8 and 24
//! cases, then three times as many while that is at most a twelfth of the
//! cases), grown to the whole by the power of the case count the two
//! largest timings show, held between [`MIN_EXPONENT`] and
//! [`MAX_EXPONENT`]. Small subsets are mostly fixed cost (the search's
//! laws, the floors), so their growth looks slower than linear and the
//! linear bound took their per-case cost for the whole: from 8 and 24
//! cases a diagnosis of 10 000 was estimated at 3 min 57 s (16 min 50 s
//! in another run) for 1 min 27 s measured; timed up to 648 cases the
//! per-case cost is the large run's. The subsets cost about a tenth of the
//! work they estimate (a geometric series up to a twelfth of the cases).
//! Nothing in it is calibrated to one design: a new search is estimated by
//! timing the new search. The constants here are the only ones to revisit.

use super::CliError;
use std::time::Instant;

/// Work estimated above this many seconds is announced on stderr.
pub const ANNOUNCE_SECONDS: f64 = 10.0;

/// Seconds per call of `f`, timed over up to `calls` calls (at least one),
/// stopping after about a second of timing (one call of a non-local model
/// can take that long).
pub fn seconds_per_call(calls: usize, mut f: impl FnMut(usize)) -> f64 {
    let start = Instant::now();
    let mut done = 0;
    while done < calls.max(1) {
        f(done);
        done += 1;
        if start.elapsed().as_secs_f64() > 1.0 {
            break;
        }
    }
    start.elapsed().as_secs_f64() / done as f64
}

/// `1 h 20 min`, `3 min 10 s`, `12 s`, `0.4 s`.
pub fn duration(seconds: f64) -> String {
    // Under 10 s a tenth still means something ("about 0 s" did not).
    if seconds < 9.95 {
        return format!("{:.1} s", seconds.max(0.0));
    }
    let s = seconds.round().max(0.0) as u64;
    match s {
        0..=59 => format!("{s} s"),
        60..=3599 => format!("{} min {} s", s / 60, s % 60),
        _ => format!("{} h {} min", s / 3600, (s % 3600) / 60),
    }
}

/// Announces `what` when it is estimated to take long; refuses it (exit 2)
/// when the estimate exceeds `budget_s`.
pub fn check(what: &str, estimate_s: f64, budget_s: Option<f64>) -> Result<(), CliError> {
    let cores = rayon::current_num_threads();
    if let Some(b) = budget_s {
        if estimate_s > b {
            return Err(CliError::input(format!(
                "{what} would take about {} on {cores} cores, over --max-seconds {b}; narrow it or raise the budget",
                duration(estimate_s)
            )));
        }
    }
    if estimate_s > ANNOUNCE_SECONDS {
        eprintln!(
            "swimbot: {what}: about {} on {cores} cores (estimated from a timed sample; --max-seconds refuses long runs)",
            duration(estimate_s)
        );
    }
    Ok(())
}

/// Cases of the two subsets [`extrapolate`] always times.
pub const SUBSET_SMALL: usize = 8;
pub const SUBSET_LARGE: usize = 24;
/// Each further subset is this many times the last, while it is at most
/// the cases over [`SUBSET_SHARE`].
pub const SUBSET_GROWTH: usize = 3;
pub const SUBSET_SHARE: usize = 12;
/// The time of a command over its cases grows at least linearly (each case
/// is predicted) and at most quadratically (pairs of cases, leave-one-out
/// refits of all the others).
pub const MIN_EXPONENT: f64 = 1.0;
pub const MAX_EXPONENT: f64 = 2.0;
/// From this many cases on, the subsets are timed before the work: at 200
/// cases the two timed runs cost 32 cases' work, at most 16 % of a run
/// that grows linearly (less for faster growth); below it the work is
/// short enough to start unasked, unless a budget asks.
pub const ESTIMATE_FROM_CASES: usize = 200;

/// `k` cases of `data`, evenly spaced (the same setup and uncertainties).
pub fn subset(data: &crate::data::Dataset, k: usize) -> crate::data::Dataset {
    let n = data.cases.len();
    let mut out = data.clone();
    out.cases = (0..k.min(n))
        .map(|i| data.cases[i * n / k.min(n).max(1)].clone())
        .collect();
    out
}

/// Seconds for `n` cases from `time_on(k)`, the seconds the same work
/// takes on `k` cases (module docs); `None` when there are too few cases
/// to tell or a timed run failed (the work itself will say why).
pub fn extrapolate(n: usize, mut time_on: impl FnMut(usize) -> Option<f64>) -> Option<f64> {
    if n <= SUBSET_LARGE {
        return None;
    }
    let mut timed: Vec<(usize, f64)> = Vec::new();
    for k in subset_sizes(n) {
        timed.push((k, time_on(k)?.max(1e-6)));
    }
    let [.., (k0, t0), (k1, t1)] = timed[..] else {
        return None;
    };
    let p = ((t1 / t0).ln() / (k1 as f64 / k0 as f64).ln()).clamp(MIN_EXPONENT, MAX_EXPONENT);
    Some(t1 * (n as f64 / k1 as f64).powf(p))
}

/// The subsets [`extrapolate`] times for `n` cases, smallest first (module
/// docs): 8, 24, then x3 while at most `n / 12`.
pub fn subset_sizes(n: usize) -> Vec<usize> {
    let mut sizes = vec![SUBSET_SMALL, SUBSET_LARGE];
    let mut next = SUBSET_LARGE * SUBSET_GROWTH;
    while next <= n / SUBSET_SHARE {
        sizes.push(next);
        next *= SUBSET_GROWTH;
    }
    sizes
}

/// Seconds of `f`, run once.
pub fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let start = Instant::now();
    let out = f();
    (out, start.elapsed().as_secs_f64())
}

/// Says that `--max-seconds` cannot be applied to `what` (too few cases
/// to time a sample of), rather than ignoring it without a word.
pub fn unestimated(what: &str, budget_s: Option<f64>) {
    if let Some(b) = budget_s {
        eprintln!(
            "swimbot: note: {what}: too few cases to estimate its time from a sample (at least {} are needed); --max-seconds {b} is not applied",
            SUBSET_LARGE + 1
        );
    }
}

/// Checks a `--max-seconds` value.
pub fn parse_budget(v: Option<f64>) -> Result<Option<f64>, CliError> {
    match v {
        Some(b) if !(b.is_finite() && b > 0.0) => Err(CliError::input(format!(
            "--max-seconds must be a positive number of seconds, got {b}"
        ))),
        other => Ok(other),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations_read_as_a_person_says_them() {
        assert_eq!(duration(12.4), "12 s");
        assert_eq!(duration(0.04), "0.0 s");
        assert_eq!(duration(3.26), "3.3 s");
        assert_eq!(duration(190.0), "3 min 10 s");
        assert_eq!(duration(8.0 * 3600.0 + 60.0), "8 h 1 min");
        assert_eq!(check("x", 100.0, Some(10.0)).unwrap_err().exit_code(), 2);
        assert!(check("x", 1.0, Some(10.0)).is_ok());
        assert!(parse_budget(Some(-1.0)).is_err());
    }

    #[test]
    fn extrapolation_follows_the_timed_growth_within_its_bounds() {
        // Quadratic work: t = k^2 microseconds.
        let quad = |k: usize| Some((k * k) as f64 * 1e-6);
        let t = extrapolate(10_000, quad).unwrap();
        assert!((t / 100.0 - 1.0).abs() < 1e-9, "{t}");
        // Faster than quadratic is held at quadratic, slower than linear at linear.
        let steep = extrapolate(240, |k: usize| Some((k as f64).powi(4))).unwrap();
        assert!(
            (steep / (24f64.powi(4) * 100.0) - 1.0).abs() < 1e-9,
            "{steep}"
        );
        // A fixed cost and a per-case one (the diagnosis's shape): the
        // largest subsets see the per-case cost; 8 and 24 cases alone gave
        // five times the truth at 10 000 cases.
        let fixed = |k: usize| Some(1.0 + 0.01 * k as f64);
        let t = extrapolate(10_000, fixed).unwrap();
        assert!((t / 101.0 - 1.0).abs() < 0.2, "{t}");
        assert_eq!(subset_sizes(10_000), [8, 24, 72, 216, 648]);
        assert_eq!(subset_sizes(200), [8, 24]);
        assert_eq!(subset_sizes(1_000), [8, 24, 72]);
        let flat = extrapolate(240, |_| Some(1.0)).unwrap();
        assert!((flat - 10.0).abs() < 1e-9, "{flat}");
        assert_eq!(extrapolate(10, quad), None, "too few cases to tell");
        assert_eq!(extrapolate(1_000, |_| None), None);
        let data = crate::data::paper();
        let s = subset(&data, 3);
        assert_eq!(s.cases.len(), 3);
        assert_eq!(s.cases[1].id, data.cases[2].id);
    }
}
