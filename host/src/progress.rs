//! Progress of long work on stderr, wherever stderr goes.
//!
//! The commands draw `indicatif` spinners and bars made here. In a
//! terminal they are drawn as usual once the work has lasted 2 s
//! ([`Delayed`]: a quick run does not flash a bar). Anywhere else (a file, a pipe, a
//! notebook cell's `!swimbot ...`), where indicatif would draw nothing,
//! [`PlainLines`] turns its redraws into a plain line every 5 s, without
//! escape codes, once the work has lasted 2 s: `k of N units (p %), about
//! H:MM:SS left` (the rest extrapolated at the mean rate so far) once the
//! work has a length, and the elapsed time. `--quiet` silences both
//! ([`set_quiet`]). `SWIMBOT_PROGRESS_MS=N` sets both the 2 s and the 5 s
//! to N milliseconds (tests; a sparser log).
//!
//! A command ends its spinner (`finish_and_clear`) before it prints its
//! result, so that a bar is never drawn over the result in a terminal.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle, TermLike};
use std::io::{IsTerminal, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

static QUIET: AtomicBool = AtomicBool::new(false);

/// `--quiet`: no progress for the rest of the process.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Default wait before the first plain line.
const GRACE: Duration = Duration::from_secs(2);
/// Default interval between plain lines.
const INTERVAL: Duration = Duration::from_secs(5);
/// Redraw period of a spinner in a terminal.
const REDRAW: Duration = Duration::from_millis(100);

/// `(grace, interval)`, from `SWIMBOT_PROGRESS_MS` when set.
fn timing() -> (Duration, Duration) {
    std::env::var("SWIMBOT_PROGRESS_MS")
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok())
        .map(|ms| (Duration::from_millis(ms), Duration::from_millis(ms.max(1))))
        .unwrap_or((GRACE, INTERVAL))
}

enum Mode {
    Quiet,
    Terminal,
    Plain,
}

fn mode() -> Mode {
    if QUIET.load(Ordering::Relaxed) {
        Mode::Quiet
    } else if std::io::stderr().is_terminal() {
        Mode::Terminal
    } else {
        Mode::Plain
    }
}

/// A spinner for work of unknown length: `message` and the elapsed time.
pub fn spinner(message: &str) -> ProgressBar {
    make(None, message, "")
}

/// A spinner for work done in `total` stages of unequal length (a
/// diagnosis, an audit): `message`, `stage k of N` once the caller sets
/// the position ([`ProgressBar::set_position`]), and the elapsed time; no
/// time left (the stages' lengths differ too much to extrapolate one).
pub fn stages(total: u64, message: &str) -> ProgressBar {
    make(Some(total), message, STAGES)
}

/// The unit of [`stages`].
const STAGES: &str = "stages";

/// A bar for `total` units (`unit`: "cases", "geometries") advanced by
/// `inc`: count, share and elapsed time, and in a terminal the time left.
pub fn bar(total: u64, unit: &str, message: &str) -> ProgressBar {
    make(Some(total), message, unit)
}

fn make(total: Option<u64>, message: &str, unit: &str) -> ProgressBar {
    let (target, template, tick) = match mode() {
        Mode::Quiet => return ProgressBar::hidden(),
        Mode::Terminal => {
            let t = match total {
                Some(_) if unit != STAGES => format!("{{spinner}} {{msg}} {{bar:30}} {{pos}}/{{len}} {unit} ({{elapsed}}, {{eta}} left)"),
                _ => "{spinner} {msg} ({done}{elapsed})".to_string(),
            };
            let term = Delayed {
                term: console::Term::stderr(),
                from: Instant::now() + timing().0,
            };
            (ProgressDrawTarget::term_like(Box::new(term)), t, REDRAW)
        }
        Mode::Plain => {
            let (grace, interval) = timing();
            // `{done}`: how far along and the expected rest, once the work
            // has a length (a spinner's caller may give it one later).
            let t = "{msg}: {done}{elapsed_precise} elapsed".to_string();
            let lines = PlainLines::new(grace, interval);
            (
                ProgressDrawTarget::term_like(Box::new(lines)),
                t,
                interval.min(REDRAW),
            )
        }
    };
    let bar = ProgressBar::with_draw_target(total, target);
    let unit = unit.to_string();
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style.with_key(
            "done",
            move |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = w.write_str(&done(s.pos(), s.len(), s.elapsed(), &unit));
            },
        ));
    }
    bar.set_message(message.to_string());
    bar.enable_steady_tick(tick);
    bar
}

