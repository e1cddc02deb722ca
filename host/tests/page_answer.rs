//! The study's page through the real binary: it opens with the answer,
//! whose every number is the study file's or the last diagnosis's
//! headline (the one `diagnose --format json` prints); its figures' text
//! is at least 11 px in a 1400 px window and its case labels stay apart at
//! 24 cases; its bundle carries the paper's table and laws that `steps
//! --format latex|markdown` prints.

use crate::common::{run_in, stderr, stdout};
use std::path::Path;
use swimbot::format::fmt_sig;
use swimbot::format::rounding::value_pm;

fn run(dir: &Path, args: &[&str]) -> String {
    let o = run_in(dir, args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    stdout(&o)
}

fn json(dir: &Path, args: &[&str]) -> serde_json::Value {
    serde_json::from_str(&run(dir, args)).expect("JSON on stdout")
}

/// The README's loop on the paper's data: two steps and the page.
fn paper_study(dir: &Path) {
    let paper = concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv");
    run(dir, &["init", "--data", paper]);
    run(dir, &["add", "body-correction"]);
    run(dir, &["diagnose", "--write-effect", "found.toml"]);
    run(dir, &["add", "found.toml"]);
    run(dir, &["report"]);
}

/// A planted set of 24 cases, built up to the noise floor.
fn planted_24(dir: &Path) {
    let design = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/fixtures/twenty-four-tails.csv"
    );
    run(
        dir,
        &[
            "synth", "--data", design, "--nominal-inputs", "--seed", "1", "--truth",
            "base + backflow + body-correction:translation=16,rotation=1.4 + buoyancy:net_force_mn=0.3",
            "-o", "planted.toml",
        ],
    );
    run(dir, &["init", "--data", "planted.toml"]);
    run(dir, &["add", "body-correction"]);
    run(dir, &["add", "backflow"]);
    run(dir, &["report"]);
}

fn page(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("swimbot-out/report/index.html")).unwrap()
}

/// The page's answer section.
fn answer(page: &str) -> &str {
    let start = page.find("<section class=\"answer\">").expect("the answer");
    let end = page[start..].find("</section>").unwrap() + start;
    &page[start..end]
}

fn pc(v: &serde_json::Value) -> String {
    format!("{:.2}\u{a0}%", 100.0 * v.as_f64().unwrap())
}

fn chi(v: &serde_json::Value) -> String {
    v.as_f64().map_or("-".into(), |c| fmt_sig(c, 3))
}

