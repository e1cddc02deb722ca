//! The profile-likelihood interval through the study, from the real
//! binary: an exponent poorly determined on the paper's six-case design
//! (30 % noise, three trials) has an asymmetric profile, which `add`
//! stores and `add`, `steps` (terminal, Markdown, LaTeX), the page and the
//! bundle's tables print, with the ends `diagnose --format json` gives the
//! same law on the same data; a linear effect's profile is symmetric and
//! its covariance interval stays; a study an earlier swimbot wrote, without
//! profiles, loads and prints its covariance intervals as before.

use crate::common::{run_in, stderr};
use std::path::Path;
use swimbot::report::steps_table::param;
use swimbot::study::file::ParamRecord;

fn ok(cwd: &Path, args: &[&str]) -> String {
    let o = run_in(cwd, args);
    assert!(o.status.success(), "{args:?}: {}", stderr(&o));
    String::from_utf8(o.stdout).unwrap()
}

/// Text with every run of white space (a wrapped line's break and
/// indentation, a no-break space) as one space.
fn flat(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The synthetic lab: the paper's cases, the paper's model as the truth,
/// 30 % noise per trial, three trials (seed 8).
fn noisy_lab(d: &Path) {
    ok(
        d,
        &[
            "synth",
            "--quiet",
            "--truth",
            "paper",
            "--noise",
            "0.3",
            "--trials",
            "3",
            "--seed",
            "8",
            "-o",
            "data.toml",
        ],
    );
    ok(d, &["init", "--quiet", "--data", "data.toml"]);
}

/// The fitted parameters of step `n` (1-based) as the study stores them.
fn fitted(d: &Path, n: usize) -> Vec<ParamRecord> {
    let study: serde_json::Value =
        serde_json::from_str(&ok(d, &["steps", "--format", "json"])).unwrap();
    let params = study["step"][n - 1]["param"].as_array().unwrap();
    params
        .iter()
        .map(|p| serde_json::from_value::<ParamRecord>(p.clone()).unwrap())
        .filter(|p| p.status == "fitted")
        .collect()
}

#[test]
fn an_asymmetric_profile_is_what_every_study_view_prints_and_diagnose_s() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    noisy_lab(d);
    let diagnosis: serde_json::Value = serde_json::from_str(&ok(
        d,
        &[
            "diagnose",
            "--quiet",
            "--write-effect",
            "found.toml",
            "--format",
            "json",
        ],
    ))
    .unwrap();
    let law = &diagnosis["headline"]["steps"][0];
    let found: toml::Value =
        toml::from_str(&std::fs::read_to_string(d.join("found.toml")).unwrap()).unwrap();
    let name = found["effect"][0]["name"].as_str().unwrap();
    let added = ok(d, &["add", "--quiet", &format!("found.toml#{name}")]);
    let params = fitted(d, 1);
    let mut profiled = 0;
    for q in law["params"].as_array().unwrap() {
        let p = params
            .iter()
            .find(|p| p.name == q["name"].as_str().unwrap())
            .unwrap_or_else(|| panic!("{q} is not a fitted parameter of the step"));
        let stored = p.profile.as_ref().expect("a profile stored");
        let r = p.report();
        assert_eq!(r.interval, q["interval"].as_str().unwrap(), "{p:?}\n{q}");
        if r.interval != "profile" {
            continue;
        }
        profiled += 1;
        assert!(stored.asymmetric);
        // The same law fitted on the same data by the same code: the ends
        // agree to a hundredth of the standard uncertainty.
        let u = r.standard_uncertainty.unwrap();
        for (mine, theirs) in [(r.ci95_low, &q["ci95_low"]), (r.ci95_high, &q["ci95_high"])] {
            match (mine, theirs.as_f64()) {
                (Some(a), Some(b)) => assert!((a - b).abs() < 0.01 * u, "{a} against {b}"),
                (None, None) => {}
                _ => panic!("{p:?} against diagnose's {q}"),
            }
        }
        let said = flat(&param(&r));
        assert!(said.contains("95 % profile"), "{said}");
        for bad in ["NaN", "inf"] {
            assert!(!said.contains(bad), "{said}");
        }
        // `add`, `steps` and the paper's tables print it as one spelling.
        let steps = ok(d, &["steps"]);
        let markdown = ok(d, &["steps", "--format", "markdown"]);
        for (what, text) in [("add", &added), ("steps", &steps), ("markdown", &markdown)] {
            assert!(flat(text).contains(&said), "{what}: {said}\n{text}");
        }
    }
    assert!(profiled >= 1, "no asymmetric profile in {law}");
    let open: Vec<&ParamRecord> = params
        .iter()
        .filter(|p| p.profile.as_ref().is_some_and(|q| q.high.is_none()))
        .collect();
    assert!(
        !open.is_empty(),
        "the bounded k's upper end is open: {params:?}"
    );
    ok(d, &["report", "--quiet"]);
    let page = std::fs::read_to_string(d.join("swimbot-out/report/index.html")).unwrap();
    let start = page.find("<section class=\"answer\">").expect("the answer");
    let answer = &page[start..start + page[start..].find("</section>").unwrap()];
    let tables = d.join("swimbot-out/report/tables");
    let read = |f: &str| std::fs::read_to_string(tables.join(f)).unwrap();
    for p in params.iter().filter(|p| p.report().interval == "profile") {
        let said = param(&p.report());
        let ends = &said[said.find("95\u{a0}% profile").unwrap()..];
        let ends = &ends[..ends.find([',', ')']).unwrap()];
        assert!(answer.contains(ends), "the page's opening: {ends}");
        assert!(read("steps.md").contains(ends), "steps.md: {ends}");
        assert!(read("laws.md").contains(ends), "laws.md: {ends}");
    }
    assert!(read("laws.tex").contains("\\text{profile}"));
    assert!(read("steps.tex").contains("profile"));
    // The step's parameter table says which interval, and an open end.
    assert!(page.contains("<td class=\"l\">profile</td>") && page.contains("<td>open</td>"));
}

