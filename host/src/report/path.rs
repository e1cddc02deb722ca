//! "Watch the error fall": MARE and reduced chi-square along the path from
//! the model to the models that explain the data.

use super::plots::steps;
use crate::data::Dataset;
use crate::model::Model;
use crate::workbench::compare::compare;
use crate::workbench::diagnose::Diagnosis;

/// MARE and reduced chi-square as the model's effects are added one by one
/// (then `diagnose`'s proposal, when given).
pub fn error_falls(
    model: &Model,
    data: &Dataset,
    diagnosis: Option<&Diagnosis>,
) -> Vec<Result<String, String>> {
    let mut labels = vec![model.coefficients.to_string()];
    let mut mare = Vec::new();
    let mut chi2 = Vec::new();
    let mut m = Model {
        effects: Vec::new(),
        ..model.clone()
    };
    let push = |m: &Model, mare: &mut Vec<f64>, chi2: &mut Vec<f64>| {
        let c = compare(m, data, 0).ok();
        mare.push(c.as_ref().map_or(f64::NAN, |c| 100.0 * c.summary.mare));
        chi2.push(c.and_then(|c| c.summary.chi2_reduced).unwrap_or(f64::NAN));
    };
    push(&m, &mut mare, &mut chi2);
    for e in &model.effects {
        m.effects.push(e.clone());
        labels.push(format!("+{}", e.name()));
        push(&m, &mut mare, &mut chi2);
    }
    if let Some(d) = diagnosis {
        let proposal = d
            .pairs
            .first()
            .filter(|_| d.ranking.first().is_none_or(|c| !c.at_noise_floor))
            .or(d.ranking.first());
        if let Some(c) = proposal {
            labels.push(format!("+{} (fitted)", c.effect));
            push(&c.model, &mut mare, &mut chi2);
        }
    }
    vec![
        steps("Watch the error fall: MARE", "MARE (%)", &labels, &mare),
        steps(
            "... and the reduced chi-square",
            "chi-square / dof",
            &labels,
            &chi2,
        ),
    ]
}
