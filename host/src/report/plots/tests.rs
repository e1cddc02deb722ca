//! Tests of the chart engine as a reader sees it: the legend covers no
//! data (and the checker really rejects one that does), tick labels,
//! notation, hidden-error-bar notes, and every figure of the built-in
//! report page.

use super::*;

const C: plotters::style::RGBColor = PALETTE[0];

/// The legend box (x, y, w, h) of a one-legend SVG.
fn legend_box(svg: &str) -> (f64, f64, f64, f64) {
    let g = &svg[svg.find("<g class=\"legend\">").expect("a legend")..];
    let r = &g[g.find("<rect ").expect("its box")..];
    let num = |k: &str| -> f64 {
        let s = &r[r.find(&format!(" {k}=\"")).expect(k) + k.len() + 3..];
        s[..s.find('"').expect("quote")].parse().expect("number")
    };
    (num("x"), num("y"), num("width"), num("height"))
}

fn svg_width(svg: &str) -> f64 {
    let s = &svg[svg.find(" width=\"").expect("width") + 8..];
    s[..s.find('"').expect("quote")].parse().expect("number")
}

/// Points on a grid over [0, 10]^2, except those `skip` rejects.
fn grid(skip: impl Fn(f64, f64) -> bool) -> Vec<(f64, f64, f64)> {
    (0..=20)
        .flat_map(|i| (0..=20).map(move |j| (i as f64 * 0.5, j as f64 * 0.5, 0.0)))
        .filter(|p| !skip(p.0, p.1))
        .collect()
}

fn entries() -> Vec<Series> {
    vec![
        Series::measured("a long legend label", C, vec![]),
        Series::model("model", PALETTE[1], vec![]),
    ]
}

#[test]
fn the_checker_rejects_a_covered_legend() {
    let hand = "<svg><g class=\"data\">\n<circle cx=\"50\" cy=\"50\" r=\"4\"/>\n</g>\n<g class=\"legend\">\n<rect x=\"40\" y=\"40\" width=\"30\" height=\"20\"/>\n</g></svg>";
    assert!(legend_clear(hand).is_err());
    // A curve crossing the box with no vertex inside it.
    let crossing = "<svg><g class=\"data\">\n<polyline points=\"0,50 100,50\"/>\n</g>\n<g class=\"legend\">\n<rect x=\"40\" y=\"40\" width=\"30\" height=\"20\"/>\n</g></svg>";
    assert!(legend_clear(crossing).is_err());
    let bar = crossing.replace(
        "<polyline points=\"0,50 100,50\"/>",
        "<line x1=\"55\" y1=\"0\" x2=\"55\" y2=\"100\"/>",
    );
    assert!(legend_clear(&bar).is_err());
    let clear = crossing.replace("0,50 100,50", "0,90 100,90");
    assert!(legend_clear(&clear).is_ok());

    // A real chart, then a marker moved into its legend.
    let mut series = entries();
    series.push(Series::measured(
        "",
        C,
        vec![(0.0, 0.0, 0.1), (1.0, 1.0, 0.1)],
    ));
    let svg = chart("t", "x", "y", &series, false).unwrap();
    legend_clear(&svg).unwrap();
    let (x, y, w, h) = legend_box(&svg);
    let covered = svg.replacen(
        "<g class=\"data\">\n",
        &format!(
            "<g class=\"data\">\n<circle cx=\"{}\" cy=\"{}\" r=\"4\"/>\n",
            x + 0.5 * w,
            y + 0.5 * h
        ),
        1,
    );
    assert!(legend_clear(&covered).is_err());
}

#[test]
fn the_legend_takes_the_free_corner() {
    // Data everywhere but one quadrant: the legend must go there.
    // (which points to leave out, legend expected right, expected upper)
    type Quadrant = (fn(f64, f64) -> bool, bool, bool);
    let quadrants: [Quadrant; 4] = [
        (|x, y| x > 5.0 && y > 5.0, true, true),
        (|x, y| x < 5.0 && y > 5.0, false, true),
        (|x, y| x > 5.0 && y < 5.0, true, false),
        (|x, y| x < 5.0 && y < 5.0, false, false),
    ];
    for (free, right, upper) in quadrants {
        let mut series = entries();
        series.push(Series::measured("", C, grid(free)));
        let svg = chart("t", "x", "y", &series, false).unwrap();
        legend_clear(&svg).unwrap();
        let (x, y, w, h) = legend_box(&svg);
        assert_eq!(svg_width(&svg), 560.0, "the legend fits inside");
        assert_eq!(x + 0.5 * w > 280.0, right, "legend at x {x}");
        assert_eq!(y + 0.5 * h < 190.0, upper, "legend at y {y}");
    }
}

