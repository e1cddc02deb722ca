//! The chart engine of the report, the simulation's figures and the run
//! log's: SVG written directly (float coordinates, real
//! subscripts, physics notation), with legends placed where they cover no
//! data ([`legend_clear`] checks it), sensible ticks (powers of ten on log
//! axes), per-point labels, error bars in x and y, and a note on the figure
//! when error bars are smaller than their markers.
//!
//! Written by hand rather than drawn with plotters because plotters rounds
//! every coordinate to whole pixels (a 1 mHz controller ripple on a flat
//! line became a sawtooth in the sim figure), cannot write SVG subscripts,
//! and does not mark which elements form the legend, which the
//! clear-legend check must know.
//!
//! The simple entry points [`chart`] and [`steps`] stay; [`Chart`] and
//! [`Bars`] are the builders behind them.

mod bars;
mod builder;
mod check;
mod colour;
mod frame;
mod geom;
mod labels;
mod legend;
mod panel;
mod series;
mod svg;
mod svg_text;
mod ticks;

#[cfg(test)]
pub(crate) mod tests;

pub use bars::{steps, Bars};
pub use builder::{legend_only, stack, Chart};
pub use check::{legend_clear, text_clear};
pub use colour::Rgb;
pub use legend::Glyph;
pub use series::Series;
pub use svg_text::{
    escape as escape_text, extent as text_extent, has_subscript, notation, runs as notation_runs,
    unit, width as text_width,
};
pub use ticks::Axis;

/// An SVG figure, or why it cannot be drawn.
pub type PlotResult = Result<String, ChartError>;

/// Why a figure cannot be drawn, its title as data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ChartError {
    /// A bar chart whose plot area is smaller than its labels leave room for.
    #[error("bar chart '{title}' is too small to draw")]
    BarsTooSmall { title: String },
    /// A panel whose plot area is smaller than its axes leave room for.
    #[error("chart '{title}' is too small to draw ({width_px} x {height_px} px)")]
    PanelTooSmall {
        title: String,
        width_px: f64,
        height_px: f64,
    },
    #[error("no legend entries")]
    NoLegendEntries,
    #[error("no panels to draw")]
    NoPanels,
    /// A figure of panels without one panel to take its legend from.
    #[error("no panel")]
    NoPanel,
    /// Every value of the figure's `what` (e.g. "step") is NaN or infinite.
    #[error("no {what} has a finite value")]
    NoFiniteValue { what: &'static str },
    /// A figure of a feature (`crate::data::quantities`) this build does not know.
    #[error("unknown feature {id}")]
    UnknownFeature { id: String },
}

pub const PALETTE: [Rgb; 6] = [
    Rgb(31, 119, 180),
    Rgb(214, 39, 40),
    Rgb(44, 160, 44),
    Rgb(148, 103, 189),
    Rgb(255, 127, 14),
    Rgb(23, 190, 207),
];

/// A scatter/line chart; `diagonal` draws y = x (parity plots).
pub fn chart(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
    diagonal: bool,
) -> PlotResult {
    let c = Chart::new(title, x_desc, y_desc);
    if diagonal { c.diagonal() } else { c }.render(series)
}