#[test]
fn the_study_page_opens_with_the_answer_the_json_holds() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    paper_study(d);
    let page = page(d);
    let a = answer(&page);
    // The answer comes before every other section.
    assert!(page.find("<section class=\"answer\">") < page.find("<h2 id=\"first-diagnosis\""));
    let study = json(d, &["steps", "--format", "json"]);
    let steps = study["step"].as_array().unwrap();
    // The error falling, from the study file's statistics.
    let all: Vec<&serde_json::Value> = std::iter::once(&study["start"])
        .chain(steps.iter().map(|s| &s["after"]))
        .collect();
    let mare: Vec<String> = all.iter().map(|s| pc(&s["stats"]["mare"])).collect();
    let chi2: Vec<String> = all
        .iter()
        .map(|s| chi(&s["stats"]["chi2_reduced"]))
        .collect();
    assert!(a.contains(&mare.join(" → ")), "{mare:?}\n{a}");
    assert!(a.contains(&chi2.join(" → ")), "{chi2:?}\n{a}");
    // Each step's fitted values as value ± u from the file's numbers.
    let mut seen = 0;
    for st in steps {
        for p in st["param"].as_array().unwrap() {
            if p["status"] != "fitted" {
                continue;
            }
            let u = p["standard_uncertainty"].as_f64();
            assert!(u.is_some(), "a fitted parameter without u: {p}");
            let printed = value_pm(p["value"].as_f64().unwrap(), u);
            assert!(a.contains(&printed), "{printed}\n{a}");
            seen += 1;
        }
    }
    assert!(seen >= 4, "{seen} parameters");
    // What is still missing and how sure: the last diagnosis's headline,
    // the same value `diagnose --format json` prints now.
    let last = &steps.last().unwrap()["diagnosis_after"];
    let stored = &last["headline"];
    let now = json(d, &["diagnose", "--format", "json"])["headline"].clone();
    assert_eq!(stored["kind"], now["kind"]);
    assert_eq!(
        stored["steps"].as_array().unwrap().len(),
        now["steps"].as_array().unwrap().len()
    );
    let floor = stored["noise_floor_chi2_reduced"].clone();
    assert_eq!(chi(&floor), chi(&now["noise_floor_chi2_reduced"]));
    assert!(
        a.contains(&format!("<span class=\"floor\">{}</span>", chi(&floor))),
        "{a}"
    );
    for (i, s) in stored["steps"].as_array().unwrap().iter().enumerate() {
        let x = s["explains"].as_f64().unwrap();
        assert_eq!(
            format!("{x:.4}"),
            format!("{:.4}", now["steps"][i]["explains"].as_f64().unwrap())
        );
        // The proposal the study keeps says the headline's share.
        assert_eq!(last["proposal"][i]["explains"].as_f64(), Some(x));
        assert!(
            a.contains(&format!("<span class=\"explains\">{:.0}</span>", 100.0 * x)),
            "{a}"
        );
    }
    let rivals = stored["rivals"].as_array().unwrap();
    match rivals.first() {
        Some(r) => assert!(a.contains(&format!(
            "<span class=\"weight\">{:.2}</span>",
            r["akaike_weight"].as_f64().unwrap()
        ))),
        None => assert!(a.contains("no rival set within the margin"), "{a}"),
    }
    let next = if rivals.len() >= 2 {
        "swimbot plan".to_string()
    } else {
        format!(
            "swimbot add found.toml#{}",
            last["proposal"][0]["name"].as_str().unwrap()
        )
    };
    assert!(
        a.contains(&format!("<code class=\"next\">{next}</code>")),
        "{next}\n{a}"
    );
}

#[test]
fn the_paper_s_first_diagnosis_proposes_body_correction_with_the_headline_s_share() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let paper = concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv");
    run(d, &["init", "--data", paper]);
    run(d, &["report"]);
    let study = json(d, &["steps", "--format", "json"]);
    let first = &study["first_diagnosis"];
    let names: Vec<&str> = first["proposal"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names[0], "body-correction", "{names:?}");
    let h = json(d, &["diagnose", "--format", "json"])["headline"].clone();
    let page = page(d);
    for (p, s) in first["proposal"]
        .as_array()
        .unwrap()
        .iter()
        .zip(h["steps"].as_array().unwrap())
    {
        let (x, y) = (
            p["explains"].as_f64().unwrap(),
            s["explains"].as_f64().unwrap(),
        );
        assert!((x - y).abs() < 1e-9, "{x} against {y}");
        // "It proposes" on the page says the same share.
        let said = format!("removes {:.0} % of the excess chi-square", 100.0 * x);
        assert!(page.contains(&said), "{said}");
    }
}

/// The `<svg>` elements of `html`, in order.
fn svgs(html: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let mut rest = html;
    while let Some(i) = rest.find("<svg") {
        let j = rest[i..].find("</svg>").unwrap() + i + 6;
        out.push(&rest[i..j]);
        rest = &rest[j..];
    }
    out
}

