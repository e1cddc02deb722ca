//! One data series of a chart: measured points (filled markers with error
//! bars), the model at the measured cases (hollow markers) or a curve, and
//! the builder methods for what a publication figure adds (per-point
//! labels, horizontal error bars, dashed lines).

use super::Rgb;

/// One data series of a chart.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text; empty: not in the legend.
    pub label: String,
    pub color: Rgb,
    /// (x, y, vertical error half-width)
    pub points: Vec<(f64, f64, f64)>,
    /// Drawn as a line instead of markers.
    pub line: bool,
    /// Hollow markers (model) instead of filled ones (measured).
    pub hollow: bool,
    /// Text next to each point (empty strings: none).
    pub labels: Vec<String>,
    /// Each point's name where a note on the figure must name it (a bar
    /// its marker hides), when it carries no label: the same case is then
    /// named the same in every series.
    pub names: Vec<String>,
    /// Horizontal error half-widths, one per point (empty: none).
    pub x_err: Vec<f64>,
    /// Dashed line (with `line`).
    pub dashed: bool,
    /// Markers, bars or line drawn this fraction of the plot's width to
    /// the right of their x (negative: left), so models at the same x can
    /// be told apart; 0: at their x.
    pub dodge: f64,
}

impl Series {
    fn new(label: impl Into<String>, color: Rgb, points: Vec<(f64, f64, f64)>) -> Self {
        Self {
            label: label.into(),
            color,
            points,
            line: false,
            hollow: false,
            labels: Vec::new(),
            names: Vec::new(),
            x_err: Vec::new(),
            dashed: false,
            dodge: 0.0,
        }
    }

    /// Measured points: filled markers with their error bars.
    pub fn measured(label: impl Into<String>, color: Rgb, points: Vec<(f64, f64, f64)>) -> Self {
        Self::new(label, color, points)
    }

    /// The model at the measured cases: hollow markers.
    pub fn model(label: impl Into<String>, color: Rgb, points: Vec<(f64, f64, f64)>) -> Self {
        Self {
            hollow: true,
            ..Self::new(label, color, points)
        }
    }

    /// A model curve: a line through `points` (their error column is ignored).
    pub fn curve(label: impl Into<String>, color: Rgb, points: Vec<(f64, f64, f64)>) -> Self {
        Self {
            line: true,
            ..Self::new(label, color, points)
        }
    }

    /// Text next to each point (e.g. the case ids).
    pub fn labels(mut self, labels: Vec<String>) -> Self {
        self.labels = labels;
        self
    }

    /// Names of the points for the figure's notes, not drawn (see [`Self::names`]).
    pub fn names(mut self, names: Vec<String>) -> Self {
        self.names = names;
        self
    }

    /// Horizontal error half-widths, one per point.
    pub fn x_errors(mut self, half_widths: Vec<f64>) -> Self {
        self.x_err = half_widths;
        self
    }

    /// A dashed line (reference values, alternative models).
    pub fn dashed(mut self) -> Self {
        self.dashed = true;
        self
    }

    /// Markers, bars or line shifted by `fraction` of the plot's width in x
    /// (the caption must say so: the x read off is then off by it).
    pub fn dodged(mut self, fraction: f64) -> Self {
        self.dodge = fraction;
        self
    }

    pub fn color(mut self, color: Rgb) -> Self {
        self.color = color;
        self
    }
}
