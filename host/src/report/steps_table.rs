//! The study's steps as a paper has them, one renderer for the bundle
//! (`tables/steps.tex`, `steps.md`, `laws.tex`, `laws.md`) and for
//! `swimbot steps --format latex|markdown`: a table with booktabs rules
//! (`\toprule`, `\midrule`, `\bottomrule`) and Markdown for a lab
//! notebook, one row per step with the error after it and its fitted
//! parameters, and each step's law as a LaTeX `equation` with its fitted
//! values. Values are `value ± u` rounded at the uncertainty's second
//! significant digit (JCGM 100 sec. 7.2.6, [`crate::format::rounding`]).
//! Every user-given name (effects, parameters, files) is escaped for
//! LaTeX ([`tex`]) and for Markdown's table cells.

use crate::format::fmt_sig;
use crate::format::rounding::{percent, value_pm};
use crate::study::file::ParamRecord;
use crate::study::Study;
use crate::workbench::fit::report::ParamReport;

/// One row: a step and the numbers after it.
pub struct PaperRow {
    pub step: usize,
    pub effect: String,
    /// MARE after the step (a fraction).
    pub mare: f64,
    pub cv_mare: f64,
    pub chi2_reduced: Option<f64>,
    /// `name = value ± u [lo, hi]` per fitted parameter.
    pub params: Vec<String>,
}

/// The rows of `s`: the base model, then each step with its own
/// parameters as the study file holds them.
pub fn rows(s: &Study) -> Vec<PaperRow> {
    let f = s.file();
    let mut out = vec![PaperRow {
        step: 0,
        effect: format!("base ({})", f.model.preset),
        mare: f.start.stats.mare,
        cv_mare: f.start.stats.cv_mare,
        chi2_reduced: f.start.stats.chi2_reduced,
        params: Vec::new(),
    }];
    out.extend(s.steps().iter().enumerate().map(|(i, st)| PaperRow {
        step: i + 1,
        effect: st.effect.name.clone(),
        mare: st.after.stats.mare,
        cv_mare: st.after.stats.cv_mare,
        chi2_reduced: st.after.stats.chi2_reduced,
        params: fitted(&st.params).map(|p| param(&p)).collect(),
    }));
    out
}

/// A step's fitted parameters as reports (held settings are not results).
pub fn fitted(params: &[ParamRecord]) -> impl Iterator<Item = ParamReport> + '_ {
    params
        .iter()
        .filter(|p| p.status == "fitted")
        .map(ParamRecord::report)
}

/// `name = value ± u unit (rel %, 95 % lo .. hi)`, or the value alone:
/// the terminal's, the page's and the tables' one spelling.
pub fn param(p: &ParamReport) -> String {
    let unit = match p.unit.as_str() {
        "" | "1" => String::new(),
        u => format!(" {u}"),
    };
    let bound = if p.at_bound { ", at its bound" } else { "" };
    let Some(u) = p.standard_uncertainty else {
        return format!(
            "{} = {}{unit} (no interval of its own{bound})",
            p.name,
            value_pm(p.value, None)
        );
    };
    let rel = p
        .relative_uncertainty_percent
        .map(|r| format!("{}, ", percent(r)))
        .unwrap_or_default();
    let profile = p.interval == "profile";
    let ci = match (p.ci95_low, p.ci95_high) {
        (None, None) if !profile => String::new(),
        (lo, hi) => format!(
            "95\u{a0}% {}{}\u{a0}..\u{a0}{}",
            if profile { "profile " } else { "" },
            end(lo, u),
            end(hi, u)
        ),
    };
    format!(
        "{} = {}{unit} ({rel}{ci}{bound})",
        p.name,
        value_pm(p.value, Some(u))
    )
}

/// An interval's end at the decimal place of the uncertainty `u` (with
/// the power of ten `value ± u` shares, `(1.2 ± 0.3)e-4` -> `1.2e-4`); a
/// profile's end not reached within the parameter's range is open.
fn end(x: Option<f64>, u: f64) -> String {
    let Some(x) = x else {
        return "open".to_string();
    };
    let t = value_pm(x, Some(u));
    let (mantissa, rest) = t.split_once(" ± ").unwrap_or((&t, ""));
    match (mantissa.strip_prefix('('), rest.rsplit_once(")e")) {
        (Some(m), Some((_, e))) => format!("{m}e{e}"),
        _ => mantissa.to_string(),
    }
}

fn pct(v: f64) -> String {
    format!("{:.2}", 100.0 * v)
}

fn chi(v: Option<f64>) -> String {
    v.map_or("-".into(), |c| fmt_sig(c, 3))
}