/// Every SVG of `page` with the width it is shown at in a 1400 px window:
/// the page's content is 1240 px wide (`report/html.rs`); a figure's grid
/// of `--cols` columns, 16 px apart, sizes each column as CSS grid does
/// `minmax(0, max-content)` tracks (the free width shared equally, no
/// column wider than its widest panel), and a panel is shown at its own
/// width or its column's, the smaller. Headless Chromium shows the same
/// widths (402.7 px for three 560 px panels).
fn shown(page: &str) -> Vec<(&str, f64)> {
    const CONTENT_PX: f64 = 1240.0;
    const GAP_PX: f64 = 16.0;
    let width = |svg: &str| -> f64 {
        let head = &svg[..svg.find('>').unwrap()];
        let i = head.find(" width=\"").unwrap() + 8;
        head[i..i + head[i..].find('"').unwrap()].parse().unwrap()
    };
    let mut out = Vec::new();
    let mut rest = page;
    while let Some(i) = rest.find("<div class=\"grid\" style=\"--cols:") {
        let g = &rest[i..];
        let cols: usize = g[32..32 + g[32..].find('"').unwrap()].parse().unwrap();
        let end = g.find("<figcaption").unwrap();
        let panels = svgs(&g[..end]);
        let n = cols.min(panels.len()).max(1);
        let mut limit = vec![0.0_f64; n];
        for (k, p) in panels.iter().enumerate() {
            limit[k % cols] = limit[k % cols].max(width(p));
        }
        let mut track = vec![0.0_f64; n];
        let mut free = CONTENT_PX - GAP_PX * (n as f64 - 1.0);
        while free > 1e-9 {
            let open: Vec<usize> = (0..n).filter(|&k| limit[k] - track[k] > 1e-9).collect();
            if open.is_empty() {
                break;
            }
            let share = free / open.len() as f64;
            for k in open {
                let add = share.min(limit[k] - track[k]);
                track[k] += add;
                free -= add;
            }
        }
        for (k, p) in panels.iter().enumerate() {
            out.push((*p, width(p).min(track[k % cols])));
        }
        rest = &g[end..];
    }
    // Legends above a grid and charts outside one: at their own width.
    for s in svgs(page) {
        if !out.iter().any(|(o, _)| std::ptr::eq(*o, s)) {
            out.push((s, width(s).min(CONTENT_PX)));
        }
    }
    out
}

/// Texts of `page` smaller than 11 px as shown: `(px, text)`. A text's
/// size is its `font-size` (or the SVG's) times the shown width over the
/// viewBox's; sub- and superscripts, drawn at 75 % of their text's size,
/// are the typesetting convention and not counted.
fn small_texts(page: &str) -> Vec<(f64, String)> {
    let attr = |tag: &str, name: &str| -> Option<f64> {
        let key = format!(" {name}=\"");
        let i = tag.find(&key)? + key.len();
        tag[i..i + tag[i..].find('"')?].parse().ok()
    };
    let mut bad = Vec::new();
    for (svg, shown_px) in shown(page) {
        let root = &svg[..svg.find('>').unwrap()];
        let view = root.find("viewBox=\"0 0 ").map(|i| {
            let v = &root[i + 13..];
            v[..v.find(' ').unwrap()].parse::<f64>().unwrap()
        });
        let scale = shown_px / view.unwrap_or(attr(root, "width").unwrap());
        let inherited = attr(root, "font-size").unwrap_or(16.0);
        let mut rest = svg;
        while let Some(i) = rest.find("<text") {
            let tag = &rest[i..i + rest[i..].find('>').unwrap()];
            let size = attr(tag, "font-size").unwrap_or(inherited) * scale;
            let body = &rest[i + tag.len() + 1..];
            let text = &body[..body.find('<').unwrap_or(body.len())];
            if size < 11.0 - 1e-9 {
                bad.push((size, text.to_string()));
            }
            rest = &rest[i + tag.len()..];
        }
    }
    bad
}

