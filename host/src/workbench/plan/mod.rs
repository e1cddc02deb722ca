//! The next experiment: the runs that best tell apart the explanations the
//! data cannot (the rival sets of a `diagnose` verdict), or otherwise most
//! sharpen the fitted law's parameters, chosen inside what the rig can run.
//!
//! - [`criterion`]: the T-optimal distance between two models over planned
//!   runs, in the standard errors the study's noise model gives each run;
//! - [`rivals`]: the models to separate, taken from a diagnosis;
//! - [`candidates`]: the runs the rig can make (the tails on hand, the
//!   tubes and oils on hand, rates inside the motor's range);
//! - [`select`]: the greedy (sequential) choice of runs, maximin over pairs;
//! - [`reach`]: the set-points the robot's motor can hold against the load;
//! - [`keys`]: a run's set-point as the IR keys the lab presses;
//! - [`sheet`]: the run sheet, a dataset CSV with the measurements empty.

pub mod candidates;
pub mod criterion;
pub mod keys;
pub mod reach;
pub mod rivals;
pub mod select;
pub mod sheet;

pub use candidates::{candidates, Candidate, PlanRig, RigError};
pub use criterion::Noise;
pub use reach::{Reach, Unlimited};
pub use rivals::{rivals_of, Goal, Rival};
pub use select::{plan, reachable, Plan, PlannedRun};

/// A plan for a model on its data: `diagnose` for the rivals, then the
/// runs of `rig` that `reach` can hold, `runs` of them chosen (`None`:
/// nothing to separate or sharpen). What `swimbot plan` runs in a study.
pub fn plan_for(
    model: &crate::model::Model,
    data: &crate::data::Dataset,
    settings: &crate::workbench::diagnose::DiagnoseSettings,
    rig: &PlanRig,
    runs: usize,
    reach: &dyn Reach,
) -> Result<(rivals::Rivals, Option<Plan>), PlanError> {
    let cands = candidates(data, rig).map_err(PlanError::Rig)?;
    let d = crate::workbench::diagnose::diagnose(model, data, settings).map_err(PlanError::Fit)?;
    let rivals = rivals_of(&d);
    if rivals.goal == Goal::Nothing {
        return Ok((rivals, None));
    }
    let p = plan(cands, &rivals, &Noise::of(data), runs, reach);
    Ok((rivals, Some(p)))
}

/// Why no plan was made.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// The rig can run nothing (an input error, naming the flag).
    #[error("{0}")]
    Rig(RigError),
    /// The diagnosis failed.
    #[error("{0}")]
    Fit(crate::workbench::fit::FitError),
}
