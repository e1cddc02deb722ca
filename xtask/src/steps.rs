//! The steps of `cargo xtask test`, timed: each step's wall time is printed
//! when it ends and again in a table at the end, so a slow run says where
//! its minutes went (the README's test-time figure is read off that table).

use std::time::{Duration, Instant};

/// The steps run so far, the current one still open.
pub struct Steps {
    started: Instant,
    current: Option<(String, Instant)>,
    done: Vec<(String, Duration)>,
}

impl Steps {
    pub fn new() -> Self {
        Steps {
            started: Instant::now(),
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
    }
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
}
