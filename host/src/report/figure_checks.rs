//! Every figure of the report page, on the built-in data and on a lab's
//! four groups, clear and readable.

use crate::chart::tests::{is_integer_with_point_zero, texts};

#[path = "../../tests/fixtures/four_groups.rs"]
mod four_groups;
use crate::chart::{legend_clear, text_clear};

/// Every figure (SVG, without its closing tag) of the report page of
/// `model` on `data`.
fn figures(model: &crate::model::Model, data: &crate::data::Dataset) -> Vec<String> {
    let dir = tempfile::tempdir().unwrap();
    let path = crate::report::write_report(
        dir.path(),
        &crate::workbench::path::user_path(model, 0, data).unwrap(),
        data,
        None,
        &|_| Ok(()),
        &crate::provenance::Inputs::new(),
    )
    .unwrap();
    let page = std::fs::read_to_string(path).unwrap();
    page.split("<svg ")
        .skip(1)
        .map(|s| format!("<svg {}", &s[..s.find("</svg>").unwrap()]))
        .collect()
}

/// Every figure of the report page on the built-in data.
#[test]
fn every_figure_of_the_report_page_is_clear_and_readable() {
    let svgs = figures(&crate::model::Model::base(), &crate::data::paper());
    assert!(svgs.len() >= 8, "{} figures", svgs.len());
    let mut residual_titles = Vec::new();
    for svg in &svgs {
        legend_clear(svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
        text_clear(svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
        let t = texts(svg);
        for s in &t {
            assert!(!is_integer_with_point_zero(s), "tick label {s}");
            for code in ["Omega_b", "N_lambda", "pitch_angle_deg", "_deg"] {
                assert!(!s.contains(code), "code identifier in '{s}'");
            }
        }
        if let Some(title) = t.iter().find(|s| s.contains("error against")) {
            residual_titles.push(title.clone());
        }
    }
    assert!(
        residual_titles.iter().any(|t| t.starts_with("U ")),
        "{residual_titles:?}"
    );
    assert!(
        residual_titles.iter().any(|t| t.starts_with("Ωb ")),
        "{residual_titles:?}"
    );
    // Parity plots: case labels and a legend naming the bars.
    let parity: Vec<&String> = svgs
        .iter()
        .filter(|s| texts(s).iter().any(|t| t.starts_with("Parity")))
        .collect();
    // the paper's model's (where it fails) and the model asked for's (step by step)
    assert_eq!(parity.len(), 4);
    for p in parity {
        let t = texts(p);
        assert!(
            t.contains(&"tail-1".to_string()) && t.contains(&"y = x".to_string()),
            "{t:?}"
        );
        assert!(t.contains(&"measured 95 % CI".to_string()), "{t:?}");
    }
}

/// A lab's four groups (tail-5 with a smaller amplitude, tail-6 in a
/// narrower tube) and body-confinement: the case labels of its residual
/// plots crowd where tail-5 and tail-6 fall together, and still no two run
/// into each other (the labels' boxes are the checker's font model).
#[test]
fn a_lab_s_crowded_case_labels_stay_clear() {
    let text = four_groups::four_groups_two_tubes(crate::data::PAPER_TOML);
    let data = crate::data::parse_str(&text, "lab.toml").unwrap();
    let model =
        crate::model::Model::base().with_effect(crate::effects::EffectInstance::default_of(
            crate::effects::by_name("body-confinement").unwrap(),
        ));
    let svgs = figures(&model, &data);
    assert!(svgs.iter().filter(|s| s.contains("tail-6")).count() >= 4);
    for svg in &svgs {
        text_clear(svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
    }
}
