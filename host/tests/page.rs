//! The loop on the page, through the real binary: the model a user builds
//! reaches every figure and table of the page, one statistic reads the
//! same in every command, no command overwrites another's page, and the
//! bundle beside the page holds every figure and table.

use crate::common;

use crate::common::run_in;
use common::{stderr, stdout};

use std::process::Output;

fn ok(o: &Output) -> String {
    assert!(o.status.success(), "{}", stderr(o));
    stdout(o)
}

fn json(o: &Output) -> serde_json::Value {
    serde_json::from_str(&ok(o)).expect("JSON on stdout")
}

/// The HTML of the `<figure id="...">` element.
fn figure<'a>(page: &'a str, id: &str) -> &'a str {
    let start = page
        .find(&format!("<figure id=\"{id}\""))
        .unwrap_or_else(|| panic!("no figure {id}"));
    let end = page[start..].find("</figure>").expect("closed figure") + start;
    &page[start..end]
}

/// The page's section `id` (to the next heading).
fn section<'a>(page: &'a str, id: &str) -> &'a str {
    let start = page.find(&format!("<h2 id=\"{id}\"")).expect("the section");
    let end = page[start + 4..]
        .find("<h2 ")
        .map_or(page.len(), |e| start + 4 + e);
    &page[start..end]
}

/// The page's number policy for a MARE (`21.1 %`).
fn pct(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

#[test]
fn diagnose_then_the_written_effect_reaches_every_figure_and_table_of_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // a lab's data with a hidden wall effect on the tail the catalogue lacks
    std::fs::write(
        d.join("hidden.toml"),
        "[[effect]]\nname = \"hidden-wall\"\nstatement = \"tail drag grows near the wall\"\n\
         reference = \"a test's hidden truth\"\n[effect.places]\n\
         \"tail.c_n\" = \"1 + 5 * tail_gap_ratio^1.3\"\n",
    )
    .unwrap();
    ok(&run_in(
        d,
        &[
            "synth",
            "--effect-file",
            "hidden.toml",
            "--truth",
            "base + hidden-wall",
            "--seed",
            "11",
            "-o",
            "lab.toml",
        ],
    ));
    let o = run_in(
        d,
        &[
            "diagnose",
            "--data",
            "lab.toml",
            "--write-effect",
            "found.toml",
        ],
    );
    ok(&o);
    let text = std::fs::read_to_string(d.join("found.toml")).expect("a law was written");
    let name = text
        .lines()
        .find_map(|l| l.strip_prefix("name = \""))
        .and_then(|l| l.strip_suffix('"'))
        .expect("the written effect's name")
        .to_string();
    let with = [
        "report",
        "--no-physics",
        "--data",
        "lab.toml",
        "--effect-file",
        "found.toml",
        "--effect",
        &name,
        "-o",
        "with",
    ];
    ok(&run_in(d, &with));
    ok(&run_in(
        d,
        &[
            "report",
            "--no-physics",
            "--data",
            "lab.toml",
            "-o",
            "without",
        ],
    ));
    let page = std::fs::read_to_string(d.join("with/index.html")).unwrap();
    let plain = std::fs::read_to_string(d.join("without/index.html")).unwrap();
    let yours = section(&page, "yours");
    let label = format!("+ {name}");
    // in the Fig. 4 analogue, the parity and residual plots, and the tables
    for fig in [
        "fig4-yours",
        "yours-parity",
        "yours-residuals",
        "yours-path",
    ] {
        assert!(figure(&page, fig).contains(&label), "{fig} names {label}");
    }
    // its MARE after the step, as compare computes it
    let cmp = json(&run_in(
        d,
        &[
            "compare",
            "--data",
            "lab.toml",
            "--effect-file",
            "found.toml",
            "--effect",
            &name,
            "--format",
            "json",
            "--no-report",
        ],
    ));
    let mare = cmp["summary"]["mare"].as_f64().unwrap();
    let row = yours
        .split("<tr>")
        .find(|r| r.contains(&format!("<td class=\"l\">{label}</td>")))
        .expect("the step's row");
    assert!(row.contains(&pct(mare)), "{row}");
    // before -> after, and a fall
    assert!(row.contains("<span class=\"fall\">falls from"), "{row}");
    assert_ne!(page, plain, "the effect changes the page");
    assert!(!section(&plain, "yours").contains(&label));
    // the title is the lab's, not the paper's
    assert!(!page.contains("<h1>swimbot: the paper's model against its measurements"));
}

