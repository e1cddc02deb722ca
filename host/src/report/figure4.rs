//! The paper's Fig. 4: `U/U_wave` (panels a-c) and `Omega_b/omega`
//! (panels d-f) against the number of waves `N_lambda`, one panel per
//! amplitude group `B_o/R_body`: the measurements with their CIs and,
//! for each model drawn, its markers at the measured cases (± 2u where the
//! comparison carries input bands) and its curve through them
//! ([`super::curve`]). One legend for the figure, drawn beside the grid
//! rather than inside panel (a): a legend that did not fit in the plot went
//! outside it, widened that panel alone (452 px against 289 with four
//! amplitude groups), and the page's grid, fitting the row into its width,
//! then drew panel (a) at about 64 % of its size. The captions say that
//! error bars smaller than a marker are hidden by it, and that the models'
//! markers are drawn side by side ([`dodge`]) so that their bars at one
//! case stay apart.

use super::curve::model_curve;
use crate::chart::Rgb;
use crate::chart::{legend_only, Chart, PlotResult, Series};
use crate::data::{Case, Dataset};
use crate::model::{Model, Prediction};
use crate::workbench::compare::Comparison;

/// The paper's colours: observations red, Gray-Hancock black, Lighthill blue.
pub const MEASURED: Rgb = Rgb(214, 39, 40);
pub const BLACK: Rgb = Rgb(0, 0, 0);
pub const BLUE: Rgb = Rgb(31, 119, 180);
pub const GREEN: Rgb = Rgb(44, 160, 44);

/// One model drawn in the figure: its markers come from its comparison
/// (the workbench's numbers, with their input bands), its curve from the
/// model between the cases.
pub struct Layer<'a> {
    pub label: String,
    pub model: &'a Model,
    pub comparison: &'a Comparison,
    pub color: Rgb,
    /// Draw its curve too (each curve point is a prediction: affordable for
    /// the local RFT models, not for a tube solve per point).
    pub curve: bool,
}

/// Amplitude groups `(B_o, cases)` in the order of first appearance.
pub fn amplitude_groups(data: &Dataset) -> Vec<(f64, Vec<&Case>)> {
    let mut groups: Vec<(f64, Vec<&Case>)> = Vec::new();
    for c in &data.cases {
        match groups
            .iter_mut()
            .find(|g| (g.0 - c.amplitude_mm).abs() < 1e-9)
        {
            Some(g) => g.1.push(c),
            None => groups.push((c.amplitude_mm, vec![c])),
        }
    }
    groups
}

/// The x range of a panel: the cases' `N_lambda` with a margin of a tenth
/// of their span (at least 0.3 % of the value), never the chart engine's
/// minimum span for flat data, which padded 3.73-3.82 out to 3.55-3.98.
fn x_range(cases: &[&Case]) -> (f64, f64) {
    n_waves_range(&cases.iter().map(|c| c.n_waves()).collect::<Vec<_>>())
}

/// [`x_range`] of the cases' `N_lambda` values.
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

/// One panel, its chart and its series: `omega` selects `Omega_b/omega`,
/// else `U/U_wave`.
fn panel(
    title: &str,
    cases: &[&Case],
    layers: &[Layer],
    omega: bool,
    ci: &str,
    groups: usize,
) -> (Chart, Vec<Series>) {
    let ratio: fn(&Prediction) -> f64 = if omega {
        |p| p.omega_ratio
    } else {
        |p| p.u_over_u_wave
    };
    let measured: Vec<(f64, f64, f64)> = cases
        .iter()
        .filter_map(|c| {
            let scale = if omega {
                c.frequency_hz
            } else {
                c.wavelength_mm * c.frequency_hz
            };
            let m = if omega { c.omega_body_hz } else { c.u_mm_s }?;
            Some((c.n_waves(), m.mean / scale, m.ci_half_width / scale))
        })
        .collect();
    let mut series = vec![Series::measured(
        format!("measured ({ci} CI)"),
        MEASURED,
        measured,
    )];
    for (k, l) in layers.iter().enumerate() {
        let markers: Vec<(f64, f64, f64)> = cases
            .iter()
            .filter_map(|c| {
                let k = l.comparison.cases.iter().find(|k| k.id == c.id)?;
                Some(if omega {
                    (
                        k.n_waves,
                        k.omega().ratio_pred,
                        2.0 * k.omega().ratio_input_sd.unwrap_or(0.0),
                    )
                } else {
                    (
                        k.n_waves,
                        k.u().ratio_pred,
                        2.0 * k.u().ratio_input_sd.unwrap_or(0.0),
                    )
                })
            })
            .collect();
        let curve = if l.curve {
            model_curve(l.model, cases, ratio)
        } else {
            Vec::new()
        };
        if !curve.is_empty() {
            series.push(Series::curve(String::new(), l.color, curve).dodged(dodge(k)));
        }
        series.push(Series::model(l.label.clone(), l.color, markers).dodged(dodge(k)));
    }
    let y = if omega {
        "Omega_b / omega"
    } else {
        "U / U_wave"
    };
    let (lo, hi) = x_range(cases);
    let chart = Chart::new(title, "N_lambda", y)
        .size(panel_width(groups), 330)
        .x_range(lo, hi)
        .without_hidden_note()
        .without_legend();
    (chart, series)
}