#[test]
fn with_data_everywhere_the_legend_goes_outside() {
    let mut series = entries();
    series.push(Series::measured("", C, grid(|_, _| false)));
    let svg = chart("t", "x", "y", &series, false).unwrap();
    legend_clear(&svg).unwrap();
    let (x, _, w, _) = legend_box(&svg);
    assert!(svg_width(&svg) > 560.0, "canvas enlarged");
    assert!(x + w <= svg_width(&svg));
    // A curve through every corner does the same.
    let zigzag: Vec<(f64, f64, f64)> = (0..40)
        .map(|i| (i as f64, if i % 2 == 0 { 0.0 } else { 1.0 }, 0.0))
        .collect();
    let svg = chart("t", "x", "y", &[Series::curve("zigzag", C, zigzag)], false).unwrap();
    legend_clear(&svg).unwrap();
    assert!(svg_width(&svg) > 560.0);
}

/// Text contents of every `<text>` element.
fn texts(svg: &str) -> Vec<String> {
    svg.split("<text ")
        .skip(1)
        .map(|t| {
            let body = &t[t.find('>').expect("tag end") + 1..t.find("</text>").expect("close")];
            // Drop tspan markup.
            let mut out = String::new();
            let mut in_tag = false;
            for c in body.chars() {
                match c {
                    '<' => in_tag = true,
                    '>' => in_tag = false,
                    c if !in_tag => out.push(c),
                    _ => {}
                }
            }
            out
        })
        .collect()
}

fn is_integer_with_point_zero(t: &str) -> bool {
    t.strip_suffix(".0")
        .is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit() || c == '-'))
}

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
fn error_bars_smaller_than_the_marker_are_drawn_and_noted() {
    let pts = vec![(0.0, 0.0, 1e-6), (1.0, 1.0, 0.3), (2.0, 0.5, 1e-6)];
    let s = Series::measured("measured", C, pts).labels(vec!["a".into(), "b".into(), "c".into()]);
    let svg = chart("t", "x", "y", &[s], false).unwrap();
    let notes = &svg[svg.find("<g class=\"notes\">").expect("a note")..];
    assert!(
        notes.contains("vertical bars of a, c (measured)."),
        "{notes}"
    );
    // Each bar is drawn (two caps and a stem per point).
    let data =
        &svg[svg.find("<g class=\"data\">").unwrap()..svg.find("<g class=\"labels\">").unwrap()];
    assert_eq!(data.matches("<line ").count(), 9);
    // Large bars: no note.
    let big = chart(
        "t",
        "x",
        "y",
        &[Series::measured(
            "m",
            C,
            vec![(0.0, 0.0, 0.5), (1.0, 1.0, 0.5)],
        )],
        false,
    )
    .unwrap();
    assert!(!big.contains("class=\"notes\""));
}

#[test]
fn flat_series_are_not_zoomed_onto_noise() {
    let flat: Vec<(f64, f64, f64)> = (0..200)
        .map(|i| (i as f64, 4.0 + 1e-9 * (i % 2) as f64, 0.0))
        .collect();
    let svg = chart("t", "x", "y", &[Series::curve("flat", C, flat)], false).unwrap();
    let data = &svg[svg.find("<g class=\"data\">").unwrap()..];
    let pts = &data[data.find("points=\"").unwrap() + 8..];
    let ys: Vec<f64> = pts[..pts.find('"').unwrap()]
        .split_whitespace()
        .map(|p| p.split_once(',').unwrap().1.parse().unwrap())
        .collect();
    let spread =
        ys.iter().cloned().fold(f64::MIN, f64::max) - ys.iter().cloned().fold(f64::MAX, f64::min);
    assert!(spread < 0.5, "a flat line spans {spread} px");
}

