//! Progress of a long computation: a callback the computation calls as each
//! of its stages starts, handed in by the caller (a terminal's spinner, a
//! notebook's widget), so that no display lives in a global and a second
//! call in the same process reports to its own caller.

use std::sync::Arc;

/// What reports a stage: its number (from 1) and a short message.
type Report = dyn Fn(u64, &str) + Send + Sync;

/// Called with the stage's number (from 1) and a short message as each
/// stage starts.
#[derive(Clone)]
pub struct Progress(Arc<Report>);

impl Progress {
    pub fn new(report: impl Fn(u64, &str) + Send + Sync + 'static) -> Self {
        Progress(Arc::new(report))
    }

    /// Stage `k` starts.
    pub fn stage(&self, k: u64, message: &str) {
        (self.0)(k, message)
    }
}

impl std::fmt::Debug for Progress {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Progress(..)")
    }
}

/// Reports to `progress`, if there is one.
pub fn say(progress: &Option<Progress>, k: u64, message: &str) {
    if let Some(p) = progress {
        p.stage(k, message);
    }
}
