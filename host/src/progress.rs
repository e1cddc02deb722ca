//! Progress of long work, on stderr, wherever stderr goes.
//!
//! Work that lasts longer than a grace period (2 s) shows progress: in a
//! terminal an `indicatif` bar or spinner; anywhere else (a file, a pipe, a
//! notebook cell's `!swimbot ...`) a plain line every 5 s, without escape
//! codes, and a last line with the total time. `--quiet` silences both
//! ([`set_quiet`]). `SWIMBOT_PROGRESS_MS=N` sets the grace period and the
//! interval of the plain lines to N milliseconds (tests, or a slower log).
//!
//! A command starts one [`Progress`] and ends it ([`Progress::finish`], or
//! by dropping it) before it prints its result, so that a bar is never
//! drawn over the result in a terminal.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

static QUIET: AtomicBool = AtomicBool::new(false);

/// `--quiet`: no progress for the rest of the process.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Default grace period before anything is shown.
const GRACE: Duration = Duration::from_secs(2);
/// Default interval between plain lines.
const INTERVAL: Duration = Duration::from_secs(5);
/// Redraw period of the terminal bar.
const REDRAW: Duration = Duration::from_millis(100);

/// `(grace, interval)`, from `SWIMBOT_PROGRESS_MS` when set.
fn timing() -> (Duration, Duration) {
    std::env::var("SWIMBOT_PROGRESS_MS")
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok())
        .map(|ms| (Duration::from_millis(ms), Duration::from_millis(ms.max(1))))
        .unwrap_or((GRACE, INTERVAL))
}

struct Shared {
    label: Mutex<String>,
    done: AtomicU64,
    /// Total units of work and their name, when counted.
    total: Option<(u64, &'static str)>,
    stop: Mutex<bool>,
    wake: Condvar,
    started: Instant,
}

/// Progress of one piece of work; see the module docs.
pub struct Progress {
    shared: Arc<Shared>,
    ticker: Option<JoinHandle<()>>,
}

impl Progress {
    /// Work of unknown size: a spinner, or lines with the elapsed time.
    pub fn start(label: &str) -> Progress {
        Progress::new(label, None)
    }

    /// `total` units (`unit`: "cases", "geometries") counted by [`Progress::inc`].
    pub fn counted(label: &str, total: u64, unit: &'static str) -> Progress {
        Progress::new(label, Some((total, unit)))
    }

    fn new(label: &str, total: Option<(u64, &'static str)>) -> Progress {
        let shared = Arc::new(Shared {
            label: Mutex::new(label.to_string()),
            done: AtomicU64::new(0),
            total,
            stop: Mutex::new(false),
            wake: Condvar::new(),
            started: Instant::now(),
        });
        let ticker = if QUIET.load(Ordering::Relaxed) {
            None
        } else {
            let s = Arc::clone(&shared);
            let terminal = std::io::stderr().is_terminal();
            std::thread::Builder::new()
                .name("progress".into())
                .spawn(move || tick(&s, terminal))
                .ok()
        };
        Progress { shared, ticker }
    }

    /// `n` more units done.
    pub fn inc(&self, n: u64) {
        self.shared.done.fetch_add(n, Ordering::Relaxed);
    }

    /// What is being done now (shown in place of the starting label).
    pub fn stage(&self, label: &str) {
        *lock(&self.shared.label) = label.to_string();
    }

    /// Ends the display (also done on drop).
    pub fn finish(self) {}
}

impl Drop for Progress {
    fn drop(&mut self) {
        *lock(&self.shared.stop) = true;
        self.shared.wake.notify_all();
        if let Some(t) = self.ticker.take() {
            let _ = t.join();
        }
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// Waits `d` or until stopped; true when stopped.
fn wait(s: &Shared, d: Duration) -> bool {
    let stopped = lock(&s.stop);
    let (stopped, _) = s
        .wake
        .wait_timeout_while(stopped, d, |stop| !*stop)
        .unwrap_or_else(|e| e.into_inner());
    *stopped
}

fn tick(s: &Shared, terminal: bool) {
    let (grace, interval) = timing();
    if wait(s, grace) {
        return;
    }
    if terminal {
        bar(s)
    } else {
        lines(s, interval)
    }
}

/// Plain lines: now, every `interval`, and the total time at the end.
fn lines(s: &Shared, interval: Duration) {
    loop {
        let stopped = wait(s, Duration::ZERO) || {
            line(s, false);
            wait(s, interval)
        };
        if stopped {
            line(s, true);
            return;
        }
    }
}

fn line(s: &Shared, last: bool) {
    let secs = s.started.elapsed().as_secs_f64();
    let label = lock(&s.label).clone();
    let count = match s.total {
        Some((total, unit)) if !last => {
            let done = s.done.load(Ordering::Relaxed).min(total);
            let pct = 100.0 * done as f64 / total.max(1) as f64;
            format!("{done}/{total} {unit} ({pct:.0} %), ")
        }
        _ => String::new(),
    };
    let status = if last { "done in " } else { "" };
    let mut err = std::io::stderr().lock();
    let _ = writeln!(err, "swimbot: {label}: {count}{status}{secs:.1} s");
}

/// The terminal bar, redrawn until stopped, then cleared.
fn bar(s: &Shared) {
    let (bar, template) = match s.total {
        Some((total, unit)) => (
            ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr()),
            format!(
                "{{spinner}} {{msg}} {{bar:30}} {{pos}}/{{len}} {unit} ({{elapsed}}, {{eta}} left)"
            ),
        ),
        None => (
            ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr()),
            "{spinner} {msg} ({elapsed})".to_string(),
        ),
    };
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style);
    }
    loop {
        bar.set_message(lock(&s.label).clone());
        bar.set_position(s.done.load(Ordering::Relaxed));
        bar.tick();
        if wait(s, REDRAW) {
            bar.finish_and_clear();
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_stages_are_kept_and_dropping_stops_the_ticker() {
        let p = Progress::counted("test", 10, "items");
        p.inc(3);
        p.inc(4);
        p.stage("second stage");
        assert_eq!(p.shared.done.load(Ordering::Relaxed), 7);
        assert_eq!(*lock(&p.shared.label), "second stage");
        let started = Instant::now();
        p.finish();
        // The ticker wakes at once, not after its grace period.
        assert!(started.elapsed() < Duration::from_secs(1));
    }
}