#[test]
fn stacked_panels_share_the_left_edge() {
    let a = Chart::new("", "t", "small").size(500, 150);
    let b = Chart::new("", "t", "wide labels").size(500, 150);
    let svg = stack(
        "two",
        &[
            (
                a,
                vec![Series::curve(
                    "a",
                    C,
                    vec![(0.0, 0.0, 0.0), (1.0, 1.0, 0.0)],
                )],
            ),
            (
                b,
                vec![Series::curve(
                    "b",
                    C,
                    vec![(0.0, 0.0, 0.0), (1.0, 123456.0, 0.0)],
                )],
            ),
        ],
    )
    .unwrap();
    legend_clear(&svg).unwrap();
    let frames: Vec<&str> = svg.split("<g class=\"frame\">").skip(1).collect();
    let left_axis = |f: &str| {
        // The y axis is the second axis line drawn (after the x axis).
        let lines: Vec<&str> = f
            .split("<line ")
            .filter(|l| l.contains("#3c3c3c"))
            .collect();
        let l = lines[1];
        let s = &l[l.find("x1=\"").unwrap() + 4..];
        s[..s.find('"').unwrap()].to_string()
    };
    assert_eq!(left_axis(frames[0]), left_axis(frames[1]));
}

/// Every figure of the report page on the built-in data.
#[test]
fn every_figure_of_the_report_page_is_clear_and_readable() {
    let dir = tempfile::tempdir().unwrap();
    let data = crate::data::paper();
    let path = crate::report::write_report(
        dir.path(),
        &crate::workbench::path::user_path(&crate::model::Model::base(), 0, &data).unwrap(),
        &data,
        None,
        &|_| Ok(()),
    )
    .unwrap();
    let page = std::fs::read_to_string(path).unwrap();
    let svgs: Vec<&str> = page
        .split("<svg ")
        .skip(1)
        .map(|s| &s[..s.find("</svg>").unwrap()])
        .collect();
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
    let parity: Vec<&&str> = svgs
        .iter()
        .filter(|s| texts(s).iter().any(|t| t.starts_with("Parity")))
        .collect();
    // the paper's model's (section 3) and the model asked for's (section 4)
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

#[test]
fn the_text_checker_catches_a_subscript_running_into_a_tick_label() {
    // Fig. 4 (e) before the fix: the rotated title's baseline 6 px left of
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

#[test]
fn dodged_markers_and_bars_stand_apart_at_one_x() {
    let at = |svg: &str| -> Vec<f64> {
        svg.match_indices("<circle cx=\"")
            .map(|(i, _)| {
                let s = &svg[i + 12..];
                s[..s.find('"').unwrap()].parse().unwrap()
            })
            .collect()
    };
    let one = |d: f64| Series::model("", C, vec![(1.0, 1.0, 0.5), (2.0, 1.5, 0.5)]).dodged(d);
    let plain = chart("", "x", "y", &[one(0.0)], false).unwrap();
    let svg = chart("", "x", "y", &[one(-0.02), one(0.02)], false).unwrap();
    let (p, d) = (at(&plain), at(&svg));
    // the same plot: the same shift at every point, left and right
    let shift = d[2] - p[0];
    assert!((p[0] - d[0] - shift).abs() < 0.11, "{p:?} {d:?}");
    assert!((d[3] - p[1] - shift).abs() < 0.11, "{p:?} {d:?}");
    // the two bars' caps (3 px either side) stand apart
    assert!(2.0 * shift > 6.0 + 1.0, "bars' caps meet: {d:?}");
    legend_clear(&svg).unwrap();
}

#[test]
fn a_point_whose_bar_reaches_below_zero_stays_on_a_log_axis() {
    let pts = vec![(0.2, 0.05, 0.13), (0.6, 0.5, 0.01), (0.3, 0.3, 0.0)];
    let svg = Chart::new("", "x", "y")
        .log_x()
        .log_y()
        .render(&[Series::measured("", C, pts)])
        .unwrap();
    let cys: Vec<f64> = svg
        .match_indices("<circle cx=\"")
        .map(|(i, _)| {
            let s = &svg[i..];
            let s = &s[s.find(" cy=\"").unwrap() + 5..];
            s[..s.find('"').unwrap()].parse().unwrap()
        })
        .collect();
    // the plot's bottom: the default 380 px height less the space below it
    let h = 380.0 - 46.0;
    assert!(
        cys.iter().all(|y| *y <= h + 0.1),
        "a marker under the axis: {cys:?}"
    );
}
