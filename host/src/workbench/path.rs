//! The user's path, computed once: the model the command's options build,
//! taken apart into cumulative steps (the preset or coefficient set alone,
//! then each added effect on top of the step before), each step with its
//! comparison against the data and its summary statistics
//! ([`crate::stats::summarise`] through [`super::compare::compare`]).
//! `compare`, `report` and the page print from this one result, so a step
//! reads the same number everywhere.
//!
//! "+ X" always means X added on top of the previous step's model; nothing
//! is an alternative and nothing appears from nowhere.

use super::compare::{carried_free_params, compare, Comparison};
use super::propagate;
use crate::data::Dataset;
use crate::model::{Model, ModelError};
use crate::stats::FitSummary;

/// One step of the path.
#[derive(Debug, Clone)]
pub struct Step {
    /// `start` or `+ NAME`: the chart's category label.
    pub label: String,
    /// The step's whole model, as the command line writes it.
    pub spec: String,
    pub model: Model,
    /// Against the data, with input-uncertainty bands when the dataset
    /// declares input uncertainties and the model is cheap enough.
    pub comparison: Comparison,
}

impl Step {
    pub fn summary(&self) -> &FitSummary {
        &self.comparison.summary
    }
}

/// The steps, start first; never empty.
#[derive(Debug, Clone)]
pub struct Path {
    pub steps: Vec<Step>,
}

impl Path {
    /// The model the user asked for (the last step).
    pub fn last(&self) -> &Step {
        self.steps.last().expect("a path has its start")
    }

    /// The step before the last, when the user added anything.
    pub fn before_last(&self) -> Option<&Step> {
        self.steps.len().checked_sub(2).map(|i| &self.steps[i])
    }
}

/// `model`'s effects from index `first_added` on are the user's steps; the
/// effects before it (a preset's) form the start.
pub fn user_path(model: &Model, first_added: usize, data: &Dataset) -> Result<Path, ModelError> {
    let first = first_added.min(model.effects.len());
    let mut steps = Vec::with_capacity(model.effects.len() - first + 1);
    for upto in first..=model.effects.len() {
        let mut m = model.clone();
        m.effects.truncate(upto);
        let label = match upto.checked_sub(1).filter(|i| *i >= first) {
            Some(i) => format!("+ {}", model.effects[i].name()),
            None => "start".to_string(),
        };
        steps.push(Step {
            label,
            spec: m.describe(),
            comparison: compare_with_bands(&m, data)?,
            model: m,
        });
    }
    Ok(Path { steps })
}

/// [`compare`] with every free parameter the model carries counted, and
/// the input bands attached when the data declare input uncertainties and
/// the model's solves are cheap.
pub fn compare_with_bands(model: &Model, data: &Dataset) -> Result<Comparison, ModelError> {
    let cmp = compare(model, data, carried_free_params(model))?;
    if propagate::has_input_uncertainty(data) && propagate::affordable(model) {
        Ok(cmp.with_bands(data, &propagate::bands(model, data)?))
    } else {
        Ok(cmp)
    }
}
