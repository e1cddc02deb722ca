//! SVG charts of the report (plotters, SVG backend): scatter with error
//! bars and model curves, parity, residual-vs-feature, and the error-falls
//! chart.

use plotters::prelude::*;

pub type PlotResult = Result<String, String>;

/// One data series of a chart.
pub struct Series {
    pub label: String,
    pub color: RGBColor,
    /// (x, y, error half-width)
    pub points: Vec<(f64, f64, f64)>,
    /// Drawn as a line instead of markers.
    pub line: bool,
    /// Hollow markers (model) instead of filled ones (measured).
    pub hollow: bool,
}

impl Series {
    /// Measured points: filled markers with their error bars.
    pub fn measured(
        label: impl Into<String>,
        color: RGBColor,
        points: Vec<(f64, f64, f64)>,
    ) -> Self {
        Self {
            label: label.into(),
            color,
            points,
            line: false,
            hollow: false,
        }
    }

    /// The model at the measured cases: hollow markers.
    pub fn model(label: impl Into<String>, color: RGBColor, points: Vec<(f64, f64, f64)>) -> Self {
        Self {
            label: label.into(),
            color,
            points,
            line: false,
            hollow: true,
        }
    }

    /// A model curve: a line through `points` (their error column is ignored).
    pub fn curve(label: impl Into<String>, color: RGBColor, points: Vec<(f64, f64, f64)>) -> Self {
        Self {
            label: label.into(),
            color,
            points,
            line: true,
            hollow: false,
        }
    }
}

pub const PALETTE: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(255, 127, 14),
    RGBColor(23, 190, 207),
];

fn range(values: impl Iterator<Item = f64>, include_zero: bool) -> (f64, f64) {
    let (mut lo, mut hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(v), b.max(v)));
    if lo > hi {
        return (0.0, 1.0);
    }
    if include_zero {
        lo = lo.min(0.0);
        hi = hi.max(0.0);
    }
    let pad = 0.08 * (hi - lo).max(1e-12 * hi.abs().max(1.0));
    (lo - pad, hi + pad)
}

/// A scatter/line chart; `diagonal` draws y = x (parity plots).
pub fn chart(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
    diagonal: bool,
) -> PlotResult {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (560, 380)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let xs = series.iter().flat_map(|s| s.points.iter().map(|p| p.0));
        let (x0, x1) = range(
            xs.chain(if diagonal {
                series
                    .iter()
                    .flat_map(|s| s.points.iter().map(|p| p.1))
                    .collect::<Vec<_>>()
            } else {
                vec![]
            }),
            diagonal,
        );
        let ys = series
            .iter()
            .flat_map(|s| s.points.iter().flat_map(|p| [p.1 - p.2, p.1 + p.2]));
        let (y0, y1) = if diagonal { (x0, x1) } else { range(ys, false) };
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 17))
            .margin(12)
            .x_label_area_size(42)
            .y_label_area_size(62)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| e.to_string())?;
        c.configure_mesh()
            .x_desc(x_desc)
            .y_desc(y_desc)
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(|e| e.to_string())?;
        if diagonal {
            c.draw_series(LineSeries::new([(x0, x0), (x1, x1)], BLACK.mix(0.4)))
                .map_err(|e| e.to_string())?;
        }
        for s in series {
            let color = s.color;
            if s.line {
                let drawn = c
                    .draw_series(LineSeries::new(
                        s.points.iter().map(|p| (p.0, p.1)),
                        color.stroke_width(2),
                    ))
                    .map_err(|e| e.to_string())?;
                if !s.label.is_empty() {
                    drawn.label(s.label.clone()).legend(move |(x, y)| {
                        PathElement::new([(x, y), (x + 16, y)], color.stroke_width(2))
                    });
                }
                continue;
            }
            for p in s.points.iter().filter(|p| p.2 > 0.0) {
                c.draw_series(std::iter::once(ErrorBar::new_vertical(
                    p.0,
                    p.1 - p.2,
                    p.1,
                    p.1 + p.2,
                    color.stroke_width(1),
                    6,
                )))
                .map_err(|e| e.to_string())?;
            }
            let hollow = s.hollow;
            c.draw_series(s.points.iter().map(move |p| {
                let style = if hollow {
                    color.stroke_width(2)
                } else {
                    color.filled()
                };
                Circle::new((p.0, p.1), 4, style)
            }))
            .map_err(|e| e.to_string())?
            .label(s.label.clone())
            .legend(move |(x, y)| {
                Circle::new(
                    (x + 8, y),
                    4,
                    if hollow {
                        color.stroke_width(2)
                    } else {
                        color.filled()
                    },
                )
            });
        }
        c.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK.mix(0.3))
            .label_font(("sans-serif", 12))
            .draw()
            .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

/// Bars of one value per step (log scale), for "watch the error fall".
pub fn steps(title: &str, y_desc: &str, labels: &[String], values: &[f64]) -> PlotResult {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (560, 380)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let pos: Vec<f64> = values
            .iter()
            .copied()
            .filter(|v| v.is_finite() && *v > 0.0)
            .collect();
        let lo = pos.iter().copied().fold(f64::MAX, f64::min).min(1.0) / 2.0;
        let hi = pos.iter().copied().fold(f64::MIN, f64::max).max(1.0) * 2.0;
        let n = labels.len() as i32;
        let mut c = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 17))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(62)
            .build_cartesian_2d((0..(n - 1).max(1)).into_segmented(), (lo..hi).log_scale())
            .map_err(|e| e.to_string())?;
        let names = labels.to_vec();
        c.configure_mesh()
            .y_desc(y_desc)
            .x_labels(labels.len())
            .x_label_formatter(&move |v| match v {
                SegmentValue::CenterOf(i) => names.get(*i as usize).cloned().unwrap_or_default(),
                _ => String::new(),
            })
            .x_label_style(("sans-serif", 11))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(|e| e.to_string())?;
        c.draw_series(
            values
                .iter()
                .enumerate()
                .filter(|(_, v)| v.is_finite() && **v > 0.0)
                .map(|(i, v)| {
                    let i = i as i32;
                    let mut bar = Rectangle::new(
                        [
                            (SegmentValue::Exact(i), lo),
                            (SegmentValue::Exact(i + 1), *v),
                        ],
                        PALETTE[0].filled(),
                    );
                    bar.set_margin(0, 0, 12, 12);
                    bar
                }),
        )
        .map_err(|e| e.to_string())?;
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}
