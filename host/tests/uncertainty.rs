//! Input uncertainties: parsing and its errors (the real binary, exit 2),
//! linear propagation against exact scalings and against Monte Carlo, and
//! the combined uncertainty that `compare --input-uncertainty` judges with.

use crate::common;
use common::swimbot;
use swimbot::data::{self, parse_str};
use swimbot::model::{preset, Model};
use swimbot::workbench::propagate::{combine, linear_band, monte_carlo, with_input_uncertainty};

/// The paper's data with its `[setup.uncertainty]` table replaced by `table`.
fn paper_with(table: &str) -> String {
    let text = data::PAPER_TOML;
    let start = text
        .find("[setup.uncertainty]")
        .expect("the paper data state uncertainties");
    let end = text[start..].find("[[case]]").unwrap() + start;
    format!("{}{table}\n\n{}", &text[..start], &text[end..])
}

fn assert_input_error(file_text: &str, needles: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("bad.toml");
    std::fs::write(&path, file_text).unwrap();
    let o = swimbot(&["compare", "--no-report", "--data", path.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("bad.toml"), "file not named: {err}");
    for n in needles {
        assert!(err.contains(n), "`{n}` missing from: {err}");
    }
}

#[test]
fn bad_uncertainties_name_file_case_and_field_and_exit_2() {
    assert_input_error(
        &paper_with("[setup.uncertainty]\nwavelength_mm = -0.5"),
        &["tail-1", "uncertainty.wavelength_mm", ">= 0"],
    );
    assert_input_error(
        &paper_with("[setup.uncertainty]\nviscosity_pa_s = nan"),
        &["uncertainty.viscosity_pa_s", "finite"],
    );
    assert_input_error(
        &paper_with("[setup.uncertainty]\nwingspan_mm = 1.0"),
        &[
            "uncertainty.wingspan_mm",
            "not a numeric input",
            "amplitude_mm",
        ],
    );
    assert_input_error(
        &paper_with("[setup.uncertainty]\namplitude_mm = \"ten%\""),
        &["uncertainty.amplitude_mm", "not a percentage"],
    );
    // A per-case override is blamed on its own case.
    let text = data::PAPER_TOML.replace(
        "id = \"tail-3\"",
        "id = \"tail-3\"\nuncertainty = { tail_length_mm = \"-3%\" }",
    );
    assert_input_error(&text, &["tail-3", "uncertainty.tail_length_mm", ">= 0"]);
}

#[test]
fn relative_and_per_case_uncertainties_resolve_and_round_trip() {
    let text = data::PAPER_TOML.replace(
        "id = \"tail-3\"",
        "id = \"tail-3\"\nuncertainty = { amplitude_mm = \"10%\" }",
    );
    let d = parse_str(&text, "t").unwrap();
    let c3 = &d.cases[2];
    assert!((c3.inputs.standard(c3, "amplitude_mm") - 0.45).abs() < 1e-12);
    assert_eq!(d.cases[0].inputs.standard(&d.cases[0], "amplitude_mm"), 0.3);
    assert!((c3.inputs.standard(c3, "viscosity_pa_s") - 0.175).abs() < 1e-12);
    assert!(c3.inputs.chord_fixed);
    let again = parse_str(&data::to_toml(&d), "round-trip").unwrap();
    assert_eq!(d, again);
}

#[test]
fn mandrel_convention_moves_the_centre_line_by_half_a_wire() {
    let text = data::PAPER_TOML.replace(
        "chord_fixed = true",
        "chord_fixed = true\namplitude_convention = \"mandrel\"",
    );
    let d = parse_str(&text, "t").unwrap();
    assert_eq!(d.cases[0].amplitude_mm, 3.0);
    assert_eq!(d.cases[5].amplitude_mm, 8.0);
}

/// Stokes flow is linear in the tail rate: U and Omega_b scale with f, so
/// a relative uncertainty of f is the same relative band, exactly; and with
/// no weight in the model every force scales with the viscosity, so it
/// cannot move the speed.
#[test]
fn linear_band_matches_exact_scalings() {
    let mut case = data::paper().cases[2].clone();
    let only = |field: &str, text: &str| {
        let t = format!("x = {text}");
        let v: toml::Table = toml::from_str(&t).unwrap();
        vec![(
            swimbot::data::uncertainty::field_id(field).unwrap(),
            swimbot::data::uncertainty::Uncertainty::from_toml(&v["x"]).unwrap(),
        )]
    };
    let model = Model::base();
    let p = model.predict(&case).unwrap();
    case.inputs.uncertainties = only("frequency_hz", "\"3%\"");
    let b = linear_band(&model, &case).unwrap();
    assert!((b.u_sd_mm_s / p.u_mm_s.abs() - 0.03).abs() < 1e-6, "{b:?}");
    assert!((b.omega_sd_hz / p.omega_body_hz.abs() - 0.03).abs() < 1e-6);
    assert!(
        b.omega_ratio_sd < 1e-6 * p.omega_ratio.abs(),
        "Omega/omega does not depend on f"
    );
    assert_eq!(b.dominant_u, Some("frequency_hz"));
    case.inputs.uncertainties = only("viscosity_pa_s", "\"10%\"");
    let b = linear_band(&model, &case).unwrap();
    assert!(b.u_sd_mm_s < 1e-6 * p.u_mm_s.abs(), "{b:?}");
}

#[test]
fn linear_bands_agree_with_monte_carlo_where_the_model_is_near_linear() {
    // 1 % on every input: well inside the linear range.
    let text = paper_with(
        "[setup.uncertainty]\nwavelength_mm = \"1%\"\namplitude_mm = \"1%\"\ntail_length_mm = \"1%\"\nfrequency_hz = \"1%\"\nchannel_diameter_mm = \"1%\"\nviscosity_pa_s = \"1%\"\nbody_diameter_mm = \"1%\"\nbody_length_mm = \"1%\"",
    );
    let d = parse_str(&text, "t").unwrap();
    let model = preset("paper").unwrap();
    let mut rows = Vec::new();
    for c in &d.cases {
        let b = linear_band(&model, c).unwrap();
        let mc = monte_carlo(&model, c, &b, 400, 7).unwrap();
        assert_eq!(mc.failed, 0);
        rows.push((c.id.clone(), mc.u_sd_ratio, mc.omega_sd_ratio));
        assert!((mc.u_sd_ratio - 1.0).abs() < 0.10, "{rows:?}");
        assert!((mc.omega_sd_ratio - 1.0).abs() < 0.10, "{rows:?}");
        assert!(!mc.nonlinear);
    }
}

#[test]
fn combined_dataset_widens_every_interval_by_quadrature() {
    let d = data::paper();
    let model = preset("paper").unwrap();
    let w = with_input_uncertainty(&model, &d).unwrap();
    for (a, b) in d.cases.iter().zip(&w.cases) {
        let band = linear_band(&model, a).unwrap();
        let (ma, mb) = (a.u_mm_s.unwrap(), b.u_mm_s.unwrap());
        let expect = (ma.standard_error().powi(2) + band.u_sd_mm_s.powi(2)).sqrt();
        assert!(
            (mb.standard_error() - expect).abs() < 1e-9 * expect,
            "{}",
            a.id
        );
        assert!(mb.trials >= ma.trials && mb.ci_half_width >= ma.ci_half_width);
        assert_eq!(combine(&ma, 0.0), ma);
    }
}

#[test]
fn compare_shows_bands_and_judges_against_the_combined_uncertainty() {
    let plain = swimbot(&[
        "compare",
        "--no-report",
        "--preset",
        "paper",
        "--mc-draws",
        "50",
    ]);
    let out = String::from_utf8_lossy(&plain.stdout);
    assert!(
        plain.status.success(),
        "{}",
        String::from_utf8_lossy(&plain.stderr)
    );
    assert!(
        out.contains("± inputs") && out.contains("dominant input"),
        "{out}"
    );
    assert!(
        out.contains("standard errors of the measured mean"),
        "{out}"
    );
    let comb = swimbot(&[
        "compare",
        "--no-report",
        "--preset",
        "paper",
        "--input-uncertainty",
        "--format",
        "json",
    ]);
    assert!(comb.status.success());
    let v: serde_json::Value = serde_json::from_slice(&comb.stdout).unwrap();
    let chi_m = v["summary"]["chi2"].as_f64().unwrap();
    let chi_c = v["summary_combined"]["chi2"].as_f64().unwrap();
    assert!(
        chi_c < chi_m,
        "inputs can only widen the uncertainty: {chi_c} vs {chi_m}"
    );
    for c in v["cases"].as_array().unwrap() {
        assert!(c["u_input_sd_mm_s"].as_f64().unwrap() > 0.0);
        assert!(c["u_dominant_input"].is_string());
    }
}

/// `(axial drag N s/m, rotational drag N m s)` of a profile `spec` in the
/// paper's closed tube at 3.5 Pa s, default resolution.
fn body_drag(spec: &str) -> (f64, f64) {
    use swimbot::nonlocal::axisym::{solve_body, AxisymSettings, Confinement};
    let profile = swimbot::physics::profile::BodyProfile::parse_sections(spec, 0.0).unwrap();
    let channel = data::paper().cases[0].channel();
    let s = solve_body(
        &profile,
        &Confinement::of_channel(&channel),
        0.0,
        3.5,
        &AxisymSettings::default(),
    )
    .unwrap();
    (s.drag_n_s_per_m, s.rotational_drag_n_m_s)
}

/// The section lengths (cork / casing / seal) are unknown, the diameters and
/// the 50 mm total are not. Every body of such sections lies inside the
/// 20 x 50 mm cylinder and contains the 18 x 50 mm one, so by the
/// minimum-dissipation theorem (Happel & Brenner 1965, 4-11: in Stokes
/// flow a body enclosed by another has the smaller drag, the walls held
/// still) its drag lies between theirs, for translation and for rotation.
/// Checked on the extremes 5/40/5 and 20/10/20 and on seeded draws
/// of the documented distribution (cork and seal each 10 +- 5 mm,
/// rectangular); swapping cork and seal mirrors the body, which Stokes
/// reversibility says cannot change its drag.
#[test]
fn section_lengths_stay_between_the_enclosing_and_the_enclosed_cylinder() {
    use rand::{Rng, SeedableRng};
    let (outer, inner) = (body_drag("50:20"), body_drag("50:18"));
    let (thin, thick) = (body_drag("5:20,40:18,5:20"), body_drag("20:20,10:18,20:20"));
    // the extremes' span (D_x 18.4-23.2 N s/m); E_x 3.08-3.58e-4 N m s (the
    // enclosing cylinder's is 3.72e-4)
    assert!((thin.0 - 18.43).abs() < 0.05 && (thick.0 - 23.21).abs() < 0.05);
    assert!((thin.1 - 3.076e-4).abs() < 5e-7 && (thick.1 - 3.585e-4).abs() < 5e-7);
    let mut rng = rand::rngs::StdRng::seed_from_u64(2024);
    let mut specs = vec![(5.0, 5.0), (20.0, 20.0), (5.0, 15.0)];
    specs.extend((0..3).map(|_| (rng.gen_range(5.0..15.0), rng.gen_range(5.0..15.0))));
    let mut seen = Vec::new();
    for (cork, seal) in specs {
        let d = body_drag(&format!("{cork}:20,{}:18,{seal}:20", 50.0 - cork - seal));
        seen.push((cork, seal, d));
        assert!(
            inner.0 < d.0 && d.0 < outer.0,
            "{seen:?}, cylinders {inner:?} {outer:?}"
        );
        assert!(
            inner.1 < d.1 && d.1 < outer.1,
            "{seen:?}, cylinders {inner:?} {outer:?}"
        );
    }
    let (a, b) = (body_drag("5:20,30:18,15:20"), body_drag("15:20,30:18,5:20"));
    assert!((a.0 / b.0 - 1.0).abs() < 1e-3, "{a:?} {b:?}");
    assert!((a.1 / b.1 - 1.0).abs() < 1e-3, "{a:?} {b:?}");
}

/// The trim is a constant axial load and Stokes flow is linear in the
/// loads: its band is exactly the change a trim of one standard
/// uncertainty makes; heavier is slower; a horizontal channel does not
/// feel it along the axis.
#[test]
fn the_trim_is_an_exact_linear_load_along_a_vertical_channel() {
    let mut case = data::paper().cases[3].clone();
    case.inputs.uncertainties = vec![(
        swimbot::data::uncertainty::field_id("net_weight_g").unwrap(),
        swimbot::data::uncertainty::Uncertainty::Absolute(0.1),
    )];
    let model = Model::base();
    let at = |c: &data::Case, w: f64| {
        let mut c = c.clone();
        c.net_weight_g = w;
        model.predict(&c).unwrap()
    };
    let (p0, heavy, light) = (at(&case, 0.0), at(&case, 0.1), at(&case, -0.1));
    assert!(heavy.u_mm_s < p0.u_mm_s && light.u_mm_s > p0.u_mm_s);
    let du = heavy.u_mm_s - p0.u_mm_s;
    assert!((light.u_mm_s - p0.u_mm_s + du).abs() < 1e-9 * du.abs());
    let b = linear_band(&model, &case).unwrap();
    assert!((b.u_sd_mm_s / du.abs() - 1.0).abs() < 1e-6, "{b:?} {du}");
    assert_eq!(b.dominant_u, Some("net_weight_g"));
    case.orientation = data::Orientation::Horizontal;
    assert_eq!(at(&case, 0.1).u_mm_s, at(&case, 0.0).u_mm_s);
}
