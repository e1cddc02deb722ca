//! The section on the paper's model (eq. 11 with the back-flow of eqs. 8-9 and
//! the body corrections of Table III) with both coefficient sets, its
//! Fig. 4 reproduced, and the summary errors of each set.

use super::figure4::models::{layers, Fitted};
use super::figure4::{letters, BLACK, BLUE};
use super::html::{html, omega_b, table, Head, Markup, Render};
use super::page::Part;
use super::wording::{pct, stat};
use crate::data::Dataset;
use crate::model::{preset, Model, ModelError};
use crate::workbench::compare::{Comparison, Quantity};
use crate::workbench::path::compare_with_bands;

/// The paper's two calibrated models and their comparisons.
pub struct PaperModels {
    pub gray_hancock: Model,
    pub lighthill: Model,
    /// Gray-Hancock's comparison, with input-uncertainty bands when the
    /// dataset states input uncertainties.
    pub gh: Comparison,
    pub li: Comparison,
}

/// Mean |relative error| of U and of Omega_b separately.
pub fn mare_by_quantity(cmp: &Comparison) -> (f64, f64) {
    let mean = |v: Vec<f64>| {
        if v.is_empty() {
            f64::NAN
        } else {
            v.iter().sum::<f64>() / v.len() as f64
        }
    };
    (
        mean(
            cmp.cases
                .iter()
                .filter_map(|k| k.u().rel_err.map(f64::abs))
                .collect(),
        ),
        mean(
            cmp.cases
                .iter()
                .filter_map(|k| k.omega().rel_err.map(f64::abs))
                .collect(),
        ),
    )
}

/// `Υ_T,x = 16, Υ_R,x = 1.4`: the body-correction factors in `model`.
pub fn table_iii(model: &Model) -> Markup {
    let factors: Vec<(&str, f64)> = model
        .effects
        .iter()
        .filter(|e| e.name() == "body-correction")
        .flat_map(|e| {
            e.effect
                .params()
                .iter()
                .zip(&e.values)
                .map(|(p, v)| (p.name.as_ref(), *v))
        })
        .collect();
    html! {
        @for (i, (name, v)) in factors.iter().enumerate() {
            @if i > 0 { ", " }
            @match *name {
                "translation" => { "Υ" sub { "T,x" } },
                "rotation" => { "Υ" sub { "R,x" } },
                other => (other),
            }
            " = " (crate::format::fmt_sig(*v, 3))
        }
    }
}

/// `2, fitted by the paper`: the free parameters `model` carries.
pub fn fitted_by_paper(model: &Model) -> String {
    let k: usize = model.effects.iter().map(|e| e.free_indices().len()).sum();
    format!("{k}, fitted by the paper")
}

/// One row of the summary tables: model, free parameters, MARE (all, U,
/// Omega_b), max |error|, reduced chi-square.
pub fn summary_row(name: impl Render, fitted: &str, cmp: &Comparison) -> Vec<Markup> {
    let (u, w) = mare_by_quantity(cmp);
    vec![
        name.render(),
        fitted.render(),
        pct(cmp.summary.mare).render(),
        pct(u).render(),
        pct(w).render(),
        pct(cmp.summary.max_abs_rel_err).render(),
        stat(cmp.summary.chi2_reduced).render(),
    ]
}

/// The summary tables' header.
pub fn summary_header() -> [Head; 7] {
    [
        "<model".into(),
        "<fitted parameters".into(),
        "MARE".into(),
        "MARE of U".into(),
        Head::num(html! { "MARE of " (omega_b()) }),
        "max |error|".into(),
        "reduced χ²".into(),
    ]
}

/// Predicted / measured of `q` for every case that measured it.
fn ratios(cmp: &Comparison, q: Quantity) -> Vec<f64> {
    cmp.cases
        .iter()
        .filter_map(|k| {
            let (p, o) = (k[q].pred, k[q].obs?);
            (o != 0.0).then(|| p / o)
        })
        .collect()
}

/// The mean of predicted / measured of `q` over the cases.
pub fn mean_ratio(cmp: &Comparison, q: Quantity) -> Option<f64> {
    let r = ratios(cmp, q);
    (!r.is_empty()).then(|| r.iter().sum::<f64>() / r.len() as f64)
}

