//! A minimal SVG writer: float coordinates (no pixel rounding, so a
//! slowly drifting line stays smooth), named groups (`frame`, `data`,
//! `labels`, `legend`, `notes`) that the legend checker reads back, and
//! text with real subscripts.

use super::svg_text::{notation, rich};
use super::Rgb;
use std::fmt::Write as _;

pub fn rgb(c: Rgb) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0, c.1, c.2)
}

/// How text is anchored horizontally.
#[derive(Clone, Copy)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

/// A line's look.
#[derive(Clone, Copy)]
pub struct Stroke {
    pub color: Rgb,
    pub width: f64,
    pub dashed: bool,
    pub opacity: f64,
}

impl Stroke {
    pub fn solid(color: Rgb, width: f64) -> Self {
        Self {
            color,
            width,
            dashed: false,
            opacity: 1.0,
        }
    }

    fn attrs(&self) -> String {
        let mut s = format!(
            "fill=\"none\" stroke=\"{}\" stroke-width=\"{}\"",
            rgb(self.color),
            self.width
        );
        if self.dashed {
            let _ = write!(
                s,
                " stroke-dasharray=\"{} {}\"",
                3.0 * self.width.max(1.5),
                2.0 * self.width.max(1.5)
            );
        }
        if self.opacity < 1.0 {
            let _ = write!(s, " stroke-opacity=\"{}\"", self.opacity);
        }
        s
    }
}

fn n(v: f64) -> String {
    let s = format!("{v:.1}");
    s.strip_suffix(".0").map(str::to_string).unwrap_or(s)
}

/// The body of an SVG document, written element by element.
#[derive(Default)]
pub struct Svg {
    body: String,
}

impl Svg {
    pub fn group(&mut self, class: &str) {
        let _ = writeln!(self.body, "<g class=\"{class}\">");
    }

    pub fn end_group(&mut self) {
        self.body.push_str("</g>\n");
    }

    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), s: Stroke) {
        let _ = writeln!(
            self.body,
            "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" {}/>",
            n(a.0),
            n(a.1),
            n(b.0),
            n(b.1),
            s.attrs()
        );
    }

    pub fn polyline(&mut self, pts: &[(f64, f64)], s: Stroke) {
        let mut p = String::with_capacity(12 * pts.len());
        let mut last = String::new();
        for (x, y) in pts {
            let xy = format!("{},{}", n(*x), n(*y));
            if xy != last {
                p.push_str(&xy);
                p.push(' ');
                last = xy;
            }
        }
        let _ = writeln!(
            self.body,
            "<polyline points=\"{}\" stroke-linejoin=\"round\" {}/>",
            p.trim_end(),
            s.attrs()
        );
    }

    pub fn circle(&mut self, c: (f64, f64), r: f64, color: Rgb, hollow: bool) {
        let paint = if hollow {
            format!(
                "fill=\"white\" stroke=\"{}\" stroke-width=\"1.6\"",
                rgb(color)
            )
        } else {
            format!(
                "fill=\"{}\" stroke=\"white\" stroke-width=\"0.6\"",
                rgb(color)
            )
        };
        let _ = writeln!(
            self.body,
            "<circle cx=\"{}\" cy=\"{}\" r=\"{}\" {paint}/>",
            n(c.0),
            n(c.1),
            n(r)
        );
    }

    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: &str, stroke: Option<&str>) {
        let stroke = stroke.map_or(String::new(), |s| {
            format!(" stroke=\"{s}\" stroke-width=\"0.8\"")
        });
        let _ = writeln!(
            self.body,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{fill}\"{stroke}/>",
            n(x),
            n(y),
            n(w),
            n(h)
        );
    }

    /// Text at baseline point `p`; `physics` applies [`notation`] first;
    /// `rotate` turns it by -90 degrees about `p` (y-axis titles).
    pub fn text(
        &mut self,
        p: (f64, f64),
        s: &str,
        size: f64,
        anchor: Anchor,
        physics: bool,
        rotate: bool,
    ) {
        let anchor = match anchor {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        };
        let rot = if rotate {
            format!(" transform=\"rotate(-90 {} {})\"", n(p.0), n(p.1))
        } else {
            String::new()
        };
        let s = if physics { notation(s) } else { s.to_string() };
        let _ = writeln!(
            self.body,
            "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{anchor}\"{rot}>{}</text>",
            n(p.0),
            n(p.1),
            n(size),
            rich(&s)
        );
    }

    /// The whole document, `w` x `h` pixels.
    pub fn finish(self, w: f64, h: f64) -> String {
        format!(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\" font-family=\"'DejaVu Sans', 'Liberation Sans', Helvetica, Arial, sans-serif\" fill=\"#222\">\n<rect x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\" fill=\"white\"/>\n{}</svg>\n",
            self.body,
            w = n(w),
            h = n(h)
        )
    }
}
