//! The steps of `cargo xtask test`, timed: each step's wall time is printed
//! when it ends and again in a table at the end, so a slow run says where
//! its minutes went (the README's test-time figure is read off that table).
//! On Linux it also prints the CPU time the hypervisor gave to other guests
//! meanwhile ("steal", `/proc/stat`): on a shared 2-core machine that alone
//! has stretched the same rebuild of the workspace crates from 2:09 to 3:21.

use std::time::{Duration, Instant};

/// The steps run so far, the current one still open.
pub struct Steps {
    started: Instant,
    steal_at_start: Option<f64>,
    current: Option<(String, Instant)>,
    done: Vec<(String, Duration)>,
}

impl Steps {
    pub fn new() -> Self {
        Steps {
            started: Instant::now(),
            steal_at_start: steal_s(),
            current: None,
            done: Vec::new(),
        }
    }

    /// Close the open step and start `title`.
    pub fn begin(&mut self, title: &str) {
        self.close();
        println!("\n==> {title}");
        self.current = Some((title.to_string(), Instant::now()));
    }

    fn close(&mut self) {
        if let Some((title, t0)) = self.current.take() {
            let took = t0.elapsed();
            println!("--- {:.1} s", took.as_secs_f64());
            self.done.push((title, took));
        }
    }

    /// Close the open step and print every step's time and the total.
    pub fn summary(&mut self) {
        self.close();
        println!("\nstep times (wall clock):");
        for (title, took) in &self.done {
            println!("  {:>7}  {title}", mmss(*took));
        }
        println!("  {:>7}  total", mmss(self.started.elapsed()));
        if let (Some(t0), Some(t1)) = (self.steal_at_start, steal_s()) {
            println!(
                "  {:>7}  CPU time stolen by other guests of this machine's host (summed over cores)",
                mmss(Duration::from_secs_f64((t1 - t0).max(0.0)))
            );
        }
    }
}

/// Seconds of steal time so far, summed over cores (`/proc/stat`, Linux).
fn steal_s() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/stat").ok()?;
    parse_steal_ticks(&stat).map(|ticks| ticks / 100.0) // USER_HZ is 100 on Linux
}

/// The 8th number of the `cpu` line: user nice system idle iowait irq softirq steal.
fn parse_steal_ticks(stat: &str) -> Option<f64> {
    let line = stat.lines().find(|l| l.starts_with("cpu "))?;
    line.split_whitespace().nth(8)?.parse().ok()
}

fn mmss(d: Duration) -> String {
    // Rounded to tenths first, so 59.96 s reads 1:00.0, not 0:60.0.
    let tenths = (d.as_secs_f64() * 10.0).round() as u64;
    format!("{}:{:02}.{}", tenths / 600, tenths % 600 / 10, tenths % 10)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn minutes_and_seconds() {
        assert_eq!(mmss(Duration::from_millis(65_240)), "1:05.2");
        assert_eq!(mmss(Duration::from_millis(59_960)), "1:00.0");
        assert_eq!(mmss(Duration::from_millis(9_000)), "0:09.0");
        assert_eq!(mmss(Duration::from_secs(600)), "10:00.0");
    }

    #[test]
    fn steal_is_the_eighth_number_of_the_cpu_line() {
        let stat =
            "cpu  3918733 1535 266341 572721 10473 0 1651 186777 0 0\ncpu0 1 2 3 4 5 6 7 8 9 10\n";
        assert_eq!(parse_steal_ticks(stat), Some(186777.0));
        assert_eq!(parse_steal_ticks("cpu0 1 2 3\n"), None);
    }
}
