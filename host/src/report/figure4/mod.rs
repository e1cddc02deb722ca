//! The paper's Fig. 4, the one figure both pages draw: `U/U_wave` (the
//! first row of panels) and `Omega_b/omega` (the second) against the
//! number of waves `N_lambda`, one panel per amplitude group `B_o/R_body`.
//! It draws [`Layers`]: the measurements with their CIs and, per model,
//! its markers (hollow or filled, with their bars) and its curve where it
//! has one. Where the layers come from is each page's: the story page's
//! fitted models with their curves ([`models`]), the study page's model
//! before and after a step from its stored rows ([`study`]).
//!
//! One legend for the figure, drawn beside the grid rather than inside
//! panel (a): a legend that did not fit in the plot went outside it,
//! widened that panel alone (452 px against 289 with four amplitude
//! groups), and the page's grid, fitting the row into its width, then
//! drew panel (a) at about 64 % of its size. The models' markers are drawn
//! side by side ([`dodge`]) so that their bars at one case stay apart.
//!
//! Reference: the paper's Fig. 4 ("In-channel experiments on vertical
//! swimming with bacteria-like robots"; host/data/paper.csv).

pub mod models;
pub mod study;

use super::html::{figure_flow, Markup};
use super::page::Part;
use crate::chart::Rgb;
use crate::chart::{legend_only, Chart, PlotResult, Series};

/// The paper's colours: observations red, Gray-Hancock black, Lighthill blue.
pub const MEASURED: Rgb = Rgb(214, 39, 40);
pub const BLACK: Rgb = Rgb(0, 0, 0);
pub const BLUE: Rgb = Rgb(31, 119, 180);
pub const GREEN: Rgb = Rgb(44, 160, 44);

/// A point `(N_lambda, ratio, error bar)`.
pub type Point = (f64, f64, f64);

/// What is drawn of one quantity, `[U/U_wave, Omega_b/omega]`.
pub type ByQuantity<T> = [T; 2];

/// One amplitude group: its panel's title ratio `B_o/R_body`, the
/// `N_lambda` of its cases (the panel's x range) and the measurements.
pub struct Group {
    pub ratio: f64,
    pub n_waves: Vec<f64>,
    pub measured: ByQuantity<Vec<Point>>,
}

/// How a model's markers are drawn.
#[derive(Clone, Copy)]
pub enum Marker {
    Hollow,
    Filled,
}

/// A model's markers in one panel, and its curve through them (empty:
/// none).
#[derive(Default)]
pub struct Marks {
    pub points: Vec<Point>,
    pub curve: Vec<Point>,
}

/// One model drawn in every panel: its marks per group, in the order of
/// [`Layers::groups`].
pub struct ModelLayer {
    pub label: String,
    pub color: Rgb,
    pub marker: Marker,
    pub groups: Vec<ByQuantity<Marks>>,
}

/// Everything the figure draws.
pub struct Layers {
    /// The confidence of the measurements' intervals (`95 %`).
    pub ci: String,
    pub groups: Vec<Group>,
    pub models: Vec<ModelLayer>,
    /// Draw a panel's y axis logarithmic where its values span more than a
    /// factor of four (a base model several times off would squash the
    /// others into a strip).
    pub log_y_when_wide: bool,
}

/// The page's content width (px) a row of Fig. 4 panels must fit in, and
/// the grid's gap between them.
const ROW_PX: u32 = 1204;
const GAP_PX: u32 = 16;

/// A panel's width for `groups` panels in a row: shown at its own size
/// (ticks read at the size they are drawn) up to 390 px, narrower for four
/// or more groups, never below 240 px.
pub fn panel_width(groups: usize) -> u32 {
    let g = groups.max(1) as u32;
    ((ROW_PX - GAP_PX * (g - 1)) / g).clamp(240, 390)
}

/// The x range of a panel: the cases' `N_lambda` with a margin of a tenth
/// of their span (at least 0.3 % of the value), never the chart engine's
/// minimum span for flat data, which padded 3.73-3.82 out to 3.55-3.98.
pub fn n_waves_range(n_waves: &[f64]) -> (f64, f64) {
    let lo = n_waves.iter().copied().fold(f64::MAX, f64::min);
    let hi = n_waves.iter().copied().fold(f64::MIN, f64::max);
    // Cases that share one N_lambda have no span to pad: a tenth of the
    // value on each side gives ticks one can read (0.3 % of it drew a
    // 3.99-4.01 axis).
    let pad = if hi - lo <= 1e-9 * hi.abs() {
        0.1 * hi.abs().max(1.0)
    } else {
        (0.1 * (hi - lo)).max(0.003 * hi)
    };
    (lo - pad, hi + pad)
}

/// How far apart (fraction of the plot's width) the markers of models at
/// the same case are drawn: 2 % is about 6 px on a 390 px panel, enough
/// for two bars and their caps to stand apart, small against the spacing
/// of the cases.
pub const DODGE: f64 = 0.02;

/// The x shift of model `k`'s markers: the measurement stays at its x, the
/// models alternate left and right of it (-1, +1, -2, +2 ... x [`DODGE`]),
/// the same in every panel, each model's curve with its markers so that it
/// still passes through them.
pub fn dodge(k: usize) -> f64 {
    let step = (k / 2 + 1) as f64 * DODGE;
    if k.is_multiple_of(2) {
        -step
    } else {
        step
    }
}

