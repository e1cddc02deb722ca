//! Text as a reader sees it: tick labels that read like a paper's, real
//! subscripts, and the text checker catching a subscript in a tick label.

use super::*;

#[test]
fn ticks_read_like_a_paper() {
    let svg = chart(
        "t",
        "psi (deg)",
        "y",
        &[Series::measured(
            "",
            C,
            vec![(0.0, 0.0, 0.0), (360.0, 1e7, 0.0)],
        )],
        false,
    )
    .unwrap();
    let t = texts(&svg);
    assert!(t.iter().all(|s| !is_integer_with_point_zero(s)), "{t:?}");
    assert!(t.iter().all(|s| !s.contains("0000")), "{t:?}");
    assert!(t.contains(&"ψ (deg)".to_string()), "{t:?}");
    let log = Chart::new("t", "x", "y")
        .log_x()
        .log_y()
        .render(&[Series::measured(
            "",
            C,
            vec![(1e-2, 1.0, 0.0), (1e6, 1e3, 0.0)],
        )])
        .unwrap();
    let t = texts(&log);
    for p in ["10⁻²", "10⁰", "10⁶"] {
        assert!(t.iter().any(|s| s == p), "{p} in {t:?}");
    }
}

#[test]
fn subscripts_are_real_in_the_svg() {
    let svg = chart(
        "Parity: Omega_b",
        "N_lambda",
        "Omega_b / omega",
        &[Series::measured("", C, vec![(1.0, 1.0, 0.0)])],
        false,
    )
    .unwrap();
    assert!(svg.contains("Ω<tspan baseline-shift=\"sub\" font-size=\"75%\">b</tspan>"));
    assert!(svg.contains("N<tspan baseline-shift=\"sub\" font-size=\"75%\">λ</tspan>"));
    assert!(!svg.contains("Omega") && !svg.contains("lambda"));
}

#[test]
fn the_text_checker_catches_a_subscript_running_into_a_tick_label() {
    // A Fig. 4 (e) layout that fails: the rotated title's baseline 6 px left of
    // the tick label "0.15"; its subscript hangs 7 px towards it.
    let tick = "<text x=\"100\" y=\"100\" font-size=\"11\" text-anchor=\"end\">0.15</text>";
    let title = |x: f64| {
        format!(
            "<text x=\"{x}\" y=\"100\" font-size=\"12\" text-anchor=\"middle\" \
             transform=\"rotate(-90 {x} 100)\">Ω<tspan baseline-shift=\"sub\" \
             font-size=\"75%\">b</tspan> / ω</text>"
        )
    };
    let svg = |x: f64| {
        format!(
            "<svg width=\"200\" height=\"200\">{tick}\n{}</svg>",
            title(x)
        )
    };
    let err = text_clear(&svg(69.4)).unwrap_err();
    assert!(err.contains("0.15") && err.contains("Ω_b / ω"), "{err}");
    // Without the subscript the same spot is clear; moved left, so is it.
    assert!(text_clear(&svg(69.4).replace(
        "<tspan baseline-shift=\"sub\" font-size=\"75%\">b</tspan>",
        ""
    ))
    .is_ok());
    text_clear(&svg(64.0)).unwrap();
    // Text leaving the drawing.
    assert!(text_clear(&svg(64.0).replace("x=\"100\"", "x=\"10\"")).is_err());
}

#[test]
fn y_titles_with_subscripts_clear_wide_tick_labels() {
    for (y_desc, lo) in [
        ("Omega_b / omega", 0.1),
        ("U / U_wave", 1234.5),
        ("f", 0.001),
    ] {
        let pts = vec![(5.0, lo, 0.0), (5.8, 2.0 * lo, 0.0)];
        let svg = Chart::new("(e) B_o/R_body = 0.45", "N_lambda", y_desc)
            .size(390, 330)
            .render(&[Series::measured("m", C, pts)])
            .unwrap();
        text_clear(&svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
    }
}