/// `k of N unit (p %), about H:MM:SS left, `: the rest extrapolated at the
/// mean rate so far (hours:minutes:seconds, as `elapsed_precise`); empty
/// without a length.
fn done(pos: u64, len: Option<u64>, elapsed: Duration, unit: &str) -> String {
    let Some(len) = len.filter(|&n| n > 0) else {
        return String::new();
    };
    if unit == STAGES {
        return format!("stage {} of {len}, ", pos.clamp(1, len));
    }
    let unit = if unit.is_empty() {
        String::new()
    } else {
        format!(" {unit}")
    };
    let percent = 100 * pos.min(len) / len;
    let left = if pos == 0 {
        "time left unknown yet".to_string()
    } else {
        let rest = elapsed.as_secs_f64() * (len.saturating_sub(pos)) as f64 / pos as f64;
        format!("about {} left", hms(rest))
    };
    format!("{pos} of {len}{unit} ({percent} %), {left}, ")
}

/// Seconds as `H:MM:SS`, rounded up (a rest is never shown as 0 early).
fn hms(seconds: f64) -> String {
    let s = seconds.max(0.0).ceil() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
}

/// The terminal, drawn on only from a given time: before it, indicatif's
/// draws go nowhere (its one-line clear-and-redraw then starts cleanly on
/// the cursor's line).
#[derive(Debug)]
pub struct Delayed {
    term: console::Term,
    from: Instant,
}

impl Delayed {
    fn on(&self) -> bool {
        Instant::now() >= self.from
    }
}

impl TermLike for Delayed {
    fn width(&self) -> u16 {
        self.term.size().1
    }
    fn height(&self) -> u16 {
        self.term.size().0
    }
    fn move_cursor_up(&self, n: usize) -> std::io::Result<()> {
        if self.on() {
            self.term.move_cursor_up(n)?;
        }
        Ok(())
    }
    fn move_cursor_down(&self, n: usize) -> std::io::Result<()> {
        if self.on() {
            self.term.move_cursor_down(n)?;
        }
        Ok(())
    }
    fn move_cursor_right(&self, n: usize) -> std::io::Result<()> {
        if self.on() {
            self.term.move_cursor_right(n)?;
        }
        Ok(())
    }
    fn move_cursor_left(&self, n: usize) -> std::io::Result<()> {
        if self.on() {
            self.term.move_cursor_left(n)?;
        }
        Ok(())
    }
    fn write_line(&self, s: &str) -> std::io::Result<()> {
        if self.on() {
            self.term.write_line(s)?;
        }
        Ok(())
    }
    fn write_str(&self, s: &str) -> std::io::Result<()> {
        if self.on() {
            self.term.write_str(s)?;
        }
        Ok(())
    }
    fn clear_line(&self) -> std::io::Result<()> {
        if self.on() {
            self.term.clear_line()?;
        }
        Ok(())
    }
    fn flush(&self) -> std::io::Result<()> {
        self.term.flush()
    }
}

/// A stand-in terminal for indicatif that prints what it would draw as a
/// plain line, at most once per interval and not before the grace period.
/// Cursor moves and clears are dropped: each line is a new line.
#[derive(Debug)]
pub struct PlainLines {
    started: Instant,
    grace: Duration,
    interval: Duration,
    last: Mutex<Option<Instant>>,
    pending: Mutex<String>,
}

