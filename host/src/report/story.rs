//! The report as a story, in the order a reader needs it: the robot, the
//! data and the question; the paper's model and its Fig. 4; where it
//! fails; the path `diagnose` takes; the best model without a fitted
//! parameter; what remains. Every number on the page is computed here, at
//! run time, from the data and the models.

use super::html::{document, html};
use super::page::{Page, Part};
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

pub fn heading(i: usize) -> Part {
    let (id, title) = SECTIONS[i];
    Part::heading(id, html! { h2 id=(id) { (title) } })
}

/// The whole page, with its artefacts.
pub fn page(s: &StoryInput) -> Result<Page, crate::model::ModelError> {
    let paper = super::paper::PaperModels::new(s.data)?;
    let fails = super::fails::section(s.data, &paper)?;
    let physics = super::physics::section(s.data, &s.zero_param, &paper, s.diagnosis, s.audit)?;
    let mut body = Part::from(html! {
        h1 { (title(s.data)) }
        p.note {
            "data: " code { (s.data.name) } " (" (s.data.source) "); model asked for: "
            code { (s.path.last().spec) } "; written by " code { "swimbot " (s.command) }
            " " (env!("CARGO_PKG_VERSION")) "."
        }
        ol.toc {
            @for (id, title) in SECTIONS {
                li { a href={ "#" (id) } { (title) } }
            }
        }
    });
    body.push(heading(0));
    body.push(super::intro::section(s.data));
    body.push(heading(1));
    body.push(paper.section(s.data));
    body.push(heading(2));
    body.push(fails);
    body.push(heading(3));
    body.push(super::yours::section(s.data, s.path));
    body.push(heading(4));
    body.push(super::path::section(s.start, s.data, s.diagnosis));
    body.push(heading(5));
    body.push(physics);
    body.push(heading(6));
    body.push(super::remains::section(s.data, s.diagnosis, s.audit));
    Ok(document(&title(s.data), body))
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
        .unwrap()
        .html;
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
