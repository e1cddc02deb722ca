//! The report as a story, in the order a reader needs it: the robot, the
//! data and the question; the paper's model and its Fig. 4; where it
//! fails; the path `diagnose` takes; the best model without a fitted
//! parameter; what remains. Every number on the page is computed here, at
//! run time, from the data and the models.

use super::html::{document, escape};
use crate::data::Dataset;
use crate::model::Model;
use crate::workbench::audit::Audit;
use crate::workbench::diagnose::Diagnosis;
use crate::workbench::path::Path;

/// The zero-parameter model of the physics section, or why it was left out.
pub enum ZeroParam<'a> {
    Model { name: String, model: &'a Model },
    Skipped(String),
}

/// What the page is written from.
pub struct StoryInput<'a> {
    pub data: &'a Dataset,
    /// The model `diagnose` starts from (the command's model options).
    pub start: &'a Model,
    /// That model taken apart into its cumulative steps, computed once by
    /// the workbench: the section on the model asked for renders it.
    pub path: &'a Path,
    /// The command that writes the page (`report`, `compare`).
    pub command: &'a str,
    pub diagnosis: Option<&'a Diagnosis>,
    pub zero_param: ZeroParam<'a>,
    pub audit: Option<&'a Audit>,
}

/// Section ids and titles, for the contents and the headings: named by
/// what they hold, never numbered (the contents list numbers them).
pub const SECTIONS: [(&str, &str); 7] = [
    ("question", "The robot, the data and the question"),
    ("paper", "The paper's model and its Fig. 4"),
    ("fails", "Where the paper's model fails"),
    ("yours", "The model asked for, step by step"),
    ("path", "The path diagnose takes"),
    ("physics", "The best model without a fitted parameter"),
    ("remains", "What remains and what is suspected"),
];

/// Whether `data` is the paper's own dataset (the page's wording then
/// speaks of "its measurements").
fn is_paper_data(data: &Dataset) -> bool {
    let paper = crate::data::paper();
    data.name == paper.name && data.cases.len() == paper.cases.len()
}

/// The page's title: the paper's data, or the dataset's own name.
pub fn title(data: &Dataset) -> String {
    if is_paper_data(data) {
        "swimbot: the paper's model against its measurements, and what is missing".into()
    } else {
        format!(
            "swimbot: models against the measurements of “{}”",
            data.name
        )
    }
}

pub fn heading(i: usize) -> String {
    let (id, title) = SECTIONS[i];
    format!("<h2 id=\"{id}\">{}</h2>", escape(title))
}

/// The whole page.
pub fn page(s: &StoryInput) -> Result<String, crate::model::ModelError> {
    let paper = super::paper::PaperModels::new(s.data)?;
    let mut b = String::new();
    b.push_str(&format!(
        "<h1>{}</h1>\
         <p class=\"note\">data: <code>{}</code> ({}); model asked for: <code>{}</code>; \
         written by <code>swimbot {}</code> {}.</p>",
        escape(&title(s.data)),
        escape(&s.data.name),
        escape(&s.data.source),
        escape(&s.path.last().spec),
        escape(s.command),
        env!("CARGO_PKG_VERSION")
    ));
    b.push_str("<ol class=\"toc\">");
    for (id, title) in SECTIONS {
        b.push_str(&format!("<li><a href=\"#{id}\">{}</a></li>", escape(title)));
    }
    b.push_str("</ol>");
    b.push_str(&heading(0));
    b.push_str(&super::intro::section(s.data));
    b.push_str(&heading(1));
    b.push_str(&paper.section(s.data));
    b.push_str(&heading(2));
    b.push_str(&super::fails::section(s.data, &paper)?);
    b.push_str(&heading(3));
    b.push_str(&super::yours::section(s.data, s.path));
    b.push_str(&heading(4));
    b.push_str(&super::path::section(s.start, s.data, s.diagnosis));
    b.push_str(&heading(5));
    b.push_str(&super::physics::section(
        s.data,
        &s.zero_param,
        &paper,
        s.diagnosis,
        s.audit,
    )?);
    b.push_str(&heading(6));
    b.push_str(&super::remains::section(s.data, s.diagnosis, s.audit));
    Ok(document(&title(s.data), &b))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::{by_name, EffectInstance};
    use crate::workbench::compare::compare;

    /// Section 5 through the same code path as `--preset physics`, with a
    /// zero-parameter model cheap enough for the test profile (the tube
    /// solves of `physics` take minutes there on a cold cache).
    #[test]
    fn the_zero_parameter_section_renders_an_injected_model() {
        let data = crate::data::paper();
        let start = Model::base();
        let cheap = Model::base().with_effect(EffectInstance::default_of(
            by_name("body-confinement").expect("a catalogue effect"),
        ));
        let path = crate::workbench::path::user_path(&start, 0, &data).unwrap();
        let html = page(&StoryInput {
            data: &data,
            start: &start,
            path: &path,
            command: "report",
            diagnosis: None,
            zero_param: ZeroParam::Model {
                name: "cheap zero-parameter model".into(),
                model: &cheap,
            },
            audit: None,
        })
        .unwrap();
        let from = html.find("id=\"physics\"").unwrap();
        let to = html.find("id=\"remains\"").unwrap();
        let section = &html[from..to];
        assert!(section.contains("cheap zero-parameter model"));
        let fig = &section[section.find("<figure id=\"fig4-physics\"").unwrap()..];
        let fig = &fig[..fig.find("</figure>").unwrap()];
        // six panels and the figure's one legend
        assert_eq!(fig.matches("<svg").count(), 7);
        assert_eq!(fig.matches("class=\"fig-legend\"").count(), 1);
        // its errors as `compare` computes them, beside the paper's
        let mare = compare(&cheap, &data, 0).unwrap().summary.mare;
        assert!(
            section.contains(&super::super::wording::pct(mare)),
            "{section}"
        );
        // its coverage with its input bands, worded as `compare` words it,
        // and a line for every quantity outside
        let banded = crate::workbench::compare::compare_with_input_bands(&cheap, &data).unwrap();
        let cov = banded
            .coverage
            .expect("the paper data state input uncertainties");
        assert!(section.contains(&cov.describe()), "{section}");
        assert_eq!(
            section.matches("combined standard deviations);").count(),
            cov.outside.len()
        );
        let paper = compare(&crate::model::preset("paper").unwrap(), &data, 0).unwrap();
        assert!(section.contains(&super::super::wording::pct(paper.summary.mare)));
    }
}