#[test]
fn a_second_and_third_effect_show_the_whole_cumulative_sequence() {
    let dir = tempfile::tempdir().unwrap();
    ok(&run_in(
        dir.path(),
        &[
            "compare",
            "--effect",
            "backflow-observed",
            "--effect",
            "body-correction:translation=16,rotation=1.4",
            "--effect",
            "body-confinement",
        ],
    ));
    let page = std::fs::read_to_string(dir.path().join("swimbot-out/compare/index.html"))
        .expect("compare's own folder");
    let yours = section(&page, "yours");
    let steps = &yours[yours.find("<table>").expect("the steps' table")..];
    let at: Vec<usize> = [
        ">start<",
        ">+ backflow-observed<",
        ">+ body-correction<",
        ">+ body-confinement<",
    ]
    .iter()
    .map(|s| steps.find(s).unwrap_or_else(|| panic!("{s}")))
    .collect();
    assert!(at.windows(2).all(|w| w[0] < w[1]), "in order: {at:?}");
    assert!(yours.contains("on top of the step before"));
    // the steps are cumulative: the third model holds the first two
    assert!(yours.contains(
        "gray-hancock + backflow-observed + body-correction:translation=16,rotation=1.4 + \
         body-confinement"
    ));
    let fig4 = figure(&page, "fig4-yours");
    for step in [
        "start",
        "+ backflow-observed",
        "+ body-correction",
        "+ body-confinement",
    ] {
        assert!(fig4.contains(step), "Fig. 4 draws {step}");
    }
}

#[test]
fn report_then_compare_leaves_the_story_page_whole() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ok(&run_in(d, &["report", "--no-physics"]));
    let story = d.join("swimbot-out/report/index.html");
    let before = std::fs::read(&story).unwrap();
    let o = run_in(d, &["compare"]);
    assert!(
        ok(&o).contains("swimbot-out/compare/index.html"),
        "says where"
    );
    assert_eq!(std::fs::read(&story).unwrap(), before, "the story is whole");
    // pointed at the story's folder, compare refuses and writes nothing
    let o = run_in(d, &["compare", "-o", "swimbot-out/report"]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("swimbot report"), "{}", stderr(&o));
    assert_eq!(std::fs::read(&story).unwrap(), before);
}

#[test]
fn one_model_reads_the_same_statistics_in_diagnose_compare_fit_and_report() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // fit the paper's two body factors, then hand the fitted model to the others
    let fit = json(&run_in(
        d,
        &["fit", "--effect", "body-correction", "--format", "json"],
    ));
    let est = fit["fit"]["estimates"].as_array().unwrap();
    let value = |n: &str| {
        est.iter()
            .find(|e| e["name"] == n)
            .and_then(|e| e["value"].as_f64())
            .unwrap()
    };
    let spec = format!(
        "body-correction:translation={},rotation={}",
        value("translation"),
        value("rotation")
    );
    let from_fit = &fit["comparison"]["summary"];
    let compare = json(&run_in(
        d,
        &[
            "compare",
            "--effect",
            &spec,
            "--format",
            "json",
            "--no-report",
        ],
    ));
    let diagnose = json(&run_in(
        d,
        &[
            "diagnose",
            "--effect",
            &spec,
            "--no-discovery",
            "--format",
            "json",
        ],
    ));
    let s = &compare["summary"];
    let close = |a: &serde_json::Value, b: &serde_json::Value| {
        let (a, b) = (a.as_f64().unwrap(), b.as_f64().unwrap());
        (a - b).abs() <= 1e-9 * b.abs()
    };
    for key in ["mare", "chi2_reduced", "max_abs_rel_err"] {
        assert!(
            close(&from_fit[key], &s[key]),
            "fit and compare differ on {key}"
        );
        assert!(
            close(&diagnose["baseline"][key], &s[key]),
            "diagnose and compare differ on {key}"
        );
    }
    assert_eq!(from_fit["free_params"], s["free_params"]);
    assert_eq!(s["free_params"], 2, "the fitted factors are counted");
    // the page's table (its JSON in the bundle) prints the same numbers
    ok(&run_in(
        d,
        &["report", "--no-physics", "--effect", &spec, "-o", "r"],
    ));
    let rows: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("r/tables/yours-1.json")).unwrap())
            .unwrap();
    let last = rows.as_array().unwrap().last().unwrap().clone();
    assert_eq!(last["step"], "+ body-correction");
    assert_eq!(last["MARE"], pct(s["mare"].as_f64().unwrap()));
    let chi = swimbot::format::fmt_sig(s["chi2_reduced"].as_f64().unwrap(), 3);
    assert_eq!(last["reduced χ²"].as_f64(), chi.parse::<f64>().ok());
    assert_eq!(last["degrees of freedom"], "12 − 2 = 10");
}