impl PlainLines {
    pub fn new(grace: Duration, interval: Duration) -> PlainLines {
        PlainLines {
            started: Instant::now(),
            grace,
            interval,
            last: Mutex::new(None),
            pending: Mutex::new(String::new()),
        }
    }

    /// The line to print now, if one is due.
    fn due(&self, text: &str) -> Option<String> {
        let text = text.trim();
        let now = Instant::now();
        if text.is_empty() || now.duration_since(self.started) < self.grace {
            return None;
        }
        let mut last = lock(&self.last);
        if last.is_some_and(|t| now.duration_since(t) < self.interval) {
            return None;
        }
        *last = Some(now);
        Some(format!("swimbot: {text}"))
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

impl TermLike for PlainLines {
    fn width(&self) -> u16 {
        // Wide enough that indicatif never wraps or truncates a line.
        400
    }
    fn move_cursor_up(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_down(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_right(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn move_cursor_left(&self, _: usize) -> std::io::Result<()> {
        Ok(())
    }
    fn write_line(&self, s: &str) -> std::io::Result<()> {
        let mut p = lock(&self.pending);
        p.push_str(s);
        p.push(' ');
        Ok(())
    }
    fn write_str(&self, s: &str) -> std::io::Result<()> {
        lock(&self.pending).push_str(&s.replace('\r', ""));
        Ok(())
    }
    fn clear_line(&self) -> std::io::Result<()> {
        Ok(())
    }
    fn flush(&self) -> std::io::Result<()> {
        let text = std::mem::take(&mut *lock(&self.pending));
        match self.due(&text) {
            Some(line) => writeln!(std::io::stderr().lock(), "{line}"),
            None => Ok(()),
        }
    }
}

/// A computation's stages told to `bar`: its message (after `prefix`) and
/// its position, the stage's number.
pub fn to_bar(bar: &ProgressBar, prefix: &'static str) -> crate::workbench::progress::Progress {
    let bar = bar.clone();
    crate::workbench::progress::Progress::new(move |k, message| {
        bar.set_message(format!("{prefix}{message}"));
        bar.set_position(k);
    })
}

/// A computation's stages told to `spinner` as its message only.
pub fn to_message(spinner: &ProgressBar) -> crate::workbench::progress::Progress {
    let spinner = spinner.clone();
    crate::workbench::progress::Progress::new(move |_, message| {
        spinner.set_message(message.to_string());
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_plain_line_says_how_far_along_and_the_expected_rest() {
        let t = Duration::from_secs(30);
        assert_eq!(
            done(250, Some(1000), t, "cases"),
            "250 of 1000 cases (25 %), about 0:01:30 left, "
        );
        assert_eq!(
            done(0, Some(10), t, ""),
            "0 of 10 (0 %), time left unknown yet, "
        );
        assert_eq!(done(3, None, t, "cases"), "");
        // Stages of unequal length: how far along, no extrapolated rest.
        assert_eq!(done(2, Some(5), t, STAGES), "stage 2 of 5, ");
        assert_eq!(done(0, Some(5), t, STAGES), "stage 1 of 5, ");
        assert_eq!(hms(3725.2), "1:02:06");
    }

    #[test]
    fn plain_lines_wait_for_the_grace_period_then_print_once_per_interval() {
        let p = PlainLines::new(Duration::from_millis(30), Duration::from_secs(3600));
        assert_eq!(p.due("early"), None, "inside the grace period");
        std::thread::sleep(Duration::from_millis(40));
        assert_eq!(p.due("   "), None, "a cleared line prints nothing");
        assert_eq!(
            p.due("  compare: 3s \u{20}\u{20}").as_deref(),
            Some("swimbot: compare: 3s")
        );
        assert_eq!(p.due("compare: 4s"), None, "within the interval");
    }
}