/// "With its Table III factors, Lighthill predicts U at 3.4 times the
/// measured on average (1.8-4.1) ..." : the size of the gap, in numbers.
fn gap_sentence(name: &str, cmp: &Comparison) -> Markup {
    let range = |q: Quantity| {
        let v = ratios(cmp, q);
        let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let part = |q: Quantity, name: Markup| {
        mean_ratio(cmp, q).map(|m| {
            let (lo, hi) = range(q);
            html! {
                (name) " at " (crate::format::fmt_sig(m, 3)) " times the measured on average ("
                (crate::format::fmt_sig(lo, 3)) "-" (crate::format::fmt_sig(hi, 3))
                " over the cases)"
            }
        })
    };
    let parts: Vec<Markup> = [
        part(Quantity::U, html! { "U" }),
        part(Quantity::Omega, omega_b()),
    ]
    .into_iter()
    .flatten()
    .collect();
    if parts.is_empty() {
        return html! {};
    }
    html! {
        p {
            "Here " (name) "'s model with the paper's factors predicts "
            @for (i, part) in parts.iter().enumerate() {
                @if i > 0 { " and " }
                (part)
            }
            "; MARE " (pct(cmp.summary.mare)) "."
        }
    }
}

impl PaperModels {
    pub fn new(data: &Dataset) -> Result<Self, ModelError> {
        let gray_hancock = preset("paper").expect("a built-in preset");
        let lighthill = preset("paper-lighthill").expect("a built-in preset");
        let gh = compare_with_bands(&gray_hancock, data)?;
        let li = compare_with_bands(&lighthill, data)?;
        Ok(PaperModels {
            gray_hancock,
            lighthill,
            gh,
            li,
        })
    }

    pub fn section(&self, data: &Dataset) -> Part {
        let gh3 = table_iii(&self.gray_hancock);
        let li3 = table_iii(&self.lighthill);
        let body = data.cases.first().map_or("-".into(), |c| {
            format!(
                "{} × {}",
                crate::format::fmt_sig(c.body_length_mm, 3),
                crate::format::fmt_sig(c.body_diameter_mm, 3)
            )
        });
        let fig = layers(
            data,
            &[
                Fitted {
                    label: "Gray-Hancock".into(),
                    model: &self.gray_hancock,
                    comparison: &self.gh,
                    color: BLACK,
                    curve: true,
                },
                Fitted {
                    label: "Lighthill".into(),
                    model: &self.lighthill,
                    comparison: &self.li,
                    color: BLUE,
                    curve: true,
                },
            ],
        );
        let ci = super::intro::confidence(data);
        let dodge = super::figure4::dodge_percent();
        let (last_u, first_w, last_w) = letters(fig.groups.len());
        let n_lambda = html! { "N" sub { "λ" } };
        let caption = html! {
            b { "Fig. 4 reproduced." } " Measurements (red, with their " (ci) " confidence \
            intervals) against the paper's model with Gray-Hancock's coefficients (black; "
            (gh3) ") and with Lighthill's (blue; " (li3) "): (a)-(" (last_u) ") dimensionless \
            speed U/U" sub { "wave" } ", U" sub { "wave" } " = λf; (" (first_w) ")-(" (last_w)
            ") dimensionless body rate " (omega_b()) "/ω, against the number of waves "
            (n_lambda) " = L" sub { "t" } "/λ, one panel per amplitude group B" sub { "o" }
            "/R" sub { "body" } ". Hollow markers: the model at each measured case (± 2u where \
            the dataset states input uncertainties). Lines: the same model between the cases \
            of a group, its inputs (chord length, tail rate, the observed speed its back-flow \
            reads) interpolated linearly in " (n_lambda) " between neighbouring cases, so each \
            line passes through its markers; a group of one case has markers only. An error \
            bar smaller than its marker is hidden by it. The models sit side by side, each \
            shifted with its bars and line by " (dodge) " % of the panel's width left or right \
            of the case's " (n_lambda) " in turn, so that bars at one case do not hide each \
            other; the measurements stay at their " (n_lambda) "."
        };
        Part::from(html! {
            p {
                "The paper's model balances the forces and torques on body and tail (eq. 11). \
                The tail's resistance integrates local drag coefficients along the helix \
                (eq. 3), from Gray and Hancock (eqs. 4-5) or from Lighthill (eqs. 6-7). The \
                closed tube adds the drag of the displaced oil flowing back past the body \
                (eqs. 8-9, driven by the " i { "observed" } " speed). The body's axial drag and \
                rotational resistance are multiplied by two factors fitted by the paper \
                (Table III): Gray-Hancock " (gh3) "; Lighthill " (li3) ". Here the body is a "
                (body) " mm prolate spheroid in free space (the paper's body coefficients come \
                from its ref. [28], which is not available), so the paper's own numbers cannot \
                be matched exactly."
            }
        })
        .with(super::figure4::figure("fig4", &fig, caption))
        .with(html! {
            (gap_sentence("Gray-Hancock", &self.gh))
            (gap_sentence("Lighthill", &self.li))
        })
        .with(table(
            &summary_header(),
            &[
                summary_row(
                    html! { "Gray-Hancock, " (gh3) },
                    &fitted_by_paper(&self.gray_hancock),
                    &self.gh,
                ),
                summary_row(
                    html! { "Lighthill, " (li3) },
                    "2, fitted by the paper",
                    &self.li,
                ),
            ],
        ))
        .with(html! {
            p.note {
                "MARE: mean absolute relative error over the " (self.gh.summary.n) " measured \
                quantities; reduced χ²: the squared errors in standard errors of the measured \
                means, over n − k = " (super::yours::dof_note(&self.gh.summary)) " degrees of \
                freedom (k = 2: the factors the paper fitted). Models: "
                code { "--preset paper" } " (" (self.gray_hancock.describe()) ") and "
                code { "--preset paper-lighthill" } " (" (self.lighthill.describe()) ")."
            }
        })
    }
}
