//! The robot file's tables as serde reads them (unknown keys rejected);
//! `robot.rs` validates them field by field. Units are in the key names;
//! the format is documented in `docs/robot-format.md`.

use crate::data::Orientation;
use crate::physics::geometry::Handedness;
use serde::Deserialize;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct Raw {
    pub(super) name: Option<String>,
    pub(super) motor: RawMotor,
    pub(super) battery: RawBattery,
    pub(super) divider: RawDivider,
    pub(super) controller: RawController,
    pub(super) drive: RawDrive,
    pub(super) remote: RawRemote,
    pub(super) body: RawBody,
    pub(super) channel: RawChannel,
    pub(super) model: RawModel,
    #[serde(rename = "tail")]
    pub(super) tails: Vec<RawTail>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMotor {
    pub(super) resistance_ohm: f64,
    pub(super) inductance_h: f64,
    pub(super) torque_constant_n_m_per_a: f64,
    pub(super) rotor_inertia_kg_m2: f64,
    pub(super) viscous_friction_n_m_s: f64,
    pub(super) coulomb_friction_n_m: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBattery {
    pub(super) capacity_mah: f64,
    pub(super) internal_resistance_ohm: f64,
    pub(super) initial_soc: Option<f64>,
    /// `[[soc, volts], ...]`, sorted by state of charge.
    pub(super) ocv: Option<Vec<(f64, f64)>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDivider {
    pub(super) top_ohm: u32,
    pub(super) bottom_ohm: u32,
    pub(super) adc_ref_mv: u32,
    pub(super) cutoff_mv: Option<u16>,
    pub(super) warn_mv: Option<u16>,
    pub(super) recharged_mv: Option<u16>,
    pub(super) cutoff_debounce_ms: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawController {
    pub(super) ramp_ms: u32,
    pub(super) target_motor_mv: u16,
    pub(super) max_duty: f64,
    pub(super) max_run_s: f64,
    pub(super) tick_us: Option<u64>,
    pub(super) adc_period_us: Option<u64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawDrive {
    pub(super) carrier_hz: f64,
    pub(super) diode_drop_v: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRemote {
    pub(super) address: u8,
    pub(super) on: u8,
    pub(super) off: u8,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawBody {
    pub(super) length_mm: f64,
    pub(super) diameter_mm: f64,
    pub(super) coupler_length_mm: f64,
    pub(super) coupler_diameter_mm: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawChannel {
    pub(super) diameter_mm: f64,
    pub(super) length_mm: f64,
    pub(super) closed: bool,
    pub(super) orientation: Orientation,
    pub(super) viscosity_pa_s: f64,
    pub(super) density_kg_m3: f64,
    pub(super) start_height_mm: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawModel {
    pub(super) coefficients: String,
    pub(super) effects: Vec<String>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTail {
    pub(super) id: String,
    pub(super) wavelength_mm: f64,
    pub(super) amplitude_mm: f64,
    pub(super) length_mm: f64,
    pub(super) wire_diameter_mm: f64,
    pub(super) handedness: Option<Handedness>,
    /// Rotating inertia of coupler and tail; from the copper helix if absent.
    pub(super) load_inertia_kg_m2: Option<f64>,
    /// The tail rate observed with this tail (Table II), for reports only.
    pub(super) observed_f_hz: Option<f64>,
}