#[test]
fn every_text_of_the_study_pages_is_at_least_11_px_in_a_1400_px_window() {
    let paper = tempfile::tempdir().unwrap();
    paper_study(paper.path());
    let planted = tempfile::tempdir().unwrap();
    planted_24(planted.path());
    for d in [paper.path(), planted.path()] {
        let page = page(d);
        assert!(shown(&page).len() >= 5);
        let bad = small_texts(&page);
        assert!(
            bad.is_empty(),
            "{} texts under 11 px: {:?}",
            bad.len(),
            &bad[..bad.len().min(8)]
        );
    }
    // The 24-case page: the parity plots name a few cases and no two
    // texts of any panel overlap; the relative error after the step has
    // its own panel, its axis the after-values' own.
    let page = page(planted.path());
    let fig = &page[page.find("<figure id=\"fig-step-1\"").unwrap()..];
    let fig = &fig[..fig.find("</figure>").unwrap()];
    let panels: Vec<&str> = fig.split("<svg").skip(1).collect();
    assert_eq!(panels.len(), 4, "two parity plots and two error panels");
    for p in &panels {
        let svg = format!("<svg{}", &p[..p.find("</svg>").unwrap() + 6]);
        swimbot::chart::text_clear(&svg).unwrap_or_else(|e| panic!("{e}"));
    }
    let named = |p: &str| {
        (1..=12)
            .filter(|i| p.contains(&format!(">t{i:02}<")) || p.contains(&format!(">u{i:02}<")))
            .count()
    };
    assert!(
        named(panels[0]) <= 5 && named(panels[0]) >= 1,
        "{}",
        named(panels[0])
    );
    assert!(panels[3].contains("after the step") && !panels[3].contains("U before"));
}

#[test]
fn the_paper_s_page_has_no_text_under_11_px() {
    let dir = tempfile::tempdir().unwrap();
    run(dir.path(), &["report", "-o", "out"]);
    let page = std::fs::read_to_string(dir.path().join("out/index.html")).unwrap();
    let bad = small_texts(&page);
    assert!(
        bad.is_empty(),
        "{} texts under 11 px: {:?}",
        bad.len(),
        &bad[..bad.len().min(8)]
    );
}

#[test]
fn the_bundle_carries_the_steps_table_and_laws_that_steps_prints() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    paper_study(d);
    let out = d.join("swimbot-out/report");
    let manifest: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let files: Vec<&str> = manifest["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f["file"].as_str().unwrap())
        .collect();
    // The files without their provenance comments, joined as `steps` prints them.
    let body = |name: &str| {
        let t = std::fs::read_to_string(out.join("tables").join(name)).unwrap();
        match name.ends_with(".tex") {
            true => t
                .lines()
                .skip_while(|l| l.starts_with("% ") && !l.starts_with("% The study"))
                .map(|l| format!("{l}\n"))
                .collect::<String>(),
            false => t[t.find("-->\n\n").unwrap() + 5..].to_string(),
        }
    };
    for (format, ext) in [("latex", "tex"), ("markdown", "md")] {
        for f in ["steps", "laws"] {
            assert!(
                files.contains(&format!("tables/{f}.{ext}").as_str()),
                "{files:?}"
            );
        }
        let printed = run(d, &["steps", "--format", format]);
        let joined = format!(
            "{}\n{}",
            body(&format!("steps.{ext}")),
            body(&format!("laws.{ext}"))
        );
        assert_eq!(printed, joined, "{format}");
    }
    let tex = body("steps.tex");
    assert!(tex.contains("\\toprule") && tex.contains("\\midrule") && tex.contains("\\bottomrule"));
    assert_eq!(
        tex.matches(" \\\\\n").count(),
        4,
        "a header and three rows: {tex}"
    );
    let laws = body("laws.tex");
    assert_eq!(laws.matches("\\begin{equation}").count(), 2, "{laws}");
    assert!(laws.contains("\\pm"), "{laws}");
    assert!(
        laws.contains("located-tail-torque") && laws.contains("\\tau")
            || laws.contains("\\mathrm{torque}")
            || laws.contains("torque"),
        "{laws}"
    );
}