/// The figure: its one legend and its panels.
pub struct Figure4 {
    pub legend: PlotResult,
    pub panels: Vec<PlotResult>,
}

/// The panels in the paper's order, each with its caption-letter title:
/// first `U/U_wave` per group, then `Omega_b/omega` per group; the legend
/// of every panel's series, once.
pub fn figure4(data: &Dataset, layers: &[Layer]) -> Figure4 {
    let groups = amplitude_groups(data);
    let ci = super::intro::confidence(data);
    let mut panels = Vec::new();
    let mut legend = Err(crate::chart::ChartError::NoPanel);
    let mut letter = b'a';
    for omega in [false, true] {
        for (b, cases) in &groups {
            let ratio = b / (0.5 * cases[0].body_diameter_mm);
            let title = format!(
                "({}) B_o/R_body = {}",
                letter as char,
                crate::format::fmt_sig(ratio, 2)
            );
            let (chart, series) = panel(&title, cases, layers, omega, &ci, groups.len());
            if panels.is_empty() {
                legend = legend_only(&chart, &series);
            }
            panels.push(chart.render(&series));
            letter = letter.wrapping_add(1);
        }
    }
    Figure4 { legend, panels }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::workbench::compare::compare;

    /// The paper's data with tail-5 at its own amplitude: four groups, two
    /// of them a single case.
    fn four_groups() -> Dataset {
        let mut data = crate::data::paper();
        data.cases[4].amplitude_mm = 6.0;
        data
    }

    #[test]
    fn the_layout_follows_the_data_u_row_then_omega_row() {
        let data = four_groups();
        assert_eq!(amplitude_groups(&data).len(), 4);
        let model = crate::model::preset("paper").unwrap();
        let cmp = compare(&model, &data, 0).unwrap();
        let layers = [Layer {
            label: "paper".into(),
            model: &model,
            comparison: &cmp,
            color: BLACK,
            curve: true,
        }];
        let fig = figure4(&data, &layers);
        let legend = fig.legend.unwrap();
        assert!(legend.contains("class=\"legend\"") && legend.contains("paper"));
        let panels: Vec<String> = fig.panels.into_iter().map(Result::unwrap).collect();
        assert_eq!(panels.len(), 8);
        for (i, p) in panels.iter().enumerate() {
            let letter = (b'a' + i as u8) as char;
            assert!(p.contains(&format!("({letter})")), "panel {letter}");
            // the first row U/U_wave, the second Omega_b/omega
            assert_eq!(p.contains("Ω"), i >= 4, "panel {letter} in the wrong row");
            // no legend in a panel: every panel at its own width, none
            // widened (and so shrunk by the page's grid)
            assert!(!p.contains("class=\"legend\""), "panel {letter}");
            let w = format!("width=\"{}\"", panel_width(4));
            assert!(p.contains(&w), "panel {letter} is not {w} wide");
        }
        // tail-5 (6.0 mm) and tail-6 (7.5 mm) stand alone: markers, no curve
        for i in [2, 3, 6, 7] {
            assert!(!panels[i].contains("<polyline"), "panel {i} draws a curve");
        }
        assert!(
            panels[0].contains("<polyline"),
            "a group of two has its curve"
        );
        // four panels in a row fit the page at their own size
        assert!(4 * panel_width(4) + 3 * GAP_PX <= ROW_PX);
        assert_eq!(panel_width(3), 390);
    }

    #[test]
    fn the_x_axis_spans_the_cases_not_a_padded_minimum() {
        let data = crate::data::paper();
        let groups = amplitude_groups(&data);
        let (_, cases) = &groups[2]; // 3.73 and 3.82 waves
        let (lo, hi) = x_range(cases);
        let span = 3.818 - 3.733;
        assert!(lo > 3.70 && hi < 3.86, "{lo}-{hi}");
        assert!(hi - lo < 2.0 * span);
    }

    #[test]
    fn cases_sharing_one_n_lambda_get_an_axis_one_can_read() {
        let data = crate::data::paper();
        let one = [&data.cases[0], &data.cases[0]];
        let n = data.cases[0].n_waves();
        let (lo, hi) = x_range(&one);
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
}