/// `s` as LaTeX text: the characters LaTeX treats as commands escaped,
/// the paper's Greek letters and symbols as math.
pub fn tex(s: &str) -> String {
    let mut out = String::new();
    for c in s.chars() {
        match c {
            '_' | '%' | '&' | '#' | '$' | '{' | '}' => {
                out.push('\\');
                out.push(c);
            }
            '^' => out.push_str("\\^{}"),
            '~' => out.push_str("\\textasciitilde{}"),
            '\\' => out.push_str("\\textbackslash{}"),
            '<' => out.push_str("\\textless{}"),
            '>' => out.push_str("\\textgreater{}"),
            '|' => out.push_str("\\textbar{}"),
            'ψ' => out.push_str("$\\psi$"),
            'λ' => out.push_str("$\\lambda$"),
            'Ω' => out.push_str("$\\Omega$"),
            'ω' => out.push_str("$\\omega$"),
            'π' => out.push_str("$\\pi$"),
            'χ' => out.push_str("$\\chi$"),
            '²' => out.push_str("$^2$"),
            '·' => out.push_str("$\\cdot$"),
            '±' => out.push_str("$\\pm$"),
            '°' => out.push_str("$^\\circ$"),
            '\u{a0}' => out.push('~'),
            // A line break or a control character would end the row or
            // the command it stands in.
            c if c.is_control() => out.push(' '),
            _ => out.push(c),
        }
    }
    out
}

/// `s` as the text of one Markdown table cell: the cell's bar escaped and
/// a line break (which would end the row) as a space.
fn md_cell(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect::<String>()
        .replace('|', "\\|")
}

/// The table in LaTeX (needs `\usepackage{booktabs}`).
pub fn latex(rows: &[PaperRow]) -> String {
    let mut s = String::from(
        "\\begin{tabular}{rlrrrl}\n\\toprule\nStep & Effect & MARE (\\%) & CV MARE (\\%) & $\\chi^2/\\nu$ & Parameters ($\\pm u$; 95\\,\\% interval) \\\\\n\\midrule\n",
    );
    for r in rows {
        s.push_str(&format!(
            "{} & {} & {} & {} & {} & {} \\\\\n",
            r.step,
            tex(&r.effect),
            pct(r.mare),
            pct(r.cv_mare),
            chi(r.chi2_reduced),
            tex(&r.params.join("; "))
        ));
    }
    s.push_str("\\bottomrule\n\\end{tabular}\n");
    s
}

/// The table in Markdown.
pub fn markdown(rows: &[PaperRow]) -> String {
    let mut s = String::from(
        "| Step | Effect | MARE (%) | CV MARE (%) | χ²/ν | Parameters (± u; 95 % interval) |\n|---:|---|---:|---:|---:|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            r.step,
            md_cell(&r.effect),
            pct(r.mare),
            pct(r.cv_mare),
            chi(r.chi2_reduced),
            md_cell(&r.params.join("; "))
        ));
    }
    s
}