#[test]
fn the_bundle_holds_every_figure_and_table_named_in_the_manifest() {
    let dir = tempfile::tempdir().unwrap();
    ok(&run_in(dir.path(), &["report", "--no-physics", "-o", "r"]));
    let r = dir.path().join("r");
    let page = std::fs::read_to_string(r.join("index.html")).unwrap();
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(r.join("manifest.json")).unwrap()).unwrap();
    assert_eq!(manifest["command"], "report");
    let files = manifest["files"].as_array().unwrap();
    let of = |kind: &str| files.iter().filter(|f| f["kind"] == kind).count();
    assert_eq!(
        of("figure"),
        page.matches("<svg ").count(),
        "one SVG per panel"
    );
    assert_eq!(
        of("table-csv"),
        page.matches("<table>").count(),
        "one CSV per table"
    );
    assert_eq!(of("table-json"), of("table-csv"));
    for f in files {
        let path = r.join(f["file"].as_str().unwrap());
        let bytes = std::fs::read(&path).unwrap_or_else(|_| panic!("{}", path.display()));
        assert!(!f["caption"].as_str().unwrap().is_empty());
        if f["kind"] == "figure" {
            let svg = String::from_utf8(bytes).unwrap();
            assert!(svg.starts_with("<svg xmlns=\"http://www.w3.org/2000/svg\""));
            assert!(svg.contains("viewBox=\"") && svg.contains("<text"));
            assert!(svg.contains("sans-serif"), "a font stack that falls back");
        }
    }
}

#[test]
fn a_lab_s_four_groups_and_second_tube_shape_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let text = crate::fixtures::four_groups::four_groups_two_tubes(swimbot::data::PAPER_TOML);
    std::fs::write(
        d.join("lab.toml"),
        text.replacen("name = ", "name = \"my-lab\"\n# ", 1),
    )
    .unwrap();
    ok(&run_in(
        d,
        &[
            "compare",
            "--data",
            "lab.toml",
            "--effect",
            "body-confinement",
            "-o",
            "c",
        ],
    ));
    let page = std::fs::read_to_string(d.join("c/index.html")).unwrap();
    // one row of U panels and one of Omega_b panels, four columns each
    for fig in ["fig4", "fig4-yours"] {
        let f = figure(&page, fig);
        assert!(f.contains("--cols:4"), "{fig}: four columns");
        // eight panels and one legend above them, so that no panel is
        // widened by it (panel (a) was, and the page's grid then showed it
        // at about 64 %): every panel as wide as the others
        assert_eq!(f.matches("<svg").count(), 9, "{fig}");
        let grid = &f[f.find("class=\"grid\"").unwrap()..];
        let widths: Vec<&str> = grid
            .split("<svg ")
            .skip(1)
            .map(|s| {
                let w = &s[s.find(" width=\"").unwrap() + 8..];
                &w[..w.find('"').unwrap()]
            })
            .collect();
        assert_eq!(widths.len(), 8, "{fig}");
        assert!(widths.iter().all(|w| *w == widths[0]), "{fig}: {widths:?}");
    }
    // narrower panels, yet no text of Fig. 4 runs into another and its
    // legend covers no data (Fig. 4 only: in this lab's residual plot the
    // labels of tail-5 and tail-6 still overlap, a known open glitch)
    for e in std::fs::read_dir(d.join("c/figures")).unwrap() {
        let path = e.unwrap().path();
        if !path.to_string_lossy().contains("fig4") {
            continue;
        }
        let svg = std::fs::read_to_string(&path).unwrap();
        swimbot::chart::text_clear(&svg)
            .and_then(|()| swimbot::chart::legend_clear(&svg))
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
    // the lab's title and each case's tube
    assert!(page.contains("<h1>swimbot: models against the measurements of “my-lab”</h1>"));
    let question = section(&page, "question");
    assert!(question.contains("28.0-35.0 mm across"), "the tubes' range");
    assert!(
        question.contains("D<sub>ch</sub> (mm)"),
        "a per-case tube column"
    );
}

/// The coverage (how many of the 12 quantities lie within 2 combined
/// standard deviations) reads the same in `compare --input-uncertainty`'s
/// table and JSON and on the page `report` writes for the same model.
#[test]
fn coverage_reads_the_same_in_compare_and_on_the_page() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let args = [
        "compare",
        "--no-report",
        "--preset",
        "paper",
        "--input-uncertainty",
    ];
    let table = ok(&run_in(d, &args));
    let line = table
        .lines()
        .find_map(|l| l.strip_prefix("coverage: "))
        .unwrap_or_else(|| panic!("no coverage line in {table}"));
    let statistic = line.split(';').next().unwrap();
    let v = json(&run_in(d, &[&args[..], &["--format", "json"]].concat()));
    let cov = &v["coverage"];
    let (within, of) = (cov["within"].as_u64().unwrap(), cov["of"].as_u64().unwrap());
    assert_eq!(of, 12);
    assert_eq!(
        statistic,
        format!("{within} of {of} quantities within 2 combined standard deviations")
    );
    assert_eq!(cov["outside"].as_array().unwrap().len() as u64, of - within);
    ok(&run_in(
        d,
        &["report", "--no-physics", "--preset", "paper", "-o", "r"],
    ));
    let page = std::fs::read_to_string(d.join("r/index.html")).unwrap();
    let yours = section(&page, "yours");
    assert!(yours.contains(&format!("<b>{statistic}</b>")), "{yours}");
}
