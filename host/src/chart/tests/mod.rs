//! Tests of the chart engine as a reader sees it, by subject: the legend
//! ([`legend`]), text ([`text`]), markers and panels ([`marks`]); the
//! helpers they share are here (the report's own figure checks use them
//! too).

use super::*;

mod legend;
mod marks;
mod text;

pub(super) const C: crate::chart::Rgb = PALETTE[0];

/// The legend box (x, y, w, h) of a one-legend SVG.
pub(super) fn legend_box(svg: &str) -> (f64, f64, f64, f64) {
    let g = &svg[svg.find("<g class=\"legend\">").expect("a legend")..];
    let r = &g[g.find("<rect ").expect("its box")..];
    let num = |k: &str| -> f64 {
        let s = &r[r.find(&format!(" {k}=\"")).expect(k) + k.len() + 3..];
        s[..s.find('"').expect("quote")].parse().expect("number")
    };
    (num("x"), num("y"), num("width"), num("height"))
}

pub(super) fn svg_width(svg: &str) -> f64 {
    let s = &svg[svg.find(" width=\"").expect("width") + 8..];
    s[..s.find('"').expect("quote")].parse().expect("number")
}

/// Points on a grid over [0, 10]^2, except those `skip` rejects.
pub(super) fn grid(skip: impl Fn(f64, f64) -> bool) -> Vec<(f64, f64, f64)> {
    (0..=20)
        .flat_map(|i| (0..=20).map(move |j| (i as f64 * 0.5, j as f64 * 0.5, 0.0)))
        .filter(|p| !skip(p.0, p.1))
        .collect()
}

pub(super) fn entries() -> Vec<Series> {
    vec![
        Series::measured("a long legend label", C, vec![]),
        Series::model("model", PALETTE[1], vec![]),
    ]
}

/// Text contents of every `<text>` element.
pub(crate) fn texts(svg: &str) -> Vec<String> {
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

pub(crate) fn is_integer_with_point_zero(t: &str) -> bool {
    t.strip_suffix(".0")
        .is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit() || c == '-'))
}
