//! The frame of a plot: title, axes with ticks and tick labels, light grid
//! lines and the axis titles, placed so no text collides (tick labels,
//! then the axis title below them; y tick labels sized to their text, the
//! y title beside them by its whole height, subscripts included;
//! [`super::text_clear`] checks it).

use super::geom::Rect;
use super::svg::{Anchor, Stroke, Svg};
use super::svg_text::{extent, width};
use super::Rgb;

pub const TICK_FONT_PX: f64 = 11.0;
pub const TITLE_FONT_PX: f64 = 15.0;
pub const AXIS_FONT_PX: f64 = 12.0;
/// Space above the plot for the title (or a little air without one).
pub fn top_px(title: &str) -> f64 {
    if title.is_empty() {
        12.0
    } else {
        34.0
    }
}
/// Below the plot: tick labels, then the x-axis title.
pub const BOTTOM_PX: f64 = 46.0;
pub const RIGHT_PX: f64 = 20.0;

/// Gap between the plot's left edge and the right end of a y tick label.
const TICK_GAP_PX: f64 = 7.0;
/// Air between the y tick labels and the y title, and left of the title.
const TITLE_AIR_PX: f64 = 4.0;

/// Width left of the plot for y tick labels and the y-axis title: the
/// labels, then the rotated title's whole height (its subscripts included,
/// which hang towards the labels) with air on both sides.
pub fn left_px(y_labels: &[String]) -> f64 {
    let w = y_labels
        .iter()
        .map(|l| width(l, TICK_FONT_PX))
        .fold(0.0, f64::max);
    let (above, below) = extent(AXIS_FONT_PX, true);
    w + TICK_GAP_PX + 2.0 * TITLE_AIR_PX + above + below
}

/// The y title's baseline x: its far side (ascent) `TITLE_AIR_PX` inside
/// the panel's left edge, so the subscripts keep clear of the labels.
fn y_title_x(plot_x0: f64, left: f64) -> f64 {
    plot_x0 - left + TITLE_AIR_PX + extent(AXIS_FONT_PX, true).0
}

/// Ticks in pixels along an axis: (position, label); empty label: minor.
pub struct Frame<'a> {
    pub title: &'a str,
    pub x_desc: &'a str,
    pub y_desc: &'a str,
    pub x_ticks: Vec<(f64, String)>,
    pub y_ticks: Vec<(f64, String)>,
    /// Grid lines at the labelled x ticks (off for category axes).
    pub x_grid: bool,
    /// Width from the panel's left edge to the plot (the y title goes there).
    pub left_of_plot: f64,
}

const AXIS: Rgb = Rgb(60, 60, 60);
const GRID: Rgb = Rgb(232, 232, 232);

impl Frame<'_> {
    /// Draws the frame around `plot`, the panel starting at `top`.
    pub fn draw(&self, svg: &mut Svg, plot: Rect, top: f64) {
        svg.group("frame");
        let grid = Stroke::solid(GRID, 1.0);
        for (y, l) in &self.y_ticks {
            if !l.is_empty() {
                svg.line((plot.x0, *y), (plot.x1, *y), grid);
            }
        }
        if self.x_grid {
            for (x, l) in &self.x_ticks {
                if !l.is_empty() {
                    svg.line((*x, plot.y0), (*x, plot.y1), grid);
                }
            }
        }
        let axis = Stroke::solid(AXIS, 1.0);
        svg.line((plot.x0, plot.y1), (plot.x1, plot.y1), axis);
        svg.line((plot.x0, plot.y0), (plot.x0, plot.y1), axis);
        for (x, l) in &self.x_ticks {
            let len = if l.is_empty() { 3.0 } else { 5.0 };
            svg.line((*x, plot.y1), (*x, plot.y1 + len), axis);
            if !l.is_empty() {
                svg.text(
                    (*x, plot.y1 + 18.0),
                    l,
                    TICK_FONT_PX,
                    Anchor::Middle,
                    false,
                    false,
                );
            }
        }
        for (y, l) in &self.y_ticks {
            let len = if l.is_empty() { 3.0 } else { 5.0 };
            svg.line((plot.x0 - len, *y), (plot.x0, *y), axis);
            if !l.is_empty() {
                svg.text(
                    (plot.x0 - TICK_GAP_PX, *y + 4.0),
                    l,
                    TICK_FONT_PX,
                    Anchor::End,
                    false,
                    false,
                );
            }
        }
        if !self.x_desc.is_empty() {
            svg.text(
                (0.5 * (plot.x0 + plot.x1), plot.y1 + 38.0),
                self.x_desc,
                AXIS_FONT_PX,
                Anchor::Middle,
                true,
                false,
            );
        }
        if !self.y_desc.is_empty() {
            svg.text(
                (
                    y_title_x(plot.x0, self.left_of_plot),
                    0.5 * (plot.y0 + plot.y1),
                ),
                self.y_desc,
                AXIS_FONT_PX,
                Anchor::Middle,
                true,
                true,
            );
        }
        if !self.title.is_empty() {
            svg.text(
                (0.5 * (plot.x0 + plot.x1), top + 22.0),
                self.title,
                TITLE_FONT_PX,
                Anchor::Middle,
                true,
                false,
            );
        }
        svg.end_group();
    }
}
