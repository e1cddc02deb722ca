//! The legend: its entries, its size, and where it goes. It is placed at
//! the first inside position (corners first, then edge midpoints, then
//! anywhere along the plot's edges) whose box,
//! grown by a margin, meets no marker, error bar, curve segment, bar or
//! point label; when none is free it goes outside, right of the plot.

use super::geom::{Rect, Shape};
use super::svg::{rgb, Anchor, Stroke, Svg};
use super::svg_text::{notation, width};
use super::Rgb;

/// What an entry shows before its text.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Glyph {
    Marker {
        hollow: bool,
    },
    Line {
        dashed: bool,
    },
    /// A horizontal error bar (e.g. a measured CI on the x axis).
    HBar,
    /// A vertical error bar.
    VBar,
    /// A filled bar (bar charts).
    Bar,
}

#[derive(Debug, Clone)]
pub struct Entry {
    pub glyph: Glyph,
    pub color: Rgb,
    pub label: String,
}

const FONT_PX: f64 = 11.0;
const ROW_PX: f64 = 16.0;
const GLYPH_PX: f64 = 22.0;
const PAD_PX: f64 = 7.0;
/// Clearance kept between the legend box and anything drawn.
pub const MARGIN_PX: f64 = 4.0;
/// Distance of an inside legend from the plot's frame.
const INSET_PX: f64 = 5.0;

pub fn size(entries: &[Entry]) -> (f64, f64) {
    let text = entries
        .iter()
        .map(|e| width(&notation(&e.label), FONT_PX))
        .fold(0.0, f64::max);
    (
        2.0 * PAD_PX + GLYPH_PX + 6.0 + text,
        2.0 * PAD_PX - 4.0 + ROW_PX * entries.len() as f64,
    )
}

/// The first inside position free of `obstacles`, if any.
pub fn place_inside(entries: &[Entry], plot: Rect, obstacles: &[Shape]) -> Option<Rect> {
    let (w, h) = size(entries);
    let (l, r) = (plot.x0 + INSET_PX, plot.x1 - INSET_PX - w);
    let (t, b) = (plot.y0 + INSET_PX, plot.y1 - INSET_PX - h);
    let (cx, cy) = (0.5 * (l + r), 0.5 * (t + b));
    if r < l || b < t {
        return None;
    }
    // Corners, then edge midpoints, then anywhere along the edges.
    let mut spots = vec![
        (r, t),
        (l, t),
        (r, b),
        (l, b),
        (cx, t),
        (cx, b),
        (r, cy),
        (l, cy),
    ];
    let steps = |a: f64, z: f64| {
        let n = ((z - a) / 4.0).floor().max(0.0) as usize;
        (0..=n).map(move |i| a + 4.0 * i as f64)
    };
    spots.extend(steps(t, b).flat_map(|y| [(r, y), (l, y)]));
    spots.extend(steps(l, r).flat_map(|x| [(x, t), (x, b)]));
    spots
        .into_iter()
        .map(|(x, y)| Rect::new(x, y, w, h))
        .find(|box_| {
            let grown = box_.inflate(MARGIN_PX);
            !obstacles.iter().any(|s| grown.meets(s))
        })
}

pub fn draw(svg: &mut Svg, entries: &[Entry], at: Rect) {
    svg.group("legend");
    svg.rect(at.x0, at.y0, at.width(), at.height(), "white", Some("#999"));
    for (i, e) in entries.iter().enumerate() {
        let y = at.y0 + PAD_PX + ROW_PX * (i as f64 + 0.5) - 2.0;
        let (x0, x1) = (at.x0 + PAD_PX, at.x0 + PAD_PX + GLYPH_PX);
        let xm = 0.5 * (x0 + x1);
        match e.glyph {
            Glyph::Marker { hollow } => svg.circle((xm, y), 4.0, e.color, hollow),
            Glyph::Line { dashed } => svg.line(
                (x0, y),
                (x1, y),
                Stroke {
                    dashed,
                    ..Stroke::solid(e.color, 2.0)
                },
            ),
            Glyph::HBar => {
                let s = Stroke::solid(e.color, 1.2);
                svg.line((x0 + 2.0, y), (x1 - 2.0, y), s);
                svg.line((x0 + 2.0, y - 3.0), (x0 + 2.0, y + 3.0), s);
                svg.line((x1 - 2.0, y - 3.0), (x1 - 2.0, y + 3.0), s);
            }
            Glyph::VBar => {
                let s = Stroke::solid(e.color, 1.2);
                svg.line((xm, y - 6.0), (xm, y + 6.0), s);
                svg.line((xm - 3.0, y - 6.0), (xm + 3.0, y - 6.0), s);
                svg.line((xm - 3.0, y + 6.0), (xm + 3.0, y + 6.0), s);
            }
            Glyph::Bar => svg.rect(x0 + 4.0, y - 5.0, GLYPH_PX - 8.0, 10.0, &rgb(e.color), None),
        }
        svg.text(
            (x1 + 6.0, y + 4.0),
            &e.label,
            FONT_PX,
            Anchor::Start,
            true,
            false,
        );
    }
    svg.end_group();
}
