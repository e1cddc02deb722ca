//! The rows and the sources of error of the chi-square with the inputs'
//! covariance ([`crate::workbench::input_covariance`]): one row per measured quantity
//! (its residual and its measured standard error), one source per
//! independent input error with its loads on the rows (the linear band's
//! signed sensitivity times standard uncertainty). A per-case input is one
//! source per case; a shared input one source for all the cases that
//! record the same value and the same uncertainty of it (one tube, one
//! oil, one body), named with its value when cases record several.
//!
//! References: JCGM 100:2008 (GUM) 5.2 (correlated inputs).

use crate::data::uncertainty::{field_value, Scope};
use crate::data::Dataset;
use crate::workbench::compare::Quantity;
use crate::workbench::propagate::Band;

/// One measured quantity: a row of the residual vector.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    pub case: String,
    pub quantity: Quantity,
    /// Observed minus predicted.
    pub residual: f64,
    /// The measured mean's standard error.
    pub sd_measured: f64,
}

/// One independent source of error: an input of one case, or a shared
/// input over the cases that share it.
#[derive(Debug, Clone, PartialEq)]
pub struct Source {
    /// The input's name (with its value when cases record several).
    pub name: String,
    pub scope: Scope,
    /// The declared standard uncertainty, in the input's unit.
    pub standard: f64,
    /// `(row, load)`: the row's change for a one-sigma error of the input.
    pub loads: Vec<(usize, f64)>,
    /// How many cases the source reaches.
    pub cases: usize,
}

/// The rows and sources of a comparison: residuals from `cases` (one per
/// case of `data`, in order: `(id, U predicted, Omega_b predicted)`), loads
/// from the bands, each input's scope from `scope` (the data layer's
/// [`crate::data::uncertainty::scope_of`] outside tests).
pub fn rows_and_sources(
    data: &Dataset,
    predicted: &[(f64, f64)],
    bands: &[Band],
    scope: impl Fn(&str) -> Scope,
) -> (Vec<Row>, Vec<Source>) {
    let mut rows = Vec::new();
    // per case: the row of U and of Omega_b, where measured
    let mut at = Vec::with_capacity(data.cases.len());
    for (case, (u, o)) in data.cases.iter().zip(predicted) {
        let mut push = |q, m: &crate::data::Measured, pred: f64| {
            rows.push(Row {
                case: case.id.clone(),
                quantity: q,
                residual: m.mean - pred,
                sd_measured: m.standard_error(),
            });
            rows.len() - 1
        };
        let ru = case.u_mm_s.as_ref().map(|m| push(Quantity::U, m, *u));
        let ro = case
            .omega_body_hz
            .as_ref()
            .map(|m| push(Quantity::Omega, m, *o));
        at.push((ru, ro));
    }
    let mut sources: Vec<(Source, u64, u64)> = Vec::new();
    for ((case, band), (ru, ro)) in data.cases.iter().zip(bands).zip(&at) {
        for c in &band.contributions {
            let loads: Vec<(usize, f64)> = [(*ru, c.u_mm_s), (*ro, c.omega_hz)]
                .into_iter()
                .filter_map(|(r, l)| r.map(|r| (r, l)))
                .collect();
            let value = field_value(case, c.field).unwrap_or(f64::NAN).to_bits();
            let key = (value, c.standard.to_bits());
            let same = |s: &(Source, u64, u64)| {
                s.0.scope == Scope::Shared && s.0.name == c.field && (s.1, s.2) == key
            };
            match sources.iter_mut().find(|s| same(s)) {
                Some(s) if scope(c.field) == Scope::Shared => {
                    s.0.loads.extend(loads);
                    s.0.cases += 1;
                }
                _ => sources.push((
                    Source {
                        name: c.field.to_string(),
                        scope: scope(c.field),
                        standard: c.standard,
                        loads,
                        cases: 1,
                    },
                    key.0,
                    key.1,
                )),
            }
        }
    }
    name_distinct_objects(&mut sources);
    (rows, sources.into_iter().map(|s| s.0).collect())
}

/// A shared input recorded with several values is several objects: each
/// is named with its value.
fn name_distinct_objects(sources: &mut [(Source, u64, u64)]) {
    let shared = |s: &Source| s.scope == Scope::Shared;
    let names: Vec<String> = sources.iter().map(|s| s.0.name.clone()).collect();
    for (s, value, _) in sources.iter_mut().filter(|s| shared(&s.0)) {
        let groups = names.iter().filter(|n| **n == s.name).count();
        if groups > 1 {
            s.name = format!(
                "{} = {}",
                s.name,
                crate::format::fmt_sig(f64::from_bits(*value), 4)
            );
        }
    }
}
