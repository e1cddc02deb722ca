//! A fitted parameter as a physicist reports it, after lmfit's
//! `fit_report`: the value, its standard uncertainty `u` (the covariance's
//! square root, GUM/JCGM 100 sec. 2.3.1), the relative uncertainty
//! `u/|value|` in %, the 95 % interval, and the pairs correlated beyond
//! [`STRONG_CORRELATION`]. Numbers only: the rounding for print (JCGM 100
//! sec. 7.2.6, two significant digits of `u`) is done where they are
//! printed (`cli/screen/rounding.rs`), so the JSON keeps full precision.
//!
//! The interval is the covariance's `value ± 1.96 u` (Wald), or the
//! profile likelihood's ([`super::profile`]) where that one is asymmetric
//! (its ends more than a tenth of the half-width from the covariance's);
//! [`ParamReport::interval`] names which one a report carries.

use super::profile::ProfileInterval;
use super::Estimate;
use serde::{Deserialize, Serialize};
use std::borrow::Cow;

/// The normal quantile of a two-sided 95 % interval: the factor between
/// [`Estimate::ci95`] and the standard uncertainty (`uncertainty.rs`).
pub const Z95: f64 = 1.96;

/// Correlations stronger than this are listed, as lmfit's `fit_report`
/// lists those above its `min_correl` (0.1 by default; 0.8 keeps the pairs
/// a reader must know trade).
pub const STRONG_CORRELATION: f64 = 0.8;

/// One fitted parameter, reported.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParamReport {
    /// `effect.param` (or the law's parameter name).
    pub name: String,
    pub unit: String,
    pub value: f64,
    /// Standard uncertainty; `None` when the data do not fix the parameter
    /// on its own.
    pub standard_uncertainty: Option<f64>,
    /// `100 u / |value|`; `None` without `u` or for a zero value.
    pub relative_uncertainty_percent: Option<f64>,
    /// The 95 % interval's ends; a profile's end is `None` where the
    /// deviance stays below the threshold up to the parameter's bound.
    pub ci95_low: Option<f64>,
    pub ci95_high: Option<f64>,
    /// How the interval was made: `covariance` (symmetric, `value ± 1.96 u`)
    /// or `profile` (the profile likelihood's, where it is asymmetric).
    pub interval: Cow<'static, str>,
    pub at_bound: bool,
}

/// A pair of parameters whose estimates trade.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StrongCorrelation {
    pub a: String,
    pub b: String,
    pub r: f64,
}

impl ParamReport {
    /// The report of one estimate, named `name`.
    pub fn of(name: &str, e: &Estimate) -> Self {
        let u = e.ci95.filter(|c| c.is_finite()).map(|c| c.abs() / Z95);
        ParamReport {
            name: name.to_string(),
            unit: e.unit.clone(),
            value: e.value,
            standard_uncertainty: u,
            relative_uncertainty_percent: u
                .filter(|_| e.value != 0.0)
                .map(|u| 100.0 * u / e.value.abs()),
            ci95_low: u.map(|u| e.value - Z95 * u),
            ci95_high: u.map(|u| e.value + Z95 * u),
            interval: "covariance".into(),
            at_bound: e.at_bound,
        }
    }

    /// The profile's interval instead of the covariance's where the
    /// profile is asymmetric ([`ProfileInterval::asymmetric`]); the
    /// standard uncertainty stays the covariance's.
    pub fn with_profile(mut self, p: &ProfileInterval) -> Self {
        if p.asymmetric && self.standard_uncertainty.is_some() {
            self.ci95_low = p.low;
            self.ci95_high = p.high;
            self.interval = "profile".into();
        }
        self
    }

    /// A value the fit holds jointly with another, with no interval of
    /// its own.
    pub fn held(name: &str, unit: &str, value: f64) -> Self {
        ParamReport {
            name: name.to_string(),
            unit: unit.to_string(),
            value,
            standard_uncertainty: None,
            relative_uncertainty_percent: None,
            ci95_low: None,
            ci95_high: None,
            interval: "covariance".into(),
            at_bound: false,
        }
    }
}

/// The pairs of `names` whose correlation in `matrix` (row-major, as
/// [`super::FitResult::correlation`]) exceeds [`STRONG_CORRELATION`] in
/// magnitude, strongest first.
pub fn strong_correlations(names: &[String], matrix: &[Vec<f64>]) -> Vec<StrongCorrelation> {
    let mut out = Vec::new();
    for (i, row) in matrix.iter().enumerate().take(names.len()) {
        for (j, &r) in row.iter().enumerate().take(names.len()).skip(i + 1) {
            if r.is_finite() && r.abs() > STRONG_CORRELATION {
                out.push(StrongCorrelation {
                    a: names[i].clone(),
                    b: names[j].clone(),
                    r,
                });
            }
        }
    }
    out.sort_by(|x, y| y.r.abs().total_cmp(&x.r.abs()));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn est(value: f64, ci95: Option<f64>) -> Estimate {
        Estimate {
            effect: "e".into(),
            name: "k".into(),
            unit: "1".into(),
            value,
            ci95,
            at_bound: false,
        }
    }

    #[test]
    fn the_standard_uncertainty_is_the_half_width_over_the_normal_quantile() {
        let r = ParamReport::of("k", &est(2.0, Some(0.392)));
        assert!((r.standard_uncertainty.unwrap() - 0.2).abs() < 1e-12);
        assert!((r.relative_uncertainty_percent.unwrap() - 10.0).abs() < 1e-9);
        assert!((r.ci95_low.unwrap() - 1.608).abs() < 1e-12);
        assert!((r.ci95_high.unwrap() - 2.392).abs() < 1e-12);
    }

    #[test]
    fn an_unfixed_parameter_has_no_interval_and_a_zero_no_relative_one() {
        let r = ParamReport::of("k", &est(2.0, None));
        assert_eq!(r.standard_uncertainty, None);
        assert_eq!(r.ci95_low, None);
        let z = ParamReport::of("k", &est(0.0, Some(0.1)));
        assert!(z.standard_uncertainty.is_some());
        assert_eq!(z.relative_uncertainty_percent, None);
        let inf = ParamReport::of("k", &est(1.0, Some(f64::INFINITY)));
        assert_eq!(inf.standard_uncertainty, None);
    }

    #[test]
    fn only_correlations_beyond_the_threshold_are_listed_strongest_first() {
        let names: Vec<String> = ["a", "b", "c"].iter().map(|s| s.to_string()).collect();
        let m = vec![
            vec![1.0, 0.85, -0.95],
            vec![0.85, 1.0, 0.5],
            vec![-0.95, 0.5, 1.0],
        ];
        let s = strong_correlations(&names, &m);
        assert_eq!(s.len(), 2);
        assert_eq!(
            (s[0].a.as_str(), s[0].b.as_str(), s[0].r),
            ("a", "c", -0.95)
        );
        assert_eq!((s[1].a.as_str(), s[1].b.as_str()), ("a", "b"));
    }
}
