//! Text placed among the data: a point's label goes to the first spot
//! around its marker (a near ring of eight, then a far one) that stays
//! inside the plot and meets no other label, and of those the first that
//! meets no marker, bar or curve; notes are wrapped to the figure's width.
//! A label's box is the font model's ([`super::svg_text::extent`]: ascent
//! and descent), the box [`super::text_clear`] checks.

use super::geom::{Rect, Shape};
use super::svg::Anchor;
use super::svg_text::{extent, width};

pub const LABEL_FONT_PX: f64 = 11.0;
pub const NOTE_FONT_PX: f64 = 11.0;

/// A point's label: text, anchor point, and its box.
pub struct Label {
    pub text: String,
    pub at: (f64, f64),
    pub anchor: Anchor,
    pub bbox: Rect,
}

pub fn place_label(
    marker_r: f64,
    text: &str,
    p: (f64, f64),
    plot: Rect,
    avoid: &[Shape],
    placed: &[Label],
) -> Label {
    let w = width(text, LABEL_FONT_PX);
    let h = LABEL_FONT_PX;
    let (above, below) = extent(LABEL_FONT_PX, false);
    // (x of the text's left edge, baseline y, anchor) at a distance `d`
    // from the marker's centre.
    let ring = |d: f64| {
        [
            (p.0 + d, p.1 + 3.5, Anchor::Start),
            (p.0 + d - 2.0, p.1 - d, Anchor::Start),
            (p.0 + d - 2.0, p.1 + d + h - 2.0, Anchor::Start),
            (p.0 - d - w, p.1 + 3.5, Anchor::End),
            (p.0 - d - w + 2.0, p.1 - d, Anchor::End),
            (p.0 - d - w + 2.0, p.1 + d + h - 2.0, Anchor::End),
            (p.0 - 0.5 * w, p.1 - d - 1.0, Anchor::Middle),
            (p.0 - 0.5 * w, p.1 + d + h, Anchor::Middle),
        ]
    };
    let near = marker_r + 3.0;
    let make = |(left, base, anchor): (f64, f64, Anchor)| {
        let bbox = Rect::new(left, base - above, w, above + below);
        let at = match anchor {
            Anchor::Start => (left, base),
            Anchor::End => (left + w, base),
            Anchor::Middle => (left + 0.5 * w, base),
        };
        Label {
            text: text.to_string(),
            at,
            anchor,
            bbox,
        }
    };
    // Leaving the plot is worst, then running into another label (text on
    // text is unreadable; the checker rejects it), then each marker, bar
    // or curve met.
    let conflicts = |l: &Label| {
        let inside = l.bbox.x0 >= plot.x0
            && l.bbox.x1 <= plot.x1
            && l.bbox.y0 >= plot.y0
            && l.bbox.y1 <= plot.y1;
        usize::from(!inside) * 1_000_000
            + 1_000 * placed.iter().filter(|o| o.bbox.overlaps(&l.bbox)).count()
            + avoid.iter().filter(|s| l.bbox.meets(s)).count()
    };
    ring(near)
        .into_iter()
        .chain(ring(near + h))
        .map(make)
        .min_by_key(conflicts)
        .expect("sixteen candidates")
}

/// `text` broken at spaces into lines at most `max_px` wide.
pub fn wrap(text: &str, max_px: f64) -> Vec<String> {
    let mut lines = vec![String::new()];
    for word in text.split(' ') {
        let last = lines.last_mut().expect("never empty");
        let candidate = if last.is_empty() {
            word.to_string()
        } else {
            format!("{last} {word}")
        };
        if width(&candidate, NOTE_FONT_PX) > max_px && !last.is_empty() {
            lines.push(word.to_string());
        } else {
            *last = candidate;
        }
    }
    lines
}
