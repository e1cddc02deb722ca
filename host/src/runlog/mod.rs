//! The robot's run log on the host: the log image the
//! firmware keeps in flash and hands out over USB (`swimbot_shared::run_log`,
//! whose module doc has the byte layout), read from a saved file or the
//! robot's port ([`read`]), decoded ([`decode`]) and checked to be the run of the power-up that
//! read it out ([`power_up`]: a run the robot could not log is refused,
//! not read as the earlier run it falls back to), turned into a time
//! series ([`trace`]), cut into steady windows ([`steady`]: set-point constant, rate settled), and those
//! into a dataset's cases and trials ([`trials`], `docs/data-format.md`),
//! with the trace figure ([`figure`]); with a can-temperature CSV from the
//! bench, the housing's thermal constants ([`thermal`]).
//!
//! What the log measures is the motor's rate, the tail relative to the
//! body, as the Hall ring on the coupler sees it; the lab-frame tail rate
//! the paper counts on video is that minus the body's counter-rotation,
//! which the log cannot know, nor the swimming speed: those stay the lab's
//! to measure. `docs/run-log.md` is the user's guide.
//!
//! References: the paper (`shared/seed/in-channel-vertical-swimming.md`,
//! section IV, the limitation on f); the batch-means estimate of the
//! variance of a mean from correlated samples: G. S. Fishman, *Discrete-Event
//! Simulation*, Springer 2001, section 6.6.

pub mod decode;
pub mod figure;
pub mod power_up;
pub mod read;
pub mod steady;
pub mod thermal;
pub mod trace;
pub mod trials;

pub use decode::{LogContentError, RunLog};
pub use read::{read_current, read_source, LogError, Source};
pub use steady::{steady_windows, SteadyWindow, STEADY_BAND};
pub use trace::{LogPoint, Trace};