/// A comment's text: one line (a line break would end the comment and
/// make the rest LaTeX).
fn comment(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// `name = value \pm u\,unit` as math; where the 95 % interval is the
/// profile's (asymmetric, so `\pm u` misreads it), its ends beside it.
fn param_math(p: &ParamReport) -> String {
    let unit = match p.unit.as_str() {
        "" | "1" => String::new(),
        u => format!("\\,\\text{{{}}}", tex(u)),
    };
    let profile = match p.standard_uncertainty {
        Some(u) if p.interval == "profile" => format!(
            "\\;(95\\,\\%\\ \\text{{profile}}\\ {}\\,..\\,{})",
            tex(&end(p.ci95_low, u)),
            tex(&end(p.ci95_high, u))
        ),
        _ => String::new(),
    };
    format!(
        "{} = {}{unit}{profile}",
        super::tex_math::name(p.name.rsplit('.').next().unwrap_or(&p.name)),
        super::tex_math::value_pm(&value_pm(p.value, p.standard_uncertainty))
    )
}

/// Each step's law as a LaTeX `equation` (needs `amsmath`), its fitted
/// values beside it (`value \pm u`); a catalogue effect, whose law is in
/// words, as a comment with its statement and an equation of its values.
pub fn laws_latex(s: &Study) -> String {
    let mut out = String::from(
        "% The study's laws with their fitted values (value \\pm standard uncertainty,\n% JCGM 100 sec. 7.2.6); needs \\usepackage{amsmath}.\n",
    );
    for (i, st) in s.steps().iter().enumerate() {
        let n = i + 1;
        out.push_str(&format!(
            "% Step {n}: + {}: {}\n",
            comment(&st.effect.name),
            comment(&st.effect.statement)
        ));
        let values: Vec<String> = fitted(&st.params).map(|p| param_math(&p)).collect();
        let values = values.join(",\\; ");
        let laws: Vec<String> = st
            .effect
            .formula
            .iter()
            .map(|f| super::tex_math::math(f))
            .collect();
        let body = match (laws.is_empty(), values.is_empty()) {
            (true, true) => continue,
            (true, false) => values,
            (false, true) => laws.join(",\\qquad "),
            (false, false) => format!("{},\\qquad {values}", laws.join(",\\qquad ")),
        };
        out.push_str(&format!(
            "\\begin{{equation}}\n  {body}\n  \\label{{eq:step-{n}}}\n\\end{{equation}}\n"
        ));
    }
    out
}

/// Each step's law and fitted values as a Markdown list for a notebook.
pub fn laws_markdown(s: &Study) -> String {
    let mut out = String::new();
    for (i, st) in s.steps().iter().enumerate() {
        let code = |t: &str| md_cell(t).replace('`', "'");
        let laws: Vec<String> = st
            .effect
            .formula
            .iter()
            .map(|f| format!("`{}`", code(f)))
            .collect();
        let law = match laws.is_empty() {
            true => code(&st.effect.statement),
            false => laws.join("; "),
        };
        let values: Vec<String> = fitted(&st.params).map(|p| code(&param(&p))).collect();
        out.push_str(&format!(
            "{}. **+ {}**: {law}",
            i + 1,
            code(&st.effect.name)
        ));
        if !values.is_empty() {
            out.push_str(&format!("; {}", values.join("; ")));
        }
        out.push('\n');
    }
    out
}

/// The paper's files of `s` for the page's bundle: the steps table and
/// the laws, each in LaTeX and in Markdown.
pub fn bundle_files(s: &Study) -> Vec<super::page::Artefact> {
    let rows = rows(s);
    let file = |file: &str, kind, caption: &str, text| super::page::Artefact {
        file: format!("tables/{file}"),
        kind,
        caption: caption.into(),
        text,
    };
    vec![
        file(
            "steps.tex",
            "table-latex",
            "the steps table in LaTeX (booktabs), as `swimbot steps --format latex` prints it",
            latex(&rows),
        ),
        file(
            "steps.md",
            "table-markdown",
            "the steps table in Markdown, as `swimbot steps --format markdown` prints it",
            markdown(&rows),
        ),
        file(
            "laws.tex",
            "equations-latex",
            "each step's law with its fitted values, as LaTeX equations (amsmath)",
            laws_latex(s),
        ),
        file(
            "laws.md",
            "equations-markdown",
            "each step's law with its fitted values, as a Markdown list",
            laws_markdown(s),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rows() -> Vec<PaperRow> {
        vec![
            PaperRow {
                step: 0,
                effect: "(base: base)".into(),
                mare: 2.946,
                cv_mare: 2.946,
                chi2_reduced: Some(8.23e6),
                params: vec![],
            },
            PaperRow {
                step: 1,
                effect: "located_tail_torque".into(),
                mare: 0.2107,
                cv_mare: 0.2226,
                chi2_reduced: Some(12700.0),
                params: vec!["k = 1.255 [1.195, 1.314]".into()],
            },
        ]
    }

    #[test]
    fn latex_has_booktabs_rules_one_row_per_step_and_escaped_names() {
        let t = latex(&rows());
        assert!(t.contains("\\toprule") && t.contains("\\midrule") && t.contains("\\bottomrule"));
        assert_eq!(t.matches(" \\\\\n").count(), 3, "{t}");
        assert!(
            t.contains("located\\_tail\\_torque & 21.07 & 22.26 & 12700"),
            "{t}"
        );
        assert!(t.contains("294.60"), "{t}");
    }

    fn report(
        value: f64,
        u: f64,
        ends: (Option<f64>, Option<f64>),
        interval: &'static str,
    ) -> ParamReport {
        ParamReport {
            name: "law.f".into(),
            unit: "N".into(),
            value,
            standard_uncertainty: Some(u),
            relative_uncertainty_percent: Some(100.0 * u / value),
            ci95_low: ends.0,
            ci95_high: ends.1,
            interval: interval.into(),
            at_bound: false,
        }
    }

    #[test]
    fn a_small_parameters_interval_ends_carry_its_power_of_ten() {
        let r = report(1.5e-4, 2e-5, (Some(1.108e-4), Some(1.892e-4)), "covariance");
        let s = param(&r);
        assert!(s.contains("(1.50 ± 0.20)e-4 N"), "{s}");
        assert!(s.contains("95\u{a0}% 1.11e-4\u{a0}..\u{a0}1.89e-4)"), "{s}");
    }

    #[test]
    fn a_laws_equation_carries_the_profile_interval_where_it_is_the_one() {
        let p = report(2.0, 0.5, (Some(1.6), None), "profile");
        let m = param_math(&p);
        assert!(
            m.ends_with("\\;(95\\,\\%\\ \\text{profile}\\ 1.60\\,..\\,open)"),
            "{m}"
        );
        let c = param_math(&report(2.0, 0.5, (Some(1.02), Some(2.98)), "covariance"));
        assert!(!c.contains("95"), "± u says the covariance's: {c}");
    }

    #[test]
    fn markdown_has_a_header_and_one_row_per_step() {
        let t = markdown(&rows());
        assert_eq!(t.lines().count(), 4, "{t}");
        assert!(
            t.contains(
                "| 1 | located_tail_torque | 21.07 | 22.26 | 12700 | k = 1.255 [1.195, 1.314] |"
            ),
            "{t}"
        );
    }
}
