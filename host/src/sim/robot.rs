//! The robot description of `swimbot sim` (TOML, `docs/robot-format.md`):
//! motor, cell, divider, controller, PWM drive, remote keys, body, tails,
//! channel, fluid and the swimmer model. serde reads the raw tables
//! (rejecting unknown keys); [`Robot::from_toml`] then checks every value
//! (`robot_file`) so that an error names the file and the field, as
//! `data/parse.rs` does.

use crate::data::Case;
use crate::model::Model;
use crate::physics::geometry::Handedness;
use crate::robot::{Motor, MotorParams, PwmDrive};
use swimbot_shared::{BatteryConfig, ControllerConfig, KeyMap};

/// The built-in robot: the paper's (Tables I, II) with the colleague's
/// motor, cell and board values.
pub const DEFAULT_ROBOT_TOML: &str = include_str!("../../data/robot.toml");

/// The built-in robot, parsed.
pub fn default_robot() -> Robot {
    Robot::from_toml(DEFAULT_ROBOT_TOML, "<built-in robot>").expect("the built-in robot is valid")
}

/// A robot file that failed to load: where and what.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}{}: {message}", field.as_ref().map(|f| format!(": field `{f}`")).unwrap_or_default())]
pub struct RobotError {
    pub file: String,
    pub field: Option<String>,
    pub message: String,
}

/// One tail the robot can carry.
#[derive(Debug, Clone, PartialEq)]
pub struct Tail {
    pub id: String,
    pub wavelength_mm: f64,
    pub amplitude_mm: f64,
    pub length_mm: f64,
    pub wire_diameter_mm: f64,
    pub handedness: Handedness,
    pub load_inertia_kg_m2: f64,
    pub observed_f_hz: Option<f64>,
}

/// The Li-Po cell: capacity, resistance, open-circuit curve.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    pub capacity_mah: f64,
    pub internal_resistance_ohm: f64,
    pub initial_soc: f64,
    pub ocv: Vec<(f64, f64)>,
}

impl Cell {
    /// Open-circuit voltage, linear between table points, clamped at the ends.
    pub fn ocv_v(&self, soc: f64) -> f64 {
        let t = &self.ocv;
        let i = t.partition_point(|p| p.0 < soc).clamp(1, t.len() - 1);
        let ((s0, v0), (s1, v1)) = (t[i - 1], t[i]);
        let x = ((soc - s0) / (s1 - s0)).clamp(0.0, 1.0);
        v0 + (v1 - v0) * x
    }
}

/// A validated robot description.
#[derive(Debug, Clone)]
pub struct Robot {
    pub name: String,
    pub motor: MotorParams,
    pub cell: Cell,
    pub battery: BatteryConfig,
    pub controller: ControllerConfig,
    pub tick_us: u64,
    pub adc_period_us: u64,
    pub drive: PwmDrive,
    pub keys: KeyMap,
    /// A template case: body, channel, fluid; the tail is filled per use.
    pub setup: Case,
    pub start_height_mm: Option<f64>,
    pub model: Model,
    pub tails: Vec<Tail>,
}

impl Robot {
    /// A robot file read, recorded in `inputs`, and checked; the effects
    /// it names are looked up in `catalogue`.
    pub fn load_file(
        path: &std::path::Path,
        catalogue: &crate::effects::Catalogue,
        inputs: &crate::provenance::Inputs,
    ) -> Result<Robot, RobotError> {
        let file = path.display().to_string();
        let text =
            crate::input_file::read_text(path, crate::input_file::cap::ROBOT, "a robot file")
                .map_err(|e| fail(&file, None, e.to_string()))?;
        inputs.record(path, text.as_bytes());
        super::robot_file::parse(&text, &file, catalogue)
    }

    /// A robot from the text of its file (`file` names it in errors),
    /// naming compiled-in effects only.
    pub fn from_toml(text: &str, file: &str) -> Result<Robot, RobotError> {
        super::robot_file::parse(text, file, &crate::effects::Catalogue::builtin())
    }

    /// The model's case for tail `tail` (index), at tail rate `f_hz`.
    pub fn case(&self, tail: usize, f_hz: f64) -> Case {
        let t = &self.tails[tail];
        Case {
            id: t.id.clone(),
            wavelength_mm: t.wavelength_mm,
            amplitude_mm: t.amplitude_mm,
            tail_length_mm: t.length_mm,
            wire_diameter_mm: t.wire_diameter_mm,
            handedness: t.handedness,
            frequency_hz: f_hz,
            ..self.setup.clone()
        }
    }

    /// The motor with tail `tail` on its shaft.
    pub fn motor_with(&self, tail: usize) -> Motor {
        Motor::new(self.motor, self.tails[tail].load_inertia_kg_m2)
    }

    /// Starting height of the nose above the channel floor: the file's, or
    /// the whole robot standing on its tail tip.
    pub fn start_height_mm(&self, tail: usize) -> f64 {
        self.start_height_mm.unwrap_or(
            self.setup.body_length_mm + self.setup.coupler_length_mm + self.tails[tail].length_mm,
        )
    }
}

pub(super) fn fail(file: &str, field: Option<&str>, message: impl Into<String>) -> RobotError {
    RobotError {
        file: file.to_string(),
        field: field.map(str::to_string),
        message: message.into(),
    }
}
