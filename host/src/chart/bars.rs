//! Bar charts of one value per step ("watch the error fall"): a log axis
//! when the values span more than a decade, else a linear one from zero;
//! each bar's value written on it; optional reference lines (a noise floor).

use super::frame::{left_px, top_px, Frame, BOTTOM_PX, RIGHT_PX};
use super::geom::{Rect, Shape};
use super::labels::wrap;
use super::legend::{self, Entry, Glyph};
use super::svg::{rgb, Anchor, Stroke, Svg};
use super::svg_text::{power_of_ten, width};
use super::ticks::Axis;
use super::Rgb;
use super::{ChartError, PlotResult, PALETTE};
use crate::format::fmt_sig;

const CATEGORY_FONT_PX: f64 = 11.0;
const VALUE_FONT_PX: f64 = 11.0;

/// A bar chart, configured by builder methods.
#[derive(Debug, Clone)]
pub struct Bars {
    title: String,
    y_desc: String,
    size: (f64, f64),
    references: Vec<(f64, String, Rgb)>,
}

impl Bars {
    pub fn new(title: &str, y_desc: &str) -> Self {
        Self {
            title: title.into(),
            y_desc: y_desc.into(),
            size: (560.0, 380.0),
            references: Vec::new(),
        }
    }

    pub fn size(mut self, w: u32, h: u32) -> Self {
        self.size = (w as f64, h as f64);
        self
    }

    /// A dashed horizontal line at `y`, named in the legend.
    pub fn reference(mut self, y: f64, label: impl Into<String>, color: Rgb) -> Self {
        self.references.push((y, label.into(), color));
        self
    }

    /// One bar per label; non-finite values (and non-positive ones on a
    /// log axis) are left out.
    pub fn render(&self, labels: &[String], values: &[f64]) -> PlotResult {
        let shown = values
            .iter()
            .chain(self.references.iter().map(|r| &r.0))
            .copied();
        let log = Axis::spans_decade(shown.clone());
        let y = Axis::fit(shown, log, !log);
        let y_ticks = y.ticks(6.0);
        let left = left_px(&y_ticks.iter().map(|t| t.1.clone()).collect::<Vec<_>>());
        let (w, h) = self.size;
        let n = labels.len().max(1);
        let slot_guess = (w - left - RIGHT_PX) / n as f64;
        let cats: Vec<Vec<String>> = labels
            .iter()
            .map(|l| wrap_category(l, slot_guess - 4.0))
            .collect();
        let extra_rows = cats
            .iter()
            .map(Vec::len)
            .max()
            .unwrap_or(1)
            .saturating_sub(1);
        let top = top_px(&self.title);
        let bottom = BOTTOM_PX - 14.0 + 12.0 * extra_rows as f64;
        let plot = Rect::new(left, top, w - left - RIGHT_PX, h - top - bottom);
        if plot.width() < 60.0 || plot.height() < 40.0 {
            return Err(ChartError::BarsTooSmall {
                title: self.title.clone(),
            });
        }
        let slot = plot.width() / n as f64;
        let py = |v: f64| y.frac(v).map(|f| plot.y1 - f * plot.height());
        let base = if log {
            plot.y1
        } else {
            py(0.0).unwrap_or(plot.y1)
        };

        let mut svg = Svg::default();
        let y_px: Vec<(f64, String)> = y_ticks
            .iter()
            .filter_map(|(v, l)| Some((py(*v)?, l.clone())))
            .chain(
                y.minor_ticks()
                    .into_iter()
                    .filter_map(|v| Some((py(v)?, String::new()))),
            )
            .collect();
        Frame {
            title: &self.title,
            x_desc: "",
            y_desc: &self.y_desc,
            x_ticks: Vec::new(),
            y_ticks: y_px,
            x_grid: false,
            left_of_plot: left,
        }
        .draw(&mut svg, plot, 0.0);

        let mut obstacles = Vec::new();
        let mut texts = Vec::new();
        svg.group("data");
        for (i, v) in values.iter().enumerate() {
            let Some(top_y) = py(*v) else { continue };
            let bw = (0.64 * slot).min(90.0);
            let x0 = plot.x0 + slot * (i as f64 + 0.5) - 0.5 * bw;
            let r = Rect::new(x0, top_y.min(base), bw, (base - top_y).abs());
            svg.rect(r.x0, r.y0, r.width(), r.height(), &rgb(PALETTE[0]), None);
            obstacles.push(Shape::Box(r));
            let text = value_label(*v);
            let at = (x0 + 0.5 * bw, r.y0 - 4.0);
            let tw = width(&text, VALUE_FONT_PX);
            obstacles.push(Shape::Box(Rect::new(at.0 - 0.5 * tw, at.1 - 9.0, tw, 10.0)));
            texts.push((at, text));
        }
        for (v, _, color) in &self.references {
            let Some(yv) = py(*v) else { continue };
            svg.line(
                (plot.x0, yv),
                (plot.x1, yv),
                Stroke {
                    dashed: true,
                    ..Stroke::solid(*color, 1.6)
                },
            );
            obstacles.push(Shape::Segment {
                a: (plot.x0, yv),
                b: (plot.x1, yv),
            });
        }
        svg.end_group();
        svg.group("labels");
        for (at, text) in &texts {
            svg.text(*at, text, VALUE_FONT_PX, Anchor::Middle, false, false);
        }
        for (i, lines) in cats.iter().enumerate() {
            let x = plot.x0 + slot * (i as f64 + 0.5);
            for (k, l) in lines.iter().enumerate() {
                svg.text(
                    (x, plot.y1 + 15.0 + 12.0 * k as f64),
                    l,
                    CATEGORY_FONT_PX,
                    Anchor::Middle,
                    true,
                    false,
                );
            }
        }
        svg.end_group();
        let entries: Vec<Entry> = self
            .references
            .iter()
            .filter(|r| !r.1.is_empty())
            .map(|r| Entry {
                glyph: Glyph::Line { dashed: true },
                color: r.2,
                label: r.1.clone(),
            })
            .collect();
        let mut canvas_w = w;
        if !entries.is_empty() {
            let at = legend::place_inside(&entries, plot, &obstacles).unwrap_or_else(|| {
                let (lw, lh) = legend::size(&entries);
                Rect::new(plot.x1 + 14.0, plot.y0, lw, lh)
            });
            canvas_w = canvas_w.max(at.x1 + 8.0);
            legend::draw(&mut svg, &entries, at);
        }
        Ok(svg.finish(canvas_w.ceil(), h))
    }
}

/// A category label in lines that fit `max_px` (breaking at spaces, and
/// before `+`, `:` or `,` inside long names).
fn wrap_category(label: &str, max_px: f64) -> Vec<String> {
    let spaced = label.replace(':', " :").replace(',', ", ");
    let lines = wrap(&spaced, max_px);
    lines
        .into_iter()
        .map(|l| l.replace(" :", ":"))
        .take(4)
        .collect()
}

/// A bar's value: three significant figures, `m×10ⁿ` when large or small.
fn value_label(v: f64) -> String {
    let s = fmt_sig(v, 3);
    match s.split_once('e') {
        Some((m, e)) => match e.parse::<i32>() {
            Ok(e) => format!("{m}×{}", power_of_ten(e)),
            Err(_) => s,
        },
        None => s,
    }
}

/// Bars of one value per step, for "watch the error fall".
pub fn steps(title: &str, y_desc: &str, labels: &[String], values: &[f64]) -> PlotResult {
    Bars::new(title, y_desc).render(labels, values)
}
