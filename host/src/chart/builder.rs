//! Scatter, curve and parity charts: the [`Chart`] builder lays out one
//! panel (axes, data, point labels, a legend that covers no data, notes)
//! and renders it alone or stacked with others sharing a width.

use super::frame::{left_px, top_px, BOTTOM_PX};
use super::geom::Rect;
use super::legend::{Entry, Glyph};
use super::panel::draw_panel;
use super::series::Series;
use super::svg::{Anchor, Svg};
use super::ticks::Axis;
use super::Rgb;
use super::{ChartError, PlotResult};

pub(super) const REFERENCE: Rgb = Rgb(110, 110, 110);

/// A horizontal reference line (an observed value, zero).
#[derive(Debug, Clone)]
pub(super) struct Reference {
    pub(super) y: f64,
    pub(super) label: String,
    pub(super) color: Rgb,
}

/// One chart panel, configured by builder methods, drawn by [`Chart::render`].
#[derive(Debug, Clone)]
pub struct Chart {
    pub(super) title: String,
    pub(super) x_desc: String,
    pub(super) y_desc: String,
    pub(super) size: (f64, f64),
    pub(super) log_x: bool,
    pub(super) log_y: bool,
    pub(super) diagonal: bool,
    pub(super) include_zero_y: bool,
    pub(super) x_range: Option<(f64, f64)>,
    pub(super) notes: Vec<String>,
    pub(super) references: Vec<Reference>,
    pub(super) entries: Vec<Entry>,
    /// Draw the legend and the hidden-error-bar note (false: a panel of a
    /// figure whose legend and notes another panel or the caption carries).
    pub(super) legend: bool,
    /// The note naming error bars hidden by their markers (false: the
    /// figure's caption says it once for every panel).
    pub(super) hidden_note: bool,
}

impl Chart {
    /// A 560 x 380 linear chart; titles may use code notation (`Omega_b`).
    pub fn new(title: &str, x_desc: &str, y_desc: &str) -> Self {
        Self {
            title: title.into(),
            x_desc: x_desc.into(),
            y_desc: y_desc.into(),
            size: (560.0, 380.0),
            log_x: false,
            log_y: false,
            diagonal: false,
            include_zero_y: false,
            x_range: None,
            notes: Vec::new(),
            references: Vec::new(),
            entries: Vec::new(),
            legend: true,
            hidden_note: true,
        }
    }

    /// No note on error bars hidden by their markers (the caption says it).
    pub fn without_hidden_note(mut self) -> Self {
        self.hidden_note = false;
        self
    }

    /// No legend: one panel of a figure that carries it once.
    pub fn without_legend(mut self) -> Self {
        self.legend = false;
        self
    }

    /// Size of the panel before any outside legend or notes are added.
    pub fn size(mut self, w: u32, h: u32) -> Self {
        self.size = (w as f64, h as f64);
        self
    }

    pub fn log_x(mut self) -> Self {
        self.log_x = true;
        self
    }

    pub fn log_y(mut self) -> Self {
        self.log_y = true;
        self
    }

    /// Parity: the same range on both axes and the line y = x.
    pub fn diagonal(mut self) -> Self {
        self.diagonal = true;
        self
    }

    pub fn include_zero_y(mut self) -> Self {
        self.include_zero_y = true;
        self
    }

    /// Fixes the x range (panels sharing a time axis).
    pub fn x_range(mut self, lo: f64, hi: f64) -> Self {
        self.x_range = Some((lo, hi));
        self
    }

    /// A line of text under the figure.
    pub fn note(mut self, text: impl Into<String>) -> Self {
        self.notes.push(text.into());
        self
    }

    /// A dashed horizontal reference line at `y` (in the legend when labelled).
    pub fn hline(mut self, y: f64, label: impl Into<String>, color: Rgb) -> Self {
        self.references.push(Reference {
            y,
            label: label.into(),
            color,
        });
        self
    }

    /// A zero line (residual plots).
    pub fn zero_line(self) -> Self {
        self.hline(0.0, "", REFERENCE)
    }

    /// A legend entry not tied to one series (what bars or lines mean).
    pub fn legend_entry(mut self, glyph: Glyph, color: Rgb, label: impl Into<String>) -> Self {
        self.entries.push(Entry {
            glyph,
            color,
            label: label.into(),
        });
        self
    }

