//! The study's steps as a paper's table: LaTeX with booktabs rules
//! (`\toprule`, `\midrule`, `\bottomrule`) and Markdown for a lab
//! notebook, one row per step with the error after it and its fitted
//! parameters with their 95 % intervals (`swimbot steps --format
//! latex|markdown`).

use crate::format::fmt_sig;

/// One row: a step and the numbers after it.
pub struct PaperRow {
    pub step: usize,
    pub effect: String,
    /// MARE after the step (a fraction).
    pub mare: f64,
    pub cv_mare: f64,
    pub chi2_reduced: Option<f64>,
    /// `name = value [lo, hi]` per fitted parameter.
    pub params: Vec<String>,
}

fn pct(v: f64) -> String {
    format!("{:.2}", 100.0 * v)
}

fn chi(v: Option<f64>) -> String {
    v.map_or("-".into(), |c| fmt_sig(c, 3))
}

/// Characters LaTeX treats as commands, escaped.
fn tex(s: &str) -> String {
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
            'ψ' => out.push_str("$\\psi$"),
            'λ' => out.push_str("$\\lambda$"),
            'Ω' => out.push_str("$\\Omega$"),
            'ω' => out.push_str("$\\omega$"),
            '·' => out.push_str("$\\cdot$"),
            _ => out.push(c),
        }
    }
    out
}

/// The table in LaTeX (needs `\usepackage{booktabs}`).
pub fn latex(rows: &[PaperRow]) -> String {
    let mut s = String::from(
        "\\begin{tabular}{rlrrrl}\n\\toprule\nStep & Effect & MARE (\\%) & CV MARE (\\%) & $\\chi^2/\\nu$ & Parameters (95\\,\\% interval) \\\\\n\\midrule\n",
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
        "| Step | Effect | MARE (%) | CV MARE (%) | χ²/ν | Parameters (95 % interval) |\n|---:|---|---:|---:|---:|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            r.step,
            r.effect.replace('|', "\\|"),
            pct(r.mare),
            pct(r.cv_mare),
            chi(r.chi2_reduced),
            r.params.join("; ").replace('|', "\\|")
        ));
    }
    s
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
