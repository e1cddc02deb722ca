//! The story page's layers of Fig. 4 ([`super`]): the measurements of the
//! dataset, grouped by amplitude, and each fitted model drawn with its
//! markers at the measured cases from its comparison (± 2u where the
//! comparison carries input bands) and, where affordable, its curve
//! between them ([`crate::report::curve`]).

use super::{ByQuantity, Group, Layers, Marker, Marks, ModelLayer, Point};
use crate::chart::Rgb;
use crate::data::{Case, Dataset};
use crate::model::{Model, Prediction};
use crate::report::curve::model_curve;
use crate::workbench::compare::Comparison;

/// One model drawn in the figure: its markers come from its comparison
/// (the workbench's numbers, with their input bands), its curve from the
/// model between the cases.
pub struct Fitted<'a> {
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

/// The measured ratio of each case with its CI: `Omega_b/omega` when
/// `omega`, else `U/U_wave`.
fn measured(cases: &[&Case], omega: bool) -> Vec<Point> {
    cases
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
        .collect()
}

/// `f`'s markers and curve of one group and quantity.
fn marks(f: &Fitted, cases: &[&Case], omega: bool) -> Marks {
    let points = cases
        .iter()
        .filter_map(|c| {
            let k = f.comparison.cases.iter().find(|k| k.id == c.id)?;
            let q = if omega { k.omega() } else { k.u() };
            Some((
                k.n_waves,
                q.ratio_pred,
                2.0 * q.ratio_input_sd.unwrap_or(0.0),
            ))
        })
        .collect();
    let ratio: fn(&Prediction) -> f64 = if omega {
        |p| p.omega_ratio
    } else {
        |p| p.u_over_u_wave
    };
    let curve = if f.curve {
        model_curve(f.model, cases, ratio)
    } else {
        Vec::new()
    };
    Marks { points, curve }
}

/// The layers of `data` and the models `fitted`, each drawn hollow.
pub fn layers(data: &Dataset, fitted: &[Fitted]) -> Layers {
    let groups = amplitude_groups(data);
    let models = fitted
        .iter()
        .map(|f| ModelLayer {
            label: f.label.clone(),
            color: f.color,
            marker: Marker::Hollow,
            groups: groups
                .iter()
                .map(|(_, cases)| -> ByQuantity<Marks> {
                    [marks(f, cases, false), marks(f, cases, true)]
                })
                .collect(),
        })
        .collect();
    Layers {
        ci: crate::report::intro::confidence(data),
        groups: groups
            .iter()
            .map(|(b, cases)| Group {
                ratio: b / (0.5 * cases[0].body_diameter_mm),
                n_waves: cases.iter().map(|c| c.n_waves()).collect(),
                measured: [measured(cases, false), measured(cases, true)],
            })
            .collect(),
        models,
        log_y_when_wide: false,
    }
}

#[cfg(test)]
mod tests {
    use super::super::{draw, panel_width, BLACK};
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
        let fitted = [Fitted {
            label: "paper".into(),
            model: &model,
            comparison: &cmp,
            color: BLACK,
            curve: true,
        }];
        let fig = draw(&layers(&data, &fitted));
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
    }
}