    /// The chart as a standalone SVG document.
    pub fn render(&self, series: &[Series]) -> PlotResult {
        stack("", &[(self.clone(), series.to_vec())])
    }
}

/// The legend `chart` would draw for `series`, alone: for a figure of
/// panels that carries one legend for all of them, drawn beside the grid
/// instead of growing one panel (which the page then shrinks to fit its
/// column).
pub fn legend_only(chart: &Chart, series: &[Series]) -> PlotResult {
    let entries = super::panel::entries_of(chart, series);
    if entries.is_empty() {
        return Err(ChartError::NoLegendEntries);
    }
    let (w, h) = super::legend::size(&entries);
    let mut svg = Svg::default();
    super::legend::draw(&mut svg, &entries, super::geom::Rect::new(1.0, 1.0, w, h));
    Ok(svg.finish((w + 2.0).ceil(), (h + 2.0).ceil()))
}

/// Panels stacked top to bottom under one title, each laid out on its own.
pub fn stack(title: &str, panels: &[(Chart, Vec<Series>)]) -> PlotResult {
    if panels.is_empty() {
        return Err(ChartError::NoPanels);
    }
    let mut svg = Svg::default();
    let mut y = if title.is_empty() { 0.0 } else { 28.0 };
    let mut w: f64 = 0.0;
    // Panels share one left edge so stacked time axes line up.
    let left = panels
        .iter()
        .map(|(c, s)| y_ticks_and_left(c, s).1)
        .fold(0.0, f64::max);
    for (chart, series) in panels {
        let (pw, ph) = draw_panel(&mut svg, chart, series, (0.0, y), left)?;
        w = w.max(pw);
        y += ph;
    }
    if !title.is_empty() {
        svg.group("frame");
        svg.text((0.5 * w, 20.0), title, 16.0, Anchor::Middle, true, false);
        svg.end_group();
    }
    Ok(svg.finish(w.ceil(), y.ceil()))
}

/// Pixel mapping of one panel.
pub(super) struct Map {
    pub(super) plot: Rect,
    pub(super) x: Axis,
    pub(super) y: Axis,
}

impl Map {
    pub(super) fn px(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        Some((
            self.plot.x0 + self.x.frac(x)? * self.plot.width(),
            self.plot.y1 - self.y.frac(y)? * self.plot.height(),
        ))
    }
}

pub(super) fn axes(c: &Chart, series: &[Series]) -> (Axis, Axis) {
    let mut xs = Vec::new();
    let mut ys = Vec::new();
    for s in series {
        for (i, p) in s.points.iter().enumerate() {
            let (ey, ex) = if s.line {
                (0.0, 0.0)
            } else {
                (p.2, s.x_err.get(i).copied().unwrap_or(0.0))
            };
            // The point itself too: on a log axis a bar reaching below
            // zero is dropped, and the point went with it (a lab's tail-6
            // at 0.05 ± 0.13 mm/s was drawn under the parity plot's axis).
            xs.extend([p.0 - ex, p.0, p.0 + ex]);
            ys.extend([p.1 - ey, p.1, p.1 + ey]);
        }
    }
    ys.extend(c.references.iter().map(|r| r.y));
    if c.diagonal {
        let all: Vec<f64> = xs.iter().chain(&ys).copied().collect();
        let log = c.log_x || c.log_y;
        let a = Axis::fit(all.into_iter(), log, !log);
        return (a, a);
    }
    let x = match c.x_range {
        Some((lo, hi)) => Axis {
            lo,
            hi,
            log: c.log_x,
        },
        None => Axis::fit(xs.into_iter(), c.log_x, false),
    };
    (x, Axis::fit(ys.into_iter(), c.log_y, c.include_zero_y))
}

/// Pixels per x tick and per y tick a reader needs to take them in.
pub(super) const X_TICK_PX: f64 = 80.0;
const Y_TICK_PX: f64 = 50.0;

/// The y ticks of a panel and the width left of its plot they need.
pub(super) fn y_ticks_and_left(c: &Chart, series: &[Series]) -> (Vec<(f64, String)>, f64) {
    let (_, y) = axes(c, series);
    let ticks = y.ticks(((c.size.1 - top_px(&c.title) - BOTTOM_PX) / Y_TICK_PX).max(4.0));
    let left = left_px(&ticks.iter().map(|t| t.1.clone()).collect::<Vec<_>>());
    (ticks, left)
}
