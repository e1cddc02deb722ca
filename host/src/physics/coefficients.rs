//! Local resistance coefficients of resistive force theory: the drag per
//! unit length of a slender filament moving along its tangent (`c_t`) and
//! normal to it (`c_n`, equal to the binormal `c_b` for a round wire).
//!
//! Implements the paper's eqs. 4-5 (Gray & Hancock 1955) and eqs. 6-7
//! (Lighthill 1976), with natural logarithms. New sets plug in through the
//! [`DragCoefficients`] trait and one line in [`CoefficientSet::all`].
//!
//! References: J. Gray & G. J. Hancock, J. Exp. Biol. 32 (1955) 802;
//! J. Lighthill, SIAM Rev. 18 (1976) 161.

use super::geometry::Helix;
use std::f64::consts::PI;
use std::fmt;

/// Local drag per unit arc length (N s / m^2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalDrag {
    pub tangential: f64,
    /// Normal and binormal (equal for a round wire).
    pub normal: f64,
}

impl LocalDrag {
    /// Both coefficients scaled by the same factor (wall effects, viscosity).
    pub fn scaled(self, factor: f64) -> Self {
        LocalDrag {
            tangential: self.tangential * factor,
            normal: self.normal * factor,
        }
    }
}

/// Why a coefficient set cannot be evaluated for a geometry.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CoefficientError {
    #[error("{set}: the logarithm's argument {arg:.4} makes a non-positive denominator (wavelength too short for the wire diameter)")]
    LogBreakdown { set: &'static str, arg: f64 },
}

/// A resistive force theory coefficient set.
pub trait DragCoefficients: Send + Sync {
    /// The name used on the command line.
    fn name(&self) -> &'static str;
    fn reference(&self) -> &'static str;
    fn local_drag(&self, helix: &Helix, viscosity_pa_s: f64)
        -> Result<LocalDrag, CoefficientError>;
}

/// Gray & Hancock (1955), the paper's eqs. 4-5.
#[derive(Debug, Clone, Copy, Default)]
pub struct GrayHancock;

impl DragCoefficients for GrayHancock {
    fn name(&self) -> &'static str {
        "gray-hancock"
    }
    fn reference(&self) -> &'static str {
        "Gray & Hancock, J. Exp. Biol. 32 (1955) 802; paper eqs. 4-5"
    }
    fn local_drag(&self, helix: &Helix, mu: f64) -> Result<LocalDrag, CoefficientError> {
        let log = (helix.wavelength_m / helix.wire_diameter_m).ln();
        checked("gray-hancock", log - 0.5, log)?;
        Ok(LocalDrag {
            tangential: 2.0 * PI * mu / (log - 0.5),
            normal: 4.0 * PI * mu / (log + 0.5),
        })
    }
}

/// Lighthill (1976), the paper's eqs. 6-7 with `alpha = L_t / l`.
#[derive(Debug, Clone, Copy, Default)]
pub struct Lighthill;

impl DragCoefficients for Lighthill {
    fn name(&self) -> &'static str {
        "lighthill"
    }
    fn reference(&self) -> &'static str {
        "Lighthill, SIAM Rev. 18 (1976) 161; paper eqs. 6-7"
    }
    fn local_drag(&self, helix: &Helix, mu: f64) -> Result<LocalDrag, CoefficientError> {
        let log = (0.36 * helix.wavelength_m / (helix.alpha() * helix.wire_diameter_m)).ln();
        checked("lighthill", log, log)?;
        Ok(LocalDrag {
            tangential: 2.0 * PI * mu / log,
            normal: 4.0 * PI * mu / (log + 0.5),
        })
    }
}

fn checked(set: &'static str, denominator: f64, log: f64) -> Result<(), CoefficientError> {
    if denominator > 0.0 && denominator.is_finite() {
        Ok(())
    } else {
        Err(CoefficientError::LogBreakdown {
            set,
            arg: log.exp(),
        })
    }
}

/// The coefficient sets the command line can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CoefficientSet {
    #[default]
    GrayHancock,
    Lighthill,
}

impl CoefficientSet {
    pub fn all() -> &'static [CoefficientSet] {
        &[CoefficientSet::GrayHancock, CoefficientSet::Lighthill]
    }

    pub fn implementation(self) -> &'static dyn DragCoefficients {
        match self {
            CoefficientSet::GrayHancock => &GrayHancock,
            CoefficientSet::Lighthill => &Lighthill,
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::all()
            .iter()
            .copied()
            .find(|s| s.implementation().name() == name)
    }

    pub fn local_drag(self, helix: &Helix, mu: f64) -> Result<LocalDrag, CoefficientError> {
        self.implementation().local_drag(helix, mu)
    }
}

impl fmt::Display for CoefficientSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.implementation().name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_drag_exceeds_tangential_drag() {
        // The anisotropy c_n / c_t > 1 is what makes a rotating helix swim.
        for set in CoefficientSet::all() {
            for &(lam, b) in &[(15.5, 2.5), (10.0, 2.5), (11.0, 7.5)] {
                let h = Helix::from_mm(lam, b, 60.0, 1.0);
                let d = set.local_drag(&h, 3.5).unwrap();
                let ratio = d.normal / d.tangential;
                assert!(ratio > 1.0 && ratio < 2.0, "{set}: ratio {ratio}");
            }
        }
    }

    #[test]
    fn coefficients_are_linear_in_viscosity() {
        let h = Helix::from_mm(12.0, 4.5, 60.0, 1.0);
        for set in CoefficientSet::all() {
            let a = set.local_drag(&h, 1.0).unwrap();
            let b = set.local_drag(&h, 3.5).unwrap();
            assert!((b.tangential / a.tangential - 3.5).abs() < 1e-12);
            assert!((b.normal / a.normal - 3.5).abs() < 1e-12);
        }
    }

    #[test]
    fn gray_hancock_matches_equation_four_by_hand() {
        let h = Helix::from_mm(15.5, 2.5, 130.0, 1.0);
        let d = GrayHancock.local_drag(&h, 3.5).unwrap();
        // ln(15.5) = 2.740840
        assert!((d.tangential - 2.0 * PI * 3.5 / (2.740840 - 0.5)).abs() < 1e-5);
        assert!((d.normal - 4.0 * PI * 3.5 / (2.740840 + 0.5)).abs() < 1e-5);
    }

    #[test]
    fn wavelength_near_wire_diameter_is_an_error_not_a_nan() {
        let h = Helix::from_mm(1.5, 0.5, 10.0, 1.0);
        assert!(matches!(
            GrayHancock.local_drag(&h, 1.0),
            Err(CoefficientError::LogBreakdown { .. })
        ));
        // 0.36 lambda / (alpha D_t) < 1 for a nearly straight, short-pitch helix.
        let h = Helix::from_mm(2.0, 0.01, 10.0, 1.0);
        assert!(Lighthill.local_drag(&h, 1.0).is_err());
    }

    #[test]
    fn names_round_trip() {
        for set in CoefficientSet::all() {
            assert_eq!(CoefficientSet::from_name(&set.to_string()), Some(*set));
        }
    }
}
