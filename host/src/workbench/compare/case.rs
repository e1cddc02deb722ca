//! One case of a comparison: the model against the measurement of each
//! measured quantity, the swimming speed `U` (mm/s) and the body's rotation
//! rate `Omega_b` (Hz), each with its prediction, measurement, errors and
//! input band, indexed by the quantity so that code for one quantity is
//! code for both.
//!
//! The JSON keeps one flat object per case with the units in the keys
//! (`u_pred_mm_s`, `omega_pred_hz`, ...), as `compare --format json` has
//! always written it: the serializer below spells the per-quantity fields
//! out under those names.

use serde::ser::{Serialize, SerializeStruct, Serializer};
use std::ops::{Index, IndexMut};

/// Which measured quantity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Quantity {
    U,
    Omega,
}

impl Quantity {
    /// Both, in the order the tables list them.
    pub const BOTH: [Quantity; 2] = [Quantity::U, Quantity::Omega];

    pub fn label(self) -> &'static str {
        match self {
            Quantity::U => "U",
            Quantity::Omega => "Omega_b",
        }
    }

    /// The unit the quantity's values are in.
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::U => "mm/s",
            Quantity::Omega => "Hz",
        }
    }
}

/// The model against the measurement of one quantity of one case, in the
/// quantity's unit (mm/s for `U`, Hz for `Omega_b`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct QuantityComparison {
    pub pred: f64,
    pub obs: Option<f64>,
    /// Half-width of the measurement's 95 % interval.
    pub ci: Option<f64>,
    pub rel_err: Option<f64>,
    /// Error in standard errors of the measured mean.
    pub err_sigma: Option<f64>,
    /// The prediction in the paper's dimensionless form: `U / U_wave` for
    /// `U`, `Omega_b / omega` for `Omega_b`.
    pub ratio_pred: f64,
    /// Input-uncertainty band of the prediction (standard uncertainty,
    /// [`crate::workbench::propagate`]) and of its dimensionless form; `None` until
    /// [`super::Comparison::with_bands`].
    pub input_sd: Option<f64>,
    pub ratio_input_sd: Option<f64>,
    /// The input that dominates the band.
    pub dominant_input: Option<String>,
    /// Error in combined standard errors (measurement and inputs in
    /// quadrature).
    pub err_sigma_combined: Option<f64>,
}

/// One case of a comparison.
#[derive(Debug, Clone)]
pub struct CaseComparison {
    pub id: String,
    pub frequency_hz: f64,
    pub n_waves: f64,
    pub amplitude_ratio: f64,
    /// `U` and `Omega_b`, indexed by [`Quantity`].
    pub quantities: [QuantityComparison; 2],
    /// What the lab recorded beside the case (temperature, date, ...),
    /// carried so that a residual can be read against it.
    pub recorded: crate::data::Recorded,
}

impl CaseComparison {
    pub fn u(&self) -> &QuantityComparison {
        &self[Quantity::U]
    }

    pub fn omega(&self) -> &QuantityComparison {
        &self[Quantity::Omega]
    }
}

impl Index<Quantity> for CaseComparison {
    type Output = QuantityComparison;
    fn index(&self, q: Quantity) -> &QuantityComparison {
        &self.quantities[q as usize]
    }
}

impl IndexMut<Quantity> for CaseComparison {
    fn index_mut(&mut self, q: Quantity) -> &mut QuantityComparison {
        &mut self.quantities[q as usize]
    }
}

impl Serialize for CaseComparison {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let (u, o) = (self.u(), self.omega());
        let mut st = s.serialize_struct("CaseComparison", 25)?;
        st.serialize_field("id", &self.id)?;
        st.serialize_field("frequency_hz", &self.frequency_hz)?;
        st.serialize_field("n_waves", &self.n_waves)?;
        st.serialize_field("amplitude_ratio", &self.amplitude_ratio)?;
        st.serialize_field("u_pred_mm_s", &u.pred)?;
        st.serialize_field("u_obs_mm_s", &u.obs)?;
        st.serialize_field("u_ci_mm_s", &u.ci)?;
        st.serialize_field("omega_pred_hz", &o.pred)?;
        st.serialize_field("omega_obs_hz", &o.obs)?;
        st.serialize_field("omega_ci_hz", &o.ci)?;
        st.serialize_field("u_rel_err", &u.rel_err)?;
        st.serialize_field("omega_rel_err", &o.rel_err)?;
        st.serialize_field("u_err_sigma", &u.err_sigma)?;
        st.serialize_field("omega_err_sigma", &o.err_sigma)?;
        st.serialize_field("u_over_u_wave_pred", &u.ratio_pred)?;
        st.serialize_field("omega_ratio_pred", &o.ratio_pred)?;
        st.serialize_field("u_input_sd_mm_s", &u.input_sd)?;
        st.serialize_field("omega_input_sd_hz", &o.input_sd)?;
        st.serialize_field("u_over_u_wave_input_sd", &u.ratio_input_sd)?;
        st.serialize_field("omega_ratio_input_sd", &o.ratio_input_sd)?;
        st.serialize_field("u_dominant_input", &u.dominant_input)?;
        st.serialize_field("omega_dominant_input", &o.dominant_input)?;
        st.serialize_field("u_err_sigma_combined", &u.err_sigma_combined)?;
        st.serialize_field("omega_err_sigma_combined", &o.err_sigma_combined)?;
        if self.recorded.is_empty() {
            st.skip_field("recorded")?;
        } else {
            st.serialize_field("recorded", &self.recorded)?;
        }
        st.end()
    }
}
