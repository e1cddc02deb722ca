//! Residual plots: the relative error of U and Omega_b against the case
//! features that correlate with it most (where the model fails).

use super::plots::{chart, Series, PALETTE};
use crate::data::Dataset;
use crate::workbench::compare::Comparison;
use crate::workbench::features::{trends, FEATURES};

pub fn residual_plots(data: &Dataset, cmp: &Comparison) -> Vec<Result<String, String>> {
    trends(data, cmp)
        .iter()
        .take(4)
        .map(|t| {
            let f = FEATURES
                .iter()
                .find(|f| f.name == t.feature)
                .expect("trend features come from FEATURES");
            let pts = data
                .cases
                .iter()
                .zip(&cmp.cases)
                .filter_map(|(c, k)| {
                    let e = match t.quantity {
                        crate::workbench::compare::Quantity::U => k.u_rel_err,
                        crate::workbench::compare::Quantity::Omega => k.omega_rel_err,
                    }?;
                    Some(((f.value)(c), e, 0.0))
                })
                .collect();
            let s = Series::measured(format!("r = {:+.2}", t.r), PALETTE[1], pts);
            chart(
                &format!("{} error vs {}", t.quantity.label(), t.feature),
                t.feature,
                "relative error",
                &[s],
                false,
            )
        })
        .collect()
}
