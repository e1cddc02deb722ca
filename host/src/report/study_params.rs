//! A study step's parameters as the page's table: every parameter of the
//! step's effect (and those a joint refit changed), its value, its 95 %
//! interval and which one that is, `covariance` (`value ± 1.96 u`, cut at
//! the parameter's range) or `profile` (the profile likelihood's, where
//! it is asymmetric, as `diagnose` reports it:
//! [`crate::workbench::fit::report::ParamReport::with_profile`]).

use super::html::table;
use super::page::Part;
use crate::chart::notation;
use crate::format::fmt_sig;
use crate::study::file::ParamRecord;
use crate::study::StepRecord;

/// A number as the page prints it: 4 significant digits, in its own cell.
fn num(v: f64) -> String {
    fmt_sig(v, 4)
}

fn opt_num(v: Option<f64>) -> String {
    v.map_or_else(String::new, num)
}

pub fn params_table(st: &StepRecord) -> Part {
    let rows: Vec<Vec<String>> = st
        .params
        .iter()
        .chain(&st.refitted)
        .map(|p| {
            let (lo, hi, kind) = interval_cells(p);
            vec![
                p.effect.clone(),
                notation(&p.name),
                p.unit.clone(),
                num(p.value),
                lo,
                hi,
                kind,
                p.status.clone(),
                p.reason
                    .as_deref()
                    .unwrap_or(if p.at_bound { "at its bound" } else { "" })
                    .to_string(),
            ]
        })
        .collect();
    table(
        &[
            "<effect",
            "<parameter",
            "<unit",
            "value",
            "95 % low",
            "95 % high",
            "<interval",
            "<status",
            "<why",
        ],
        &rows,
    )
}

/// A parameter's 95 % interval as the page reports it and which one it
/// is: a fitted one's as [`ParamRecord::report`] chooses (the profile's
/// where asymmetric, an end it leaves open said so), else the stored ends.
fn interval_cells(p: &ParamRecord) -> (String, String, String) {
    if p.status != "fitted" {
        return (opt_num(p.lo), opt_num(p.hi), String::new());
    }
    let r = p.report();
    let profile = r.interval == "profile";
    let end = |x: Option<f64>| match x {
        None if profile => "open".to_string(),
        x => opt_num(x),
    };
    let kind = if r.standard_uncertainty.is_some() {
        r.interval.to_string()
    } else {
        String::new()
    };
    (end(r.ci95_low), end(r.ci95_high), kind)
}
