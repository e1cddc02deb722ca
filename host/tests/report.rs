//! `swimbot report`: the story page from the real binary (the fast variant
//! without the zero-parameter model, whose first run solves every tail in
//! the tube; its section is tested in `report::story` with a cheaper
//! zero-parameter model through the same code path).

use crate::common;

use crate::common::run_in;
use common::stderr;

/// The HTML of the `<figure id="...">` element.
fn figure<'a>(page: &'a str, id: &str) -> &'a str {
    let start = page
        .find(&format!("<figure id=\"{id}\""))
        .unwrap_or_else(|| panic!("no figure {id}"));
    let end = page[start..].find("</figure>").expect("closed figure") + start;
    &page[start..end]
}

#[test]
fn the_default_report_tells_the_story_with_six_fig4_panels_and_the_noise_floor() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_in(dir.path(), &["report", "--no-physics"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(dir.path().join("swimbot-out/report/index.html"))
        .expect("the default output is swimbot-out/report/index.html");
    // the sections in the story's order
    let order = [
        "id=\"question\"",
        "id=\"paper\"",
        "id=\"fails\"",
        "id=\"path\"",
        "id=\"physics\"",
        "id=\"remains\"",
    ];
    let at: Vec<usize> = order
        .iter()
        .map(|s| page.find(s).unwrap_or_else(|| panic!("{s}")))
        .collect();
    assert!(
        at.windows(2).all(|w| w[0] < w[1]),
        "sections out of order: {at:?}"
    );
    // Fig. 4: six panels (a)-(f), both coefficient sets
    let fig4 = figure(&page, "fig4");
    // six panels and the figure's one legend above them
    assert_eq!(fig4.matches("<svg").count(), 7, "six panels and a legend");
    for panel in ["(a)", "(b)", "(c)", "(d)", "(e)", "(f)"] {
        assert!(fig4.contains(panel), "panel {panel}");
    }
    assert!(fig4.contains("Gray-Hancock") && fig4.contains("Lighthill"));
    // the two models' markers side by side at each case, as the caption says
    assert!(fig4.contains("side by side"), "the caption names the shift");
    // every figure as a reader sees it: no text runs into another (tick
    // labels, subscripted axis titles, labels, legends), no legend on data
    let figures = dir.path().join("swimbot-out/report/figures");
    for e in std::fs::read_dir(&figures).unwrap() {
        let path = e.unwrap().path();
        let svg = std::fs::read_to_string(&path).unwrap();
        swimbot::chart::text_clear(&svg)
            .and_then(|()| swimbot::chart::legend_clear(&svg))
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
    // the path with the noise floor drawn as a line
    let path = figure(&page, "path-chart");
    assert!(path.contains("class=\"noise-floor\""), "noise-floor line");
    assert!(path.contains("noise floor"), "labelled");
    // no raw reduced chi-square like 8228626.1208 anywhere on the page
    assert!(!page.contains("8228626"), "a chi-square printed unrounded");
    assert!(!page.contains("chart failed"));
    assert!(page.contains("Verdict: "), "the verdict is stated");
    // skipped physics is said, not silently missing
    assert!(page.contains("--no-physics"));
}

#[test]
fn from_the_paper_model_a_rise_is_drawn_and_worded_as_a_rise() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_in(
        dir.path(),
        &["report", "--no-physics", "--preset", "paper", "-o", "r"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let page = std::fs::read_to_string(dir.path().join("r/index.html")).unwrap();
    let spans = |class: &str| -> Vec<String> {
        page.split(&format!("<span class=\"{class}\">"))
            .skip(1)
            .map(|s| s[..s.find("</span>").unwrap()].to_string())
            .collect()
    };
    let rises = spans("rise");
    assert!(
        !rises.is_empty(),
        "the paper's model's path has a rising step"
    );
    assert!(
        rises.iter().all(|s| s.starts_with("rises from")),
        "{rises:?}"
    );
    assert!(spans("fall").iter().all(|s| s.starts_with("falls from")));
    // and the chart marks it in red with the word
    let path = figure(&page, "path-chart");
    assert!(
        path.contains(">rises: "),
        "a rising step labelled in the chart"
    );
}

#[test]
fn a_bad_dataset_exits_2_naming_the_file_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.toml");
    let text =
        swimbot::data::PAPER_TOML.replacen("wavelength_mm = 15.5", "wavelength_mm = -15.5", 1);
    std::fs::write(&bad, text).unwrap();
    let o = run_in(
        dir.path(),
        &[
            "report",
            "--no-physics",
            "--data",
            bad.to_str().unwrap(),
            "-o",
            "r",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("bad.toml") && err.contains("tail-1"), "{err}");
    assert!(!dir.path().join("r/index.html").exists());
}
