//! Markers, error bars and panels: bars smaller than the marker noted,
//! flat series not zoomed onto noise, stacked panels aligned, dodged
//! markers apart, a bar below zero on a log axis.

use super::*;

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