#[test]
fn a_linear_effect_keeps_its_covariance_interval() {
    // Buoyancy is a constant axial force: U and Ω_b are linear in it, the
    // chi-square a parabola, and the profile the covariance's.
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    noisy_lab(d);
    ok(d, &["add", "--quiet", "buoyancy"]);
    let params = fitted(d, 1);
    assert!(!params.is_empty());
    let steps = ok(d, &["steps"]);
    for p in &params {
        let q = p.profile.as_ref().expect("a profile stored");
        assert!(!q.asymmetric, "{p:?}");
        let r = p.report();
        assert_eq!(
            (r.interval.as_ref(), r.ci95_low, r.ci95_high),
            ("covariance", p.lo, p.hi)
        );
        assert!(flat(&steps).contains(&flat(&param(&r))), "{steps}");
    }
    assert!(!steps.contains("profile"), "{steps}");
}

#[test]
fn a_study_without_profiles_loads_and_prints_as_before() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    noisy_lab(d);
    ok(d, &["diagnose", "--quiet", "--write-effect", "found.toml"]);
    let found: toml::Value =
        toml::from_str(&std::fs::read_to_string(d.join("found.toml")).unwrap()).unwrap();
    let name = found["effect"][0]["name"].as_str().unwrap();
    ok(d, &["add", "--quiet", &format!("found.toml#{name}")]);
    let with = ok(d, &["steps", "--format", "markdown"]);
    assert!(with.contains("profile"), "{with}");
    let recorded = fitted(d, 1);
    // The file as a swimbot before the profile wrote it: no
    // `[step.param.profile]` tables.
    let file = d.join("swimbot-study.toml");
    let text = std::fs::read_to_string(&file).unwrap();
    let mut old = String::new();
    let mut skip = false;
    for line in text.lines() {
        if line.starts_with('[') {
            skip = line == "[step.param.profile]";
        }
        if !skip {
            old.push_str(line);
            old.push('\n');
        }
    }
    assert!(old.len() < text.len() && !old.contains("asymmetric"));
    std::fs::write(&file, &old).unwrap();
    let without = ok(d, &["steps", "--format", "markdown"]);
    // It loads with every other field as stored, and prints each
    // parameter's covariance interval where the profile was, the rest
    // unchanged.
    let mut expected = with.clone();
    let mut before: Vec<ParamRecord> = Vec::new();
    for p in recorded {
        let mut was = p.clone();
        was.profile = None;
        expected = expected.replace(&param(&p.report()), &param(&was.report()));
        before.push(was);
    }
    assert_eq!(fitted(d, 1), before);
    assert!(!without.contains("profile"), "{without}");
    assert_eq!(without, expected);
    // Reading never rewrote it.
    assert_eq!(std::fs::read_to_string(&file).unwrap(), old);
}

#[test]
fn an_absurd_stored_profile_end_is_refused_by_step_and_field() {
    // Checked by range only, as the covariance's ends: an end that is not
    // a number, or an interval that does not hold its value, is exit 2.
    for (bad, says) in [
        ("inf", "not a finite number"),
        ("nan", "not a finite number"),
        ("1e9", "does not hold"),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        noisy_lab(d);
        ok(d, &["add", "--quiet", "buoyancy"]);
        let file = d.join("swimbot-study.toml");
        let text = std::fs::read_to_string(&file).unwrap();
        let at = text
            .find("[step.param.profile]\nlow = ")
            .expect("a stored profile")
            + 27;
        let end = at + text[at..].find('\n').unwrap();
        std::fs::write(&file, format!("{}{bad}{}", &text[..at], &text[end..])).unwrap();
        let o = run_in(d, &["steps"]);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{bad}: {e}");
        assert!(!e.contains("panicked"), "{e}");
        for needle in ["swimbot-study.toml", "step 1", "profile", says] {
            assert!(e.contains(needle), "{bad}: no `{needle}` in {e}");
        }
    }
}
