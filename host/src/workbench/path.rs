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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::parse_effect_spec;

    fn model(specs: &[&str]) -> Model {
        let mut m = Model::base();
        for s in specs {
            m.effects.push(parse_effect_spec(s).unwrap());
        }
        m
    }

    #[test]
    fn each_step_is_the_step_before_plus_one_effect() {
        let data = crate::data::paper();
        let m = model(&[
            "backflow-observed",
            "body-correction:translation=16,rotation=1.4",
            "body-confinement",
        ]);
        let p = user_path(&m, 1, &data).unwrap();
        let labels: Vec<&str> = p.steps.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["start", "+ body-correction", "+ body-confinement"]);
        for w in p.steps.windows(2) {
            let (a, b) = (&w[0].model, &w[1].model);
            assert_eq!(b.effects.len(), a.effects.len() + 1);
            assert!(a
                .effects
                .iter()
                .zip(&b.effects)
                .all(|(x, y)| x.spec() == y.spec()));
        }
        assert_eq!(p.last().spec, m.describe());
        assert_eq!(p.before_last().unwrap().label, "+ body-correction");
    }

    #[test]
    fn a_step_reads_what_compare_reads_for_its_model() {
        let data = crate::data::paper();
        let m = model(&[
            "backflow-observed",
            "body-correction:translation=16,rotation=1.4",
        ]);
        let p = user_path(&m, 0, &data).unwrap();
        for s in &p.steps {
            let direct = compare(&s.model, &data, 0).unwrap().summary;
            assert_eq!(s.summary().mare, direct.mare);
            assert_eq!(s.summary().chi2_reduced, direct.chi2_reduced);
            // the fitted factors count, whoever fitted them
            assert_eq!(s.summary().free_params, carried_free_params(&s.model));
        }
        assert_eq!(p.last().summary().free_params, 2);
        assert_eq!(p.last().summary().dof(), Some(10));
    }

    #[test]
    fn a_model_with_nothing_added_is_one_step() {
        let data = crate::data::paper();
        let m = crate::model::preset("paper").unwrap();
        let p = user_path(&m, m.effects.len(), &data).unwrap();
        assert_eq!(p.steps.len(), 1);
        assert!(p.before_last().is_none());
        assert_eq!(p.last().label, "start");
    }
}
