//! The legend covers no data: the checker rejects a covered legend, the
//! legend takes the free corner, or goes outside when data are everywhere.

use super::*;

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
