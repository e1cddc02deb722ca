//! Network fetches started at the beginning of `cargo xtask test` and
//! collected when their step comes: `npm ci` for the emulator tests and the
//! RP2040 bootrom download. They wait on the network, not the CPU, so they
//! overlap the compile steps instead of adding to the total.

use std::fs::File;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

/// A command running in the background, its output going to a log file.
pub struct Background {
    what: String,
    log: PathBuf,
    child: Result<Child, String>,
}

impl Background {
    /// Start `program args` in `dir`; stdout and stderr go to `log`.
    pub fn start(what: &str, dir: &Path, program: &str, args: &[&str], log: PathBuf) -> Self {
        let child = File::create(&log)
            .and_then(|out| {
                let err = out.try_clone()?;
                Command::new(program)
                    .args(args)
                    .current_dir(dir)
                    .stdin(Stdio::null())
                    .stdout(out)
                    .stderr(err)
                    .spawn()
            })
            .map_err(|e| format!("cannot start `{program}` ({what}): {e}"));
        Background {
            what: what.to_string(),
            log,
            child,
        }
    }

    /// Wait for it; print its output either way, fail if it failed.
    pub fn finish(self) -> Result<(), String> {
        let status = self
            .child?
            .wait()
            .map_err(|e| format!("{}: {e}", self.what))?;
        let output = std::fs::read_to_string(&self.log).unwrap_or_default();
        println!("{} (ran in the background):", self.what);
        print!("{output}");
        if status.success() {
            Ok(())
        } else {
            Err(format!(
                "{} failed ({status}); its output is in {}",
                self.what,
                self.log.display()
            ))
        }
    }
}
