//! Whether a log read out is the run the lab just did: the robot answers
//! `LOG` with its current power-up's records, or with an earlier
//! power-up's when this one kept none, and (image version 2) says which
//! and how many records this power-up dropped
//! (`swimbot_shared::run_log::power_up`). A run the robot could not log
//! (no erased slot yet, or a full one) must not be read as the earlier run
//! it falls back to: that is refused unless asked for (`--earlier`);
//! whatever else is not plainly this power-up's whole run is warned about.

use swimbot_shared::run_log::{image::LogImage, LogOf, ThisRun};

/// Why the log is refused: the run the lab expects was not logged.
pub type Refusal = String;

/// The warnings to print for `image`, or why it is refused. `earlier`:
/// an earlier power-up's run is wanted even though this one's was dropped.
pub fn check(image: &LogImage<'_>, earlier: bool) -> Result<Vec<String>, Refusal> {
    let n = image.len();
    let of = LogOf::of(&image.header);
    let mut warnings = Vec::new();
    match image.this_run() {
        Some(ThisRun::Kept) => {}
        Some(ThisRun::NoRun) => {
            if of == LogOf::EarlierPowerUp {
                warnings.push(format!(
                    "the {n} records are an EARLIER power-up's run: the robot was powered off \
                     and on since, and has not run since"
                ));
            }
        }
        Some(ThisRun::PartlyDropped { dropped }) => warnings.push(format!(
            "this power-up's log misses {dropped} records ({}): its slot was not yet erased \
             when the motor first ran, was full, or its flash did not take a page; the \
             trace has gaps",
            running_time(dropped, image.header.sample_period_ms)
        )),
        Some(ThisRun::Dropped { dropped }) => {
            let lost = format!(
                "this power-up's run was NOT logged: the robot dropped all {dropped} records \
                 it took ({}; no erased log slot: the power-up before it ended before its \
                 erase; or flash that did not take the records)",
                running_time(dropped, image.header.sample_period_ms)
            );
            if of != LogOf::EarlierPowerUp {
                return Err(format!("{lost}; the robot holds no other log"));
            }
            if !earlier {
                return Err(format!(
                    "{lost}; the {n} records it sent are an EARLIER power-up's run, not this \
                     one's. Nothing written; give --earlier to read that earlier run"
                ));
            }
            warnings.push(format!(
                "{lost}; reading the {n} records of an EARLIER power-up's run (--earlier)"
            ));
        }
        None => warnings.push(format!(
            "the {n} records are an earlier power-up's run, in a version-1 log: whether the \
             run of the power-up that read it out was dropped cannot be told (firmware older \
             than the version-2 log)"
        )),
    }
    Ok(warnings)
}

/// `n` records at `period_ms` as running time, in words.
fn running_time(n: u32, period_ms: u16) -> String {
    let s = f64::from(n) * f64::from(period_ms) / 1000.0;
    format!("{s:.1} s of running at one record every {period_ms} ms")
}
