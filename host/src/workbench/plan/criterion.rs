//! The T-optimal criterion (A. C. Atkinson & V. V. Fedorov, Biometrika 62
//! (1975) 57-70: the design that maximises the sum of squared differences
//! between the rivals' predictions discriminates best), weighted by the
//! expected measurement error of each run as in sequential Bayesian design
//! (NIST's optbayesexpt: the expected utility of a setting is how far the
//! rivals' predicted outcomes lie apart in units of the outcome's noise).
//!
//! For rivals `i`, `j` and planned runs `r`, over the measured quantities
//! `q` (U and Omega_b):
//!
//! ```text
//! D_ij = sum_r sum_q ((y_i(r, q) - y_j(r, q)) / sigma(r, q))^2
//! ```
//!
//! `sqrt(D_ij)` is the plan's expected separation in standard deviations.
//! `sigma(r, q)` is the study's noise model at that run: the standard
//! error of the mean of a run's trials, taken as the median relative
//! standard error the data's own measurements of `q` carry (the noise a
//! run of this rig shows, [`crate::workbench::noise`]) times the size of
//! the predicted value (the mean of the two rivals' predictions). A
//! quantity the data never measure is never counted.

use crate::data::Dataset;
use crate::model::Prediction;

/// The expected relative standard error of a new run's mean, per quantity
/// (`None`: the data never measure it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noise {
    pub u_rel: Option<f64>,
    pub omega_rel: Option<f64>,
}

fn median_rel(v: impl Iterator<Item = Option<crate::data::Measured>>) -> Option<f64> {
    let mut r: Vec<f64> = v
        .flatten()
        .map(|m| (m.standard_error() / m.mean).abs())
        .filter(|x| x.is_finite() && *x > 0.0)
        .collect();
    if r.is_empty() {
        return None;
    }
    r.sort_by(f64::total_cmp);
    Some(r[r.len() / 2])
}

impl Noise {
    /// The noise model of `data` (module docs).
    pub fn of(data: &Dataset) -> Noise {
        Noise {
            u_rel: median_rel(data.cases.iter().map(|c| c.u_mm_s)),
            omega_rel: median_rel(data.cases.iter().map(|c| c.omega_body_hz)),
        }
    }

    /// `sum_q ((y_a - y_b) / sigma)^2` at one run (module docs).
    pub fn distance2(&self, a: &Prediction, b: &Prediction) -> f64 {
        let term = |rel: Option<f64>, x: f64, y: f64| match rel {
            Some(rel) => {
                let sigma = rel * 0.5 * (x.abs() + y.abs());
                match sigma > 0.0 {
                    true => ((x - y) / sigma).powi(2),
                    false => 0.0,
                }
            }
            None => 0.0,
        };
        let d = term(self.u_rel, a.u_mm_s, b.u_mm_s)
            + term(self.omega_rel, a.omega_body_hz, b.omega_body_hz);
        if d.is_finite() {
            d
        } else {
            0.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::Model;

    #[test]
    fn distance_is_zero_for_one_model_symmetric_and_scales_as_the_inverse_square_of_the_noise() {
        let data = crate::data::paper();
        let n = Noise::of(&data);
        let c = &data.cases[0];
        let a = Model::base().predict(c).unwrap();
        let mut faster = a;
        faster.u_mm_s *= 1.05;
        assert_eq!(n.distance2(&a, &a), 0.0);
        let d = n.distance2(&a, &faster);
        assert!(d > 0.0);
        assert_eq!(d, n.distance2(&faster, &a));
        let half = Noise {
            u_rel: n.u_rel.map(|r| 0.5 * r),
            omega_rel: n.omega_rel.map(|r| 0.5 * r),
        };
        assert!((half.distance2(&a, &faster) / d - 4.0).abs() < 1e-12);
        // U alone differs: the distance is (0.05 y / (rel * 1.025 y))^2.
        let rel = n.u_rel.unwrap();
        let expect = (0.05 / (rel * 1.025)).powi(2);
        assert!((d / expect - 1.0).abs() < 1e-9, "{d} vs {expect}");
    }

    #[test]
    fn a_quantity_never_measured_is_not_counted() {
        let mut data = crate::data::paper();
        for c in &mut data.cases {
            c.omega_body_hz = None;
        }
        let n = Noise::of(&data);
        assert!(n.omega_rel.is_none());
        let a = Model::base().predict(&data.cases[0]).unwrap();
        let mut spun = a;
        spun.omega_body_hz *= 2.0;
        assert_eq!(n.distance2(&a, &spun), 0.0);
    }
}