/// [`DODGE`] in per cent as the captions print it.
pub fn dodge_percent() -> String {
    crate::format::fmt_sig(100.0 * DODGE, 2)
}

/// The captions' panel letters for `groups` groups: the last of the first
/// row, the first and the last of the second.
pub fn letters(groups: usize) -> (char, char, char) {
    let k = groups as u8;
    (
        (b'a' + k - 1) as char,
        (b'a' + k) as char,
        (b'a' + 2 * k - 1) as char,
    )
}

/// One panel, its chart and its series: quantity `q` of group `i`.
fn panel(l: &Layers, i: usize, q: usize, title: &str) -> (Chart, Vec<Series>) {
    let g = &l.groups[i];
    let mut series = vec![Series::measured(
        format!("measured ({} CI)", l.ci),
        MEASURED,
        g.measured[q].clone(),
    )];
    for (k, m) in l.models.iter().enumerate() {
        let marks = &m.groups[i][q];
        if !marks.curve.is_empty() {
            series
                .push(Series::curve(String::new(), m.color, marks.curve.clone()).dodged(dodge(k)));
        }
        let points = marks.points.clone();
        let drawn = match m.marker {
            Marker::Hollow => Series::model(m.label.clone(), m.color, points),
            Marker::Filled => Series::measured(m.label.clone(), m.color, points),
        };
        series.push(drawn.dodged(dodge(k)));
    }
    let y = if q == 1 {
        "Omega_b / omega"
    } else {
        "U / U_wave"
    };
    let (lo, hi) = n_waves_range(&g.n_waves);
    let mut chart = Chart::new(title, "N_lambda", y)
        .size(panel_width(l.groups.len()), 330)
        .x_range(lo, hi)
        .without_hidden_note()
        .without_legend();
    if l.log_y_when_wide {
        let ys = series.iter().flat_map(|s| s.points.iter().map(|p| p.1));
        let (y_lo, y_hi) = ys.fold((f64::MAX, f64::MIN), |(a, b), y| (a.min(y), b.max(y)));
        if y_lo > 0.0 && y_hi / y_lo > 4.0 {
            chart = chart.log_y();
        }
    }
    (chart, series)
}

/// The figure drawn: its one legend and its panels.
pub struct Drawn {
    pub legend: PlotResult,
    pub panels: Vec<PlotResult>,
}

/// The panels in the paper's order, each with its caption-letter title:
/// first `U/U_wave` per group, then `Omega_b/omega` per group; the legend
/// of every panel's series, once.
pub fn draw(l: &Layers) -> Drawn {
    let mut panels = Vec::new();
    let mut legend = Err(crate::chart::ChartError::NoPanel);
    let mut letter = b'a';
    for q in 0..2 {
        for (i, g) in l.groups.iter().enumerate() {
            let title = format!(
                "({}) B_o/R_body = {}",
                letter as char,
                crate::format::fmt_sig(g.ratio, 2)
            );
            let (chart, series) = panel(l, i, q, &title);
            if panels.is_empty() {
                legend = legend_only(&chart, &series);
            }
            panels.push(chart.render(&series));
            letter = letter.wrapping_add(1);
        }
    }
    Drawn { legend, panels }
}

/// The figure `id` on the page: its legend above a grid of one column per
/// group, the U row then the Omega_b row, with `caption`.
pub fn figure(id: &str, l: &Layers, caption: Markup) -> Part {
    let drawn = draw(l);
    figure_flow(
        id,
        Some(&drawn.legend),
        &drawn.panels,
        l.groups.len().max(1),
        caption,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_x_axis_spans_the_cases_not_a_padded_minimum() {
        let (lo, hi) = n_waves_range(&[3.733, 3.818]);
        let span = 3.818 - 3.733;
        assert!(lo > 3.70 && hi < 3.86, "{lo}-{hi}");
        assert!(hi - lo < 2.0 * span);
    }

    #[test]
    fn cases_sharing_one_n_lambda_get_an_axis_one_can_read() {
        let n = crate::data::paper().cases[0].n_waves();
        let (lo, hi) = n_waves_range(&[n, n]);
        assert!(lo < n && n < hi);
        assert!((hi - lo) / n > 0.15, "{lo}-{hi}");
    }

    #[test]
    fn models_alternate_left_and_right_each_at_its_own_x() {
        assert_eq!(dodge(0), -DODGE);
        assert_eq!(dodge(1), DODGE);
        let shifts: Vec<f64> = (0..6).map(dodge).collect();
        for (i, a) in shifts.iter().enumerate() {
            assert!(*a != 0.0, "a model on the measurement's x");
            for b in &shifts[i + 1..] {
                assert!((a - b).abs() >= DODGE - 1e-12, "{shifts:?}");
            }
        }
    }

    #[test]
    fn four_panels_in_a_row_fit_the_page_at_their_own_size() {
        assert!(4 * panel_width(4) + 3 * GAP_PX <= ROW_PX);
        assert_eq!(panel_width(3), 390);
        assert_eq!(letters(3), ('c', 'd', 'f'));
    }
}
