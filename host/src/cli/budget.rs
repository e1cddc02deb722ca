//! Work that will take long says so before it starts, with an estimate,
//! and is refused when the estimate is over the user's budget
//! (`--max-seconds`). The estimates time a small sample of the work
//! itself (a few predictions of the model the run uses) and multiply by
//! the count of such steps the command makes, divided over the cores; they
//! are meant to be right within a factor of a few, which is what deciding
//! "start it now or narrow it" needs.

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
}
