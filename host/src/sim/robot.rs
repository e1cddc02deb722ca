//! The robot description of `swimbot sim` (TOML, `docs/robot-format.md`):
//! motor, cell, divider, controller, PWM drive, remote keys, body, tails,
//! channel, fluid and the swimmer model. serde reads the raw tables
//! (rejecting unknown keys); [`Robot::from_toml`] then checks every value so
//! that an error names the file and the field, as `data/parse.rs` does.

use super::raw::Raw;
use crate::data::Case;
use crate::effects::parse_effect_spec;
use crate::model::Model;
use crate::physics::coefficients::CoefficientSet;
use crate::physics::geometry::Handedness;
use crate::robot::{Motor, MotorParams, PwmDrive};
use swimbot_shared::{BatteryConfig, ControllerConfig, Duty, KeyMap};

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

/// Copper, for the tail's inertia when the file does not give it.
const COPPER_KG_M3: f64 = 8960.0;

impl Robot {
    pub fn load_file(path: &std::path::Path) -> Result<Robot, RobotError> {
        let file = path.display().to_string();
        let text =
            crate::input_file::read_text(path, crate::input_file::cap::ROBOT, "a robot file")
                .map_err(|e| fail(&file, None, e.to_string()))?;
        crate::provenance::record_input(path, text.as_bytes());
        Robot::from_toml(&text, &file)
    }

    pub fn from_toml(text: &str, file: &str) -> Result<Robot, RobotError> {
        let raw: Raw = toml::from_str(text).map_err(|e| {
            // serde reports a missing table or key at the document's start
            // ("line 1, column 1"); name what is missing instead.
            let msg = e.message();
            match msg.strip_prefix("missing field ") {
                Some(what) if e.span().is_none_or(|s| s.start == 0) => fail(
                    file,
                    None,
                    format!("missing table or key {what} (see docs/robot-format.md)"),
                ),
                _ => fail(
                    file,
                    None,
                    format!("not a valid robot file: {}", e.to_string().trim_end()),
                ),
            }
        })?;
        let v = Check { file };
        let m = &raw.motor;
        let motor = MotorParams {
            resistance_ohm: v.pos("motor.resistance_ohm", m.resistance_ohm)?,
            inductance_h: v.pos("motor.inductance_h", m.inductance_h)?,
            torque_constant_n_m_per_a: v.pos(
                "motor.torque_constant_n_m_per_a",
                m.torque_constant_n_m_per_a,
            )?,
            rotor_inertia_kg_m2: v.pos("motor.rotor_inertia_kg_m2", m.rotor_inertia_kg_m2)?,
            viscous_friction_n_m_s: v
                .non_neg("motor.viscous_friction_n_m_s", m.viscous_friction_n_m_s)?,
            coulomb_friction_n_m: v
                .non_neg("motor.coulomb_friction_n_m", m.coulomb_friction_n_m)?,
        };
        let b = &raw.battery;
        let ocv = b
            .ocv
            .clone()
            .unwrap_or_else(|| crate::robot::battery::LIPO_OCV_TABLE.to_vec());
        if ocv.len() < 2
            || ocv.windows(2).any(|w| w[1].0 <= w[0].0 || w[1].0.is_nan())
            || ocv
                .iter()
                .any(|p| p.1 <= 0.0 || !p.1.is_finite() || !p.0.is_finite())
        {
            return Err(fail(
                file,
                Some("battery.ocv"),
                "needs >= 2 [soc, volts] pairs, soc strictly increasing, volts > 0",
            ));
        }
        let soc0 = b.initial_soc.unwrap_or(1.0);
        if !(0.0..=1.0).contains(&soc0) {
            return Err(fail(
                file,
                Some("battery.initial_soc"),
                format!("must be within 0..=1, got {soc0}"),
            ));
        }
        let cell = Cell {
            capacity_mah: v.pos("battery.capacity_mah", b.capacity_mah)?,
            internal_resistance_ohm: v
                .non_neg("battery.internal_resistance_ohm", b.internal_resistance_ohm)?,
            initial_soc: soc0,
            ocv,
        };
        let d = &raw.divider;
        if d.bottom_ohm == 0 || d.adc_ref_mv == 0 {
            let f = if d.bottom_ohm == 0 {
                "divider.bottom_ohm"
            } else {
                "divider.adc_ref_mv"
            };
            return Err(fail(file, Some(f), "must be positive"));
        }
        let mut battery = BatteryConfig::new(d.top_ohm, d.bottom_ohm, d.adc_ref_mv);
        battery.cutoff_mv = d.cutoff_mv.unwrap_or(battery.cutoff_mv);
        battery.warn_mv = d.warn_mv.unwrap_or(battery.warn_mv);
        battery.recharged_mv = d.recharged_mv.unwrap_or(battery.recharged_mv);
        battery.cutoff_debounce_us = d
            .cutoff_debounce_ms
            .map_or(battery.cutoff_debounce_us, |ms| ms * 1000);
        let c = &raw.controller;
        if !(0.0..=1.0).contains(&c.max_duty) {
            return Err(fail(
                file,
                Some("controller.max_duty"),
                format!("must be within 0..=1, got {}", c.max_duty),
            ));
        }
        if c.target_motor_mv == 0 {
            return Err(fail(
                file,
                Some("controller.target_motor_mv"),
                "must be positive",
            ));
        }
        let controller = ControllerConfig {
            ramp_us: c.ramp_ms.saturating_mul(1000),
            target_motor_mv: c.target_motor_mv,
            max_duty: Duty::from_ratio((c.max_duty * 65536.0).round() as u32, 65536),
            max_run_us: (v.pos("controller.max_run_s", c.max_run_s)? * 1e6) as u64,
        };
        let tick_us = c.tick_us.unwrap_or(1000);
        if !(10..=100_000).contains(&tick_us) {
            return Err(fail(
                file,
                Some("controller.tick_us"),
                format!("must be within 10..=100000, got {tick_us}"),
            ));
        }
        let adc_period_us = c.adc_period_us.unwrap_or(20_000).max(tick_us);
        let drive = PwmDrive {
            carrier_hz: v.pos("drive.carrier_hz", raw.drive.carrier_hz)?,
            diode_drop_v: v.non_neg("drive.diode_drop_v", raw.drive.diode_drop_v)?,
        };
        let keys = KeyMap {
            address: raw.remote.address,
            on: raw.remote.on,
            off: raw.remote.off,
        };
        if keys.on == keys.off {
            return Err(fail(
                file,
                Some("remote.on"),
                "the on and off keys must differ",
            ));
        }
        let (bd, ch) = (&raw.body, &raw.channel);
        let setup = Case {
            id: String::new(),
            wavelength_mm: 1.0,
            amplitude_mm: 1.0,
            tail_length_mm: 1.0,
            wire_diameter_mm: 1.0,
            handedness: Handedness::Right,
            frequency_hz: 1.0,
            channel_diameter_mm: v.pos("channel.diameter_mm", ch.diameter_mm)?,
            channel_length_mm: v.pos("channel.length_mm", ch.length_mm)?,
            channel_closed: ch.closed,
            orientation: ch.orientation,
            viscosity_pa_s: v.pos("channel.viscosity_pa_s", ch.viscosity_pa_s)?,
            density_kg_m3: v.pos("channel.density_kg_m3", ch.density_kg_m3)?,
            body_diameter_mm: v.pos("body.diameter_mm", bd.diameter_mm)?,
            body_length_mm: v.pos("body.length_mm", bd.length_mm)?,
            coupler_diameter_mm: v.non_neg("body.coupler_diameter_mm", bd.coupler_diameter_mm)?,
            coupler_length_mm: v.non_neg("body.coupler_length_mm", bd.coupler_length_mm)?,
            coupler_gap_mm: crate::data::DEFAULT_COUPLER_GAP_MM,
            body_profile: None,
            net_weight_g: 0.0,
            u_mm_s: None,
            omega_body_hz: None,
            inputs: Default::default(),
            recorded: Default::default(),
        };
        if setup.body_diameter_mm >= setup.channel_diameter_mm {
            return Err(fail(
                file,
                Some("body.diameter_mm"),
                "the body must fit in the channel",
            ));
        }
        let start_height_mm = match ch.start_height_mm {
            Some(h) => Some(v.non_neg("channel.start_height_mm", h)?),
            None => None,
        };
        let mut model = Model::base();
        model.coefficients =
            CoefficientSet::from_name(&raw.model.coefficients).ok_or_else(|| {
                fail(
                    file,
                    Some("model.coefficients"),
                    format!(
                        "unknown set `{}`; known: gray-hancock, lighthill",
                        raw.model.coefficients
                    ),
                )
            })?;
        for (i, spec) in raw.model.effects.iter().enumerate() {
            let e = parse_effect_spec(spec)
                .map_err(|e| fail(file, Some(&format!("model.effects[{i}]")), e.to_string()))?;
            model.effects.push(e);
        }
        if raw.tails.is_empty() {
            return Err(fail(
                file,
                Some("tail"),
                "the robot needs at least one [[tail]]",
            ));
        }
        let mut tails = Vec::new();
        for (i, t) in raw.tails.iter().enumerate() {
            let f = |name: &str| format!("tail[{i}].{name}");
            let (lambda, amp, len, wire) = (
                v.pos(&f("wavelength_mm"), t.wavelength_mm)?,
                v.pos(&f("amplitude_mm"), t.amplitude_mm)?,
                v.pos(&f("length_mm"), t.length_mm)?,
                v.pos(&f("wire_diameter_mm"), t.wire_diameter_mm)?,
            );
            if 2.0 * amp + wire >= setup.channel_diameter_mm {
                return Err(fail(
                    file,
                    Some(&f("amplitude_mm")),
                    "the helix must fit in the channel",
                ));
            }
            let load_inertia_kg_m2 = match t.load_inertia_kg_m2 {
                Some(j) => v.non_neg(&f("load_inertia_kg_m2"), j)?,
                None => helix_inertia_kg_m2(lambda, amp, len, wire),
            };
            let observed_f_hz = match t.observed_f_hz {
                Some(x) => Some(v.pos(&f("observed_f_hz"), x)?),
                None => None,
            };
            tails.push(Tail {
                id: t.id.clone(),
                wavelength_mm: lambda,
                amplitude_mm: amp,
                length_mm: len,
                wire_diameter_mm: wire,
                handedness: t.handedness.unwrap_or(Handedness::Right),
                load_inertia_kg_m2,
                observed_f_hz,
            });
        }
        let robot = Robot {
            name: raw.name.unwrap_or_else(|| "unnamed robot".into()),
            motor,
            cell,
            battery,
            controller,
            tick_us,
            adc_period_us,
            drive,
            keys,
            setup,
            start_height_mm,
            model,
            tails,
        };
        super::robot_limits::check(&robot, file)?;
        Ok(robot)
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

/// A copper helix at radius `B_o` about its axis: `m B_o^2`.
fn helix_inertia_kg_m2(lambda_mm: f64, amp_mm: f64, len_mm: f64, wire_mm: f64) -> f64 {
    let chord_m =
        len_mm * 1e-3 * (1.0 + (std::f64::consts::TAU * amp_mm / lambda_mm).powi(2)).sqrt();
    let mass_kg = COPPER_KG_M3 * std::f64::consts::PI * (0.5e-3 * wire_mm).powi(2) * chord_m;
    mass_kg * (amp_mm * 1e-3).powi(2)
}

pub(super) fn fail(file: &str, field: Option<&str>, message: impl Into<String>) -> RobotError {
    RobotError {
        file: file.to_string(),
        field: field.map(str::to_string),
        message: message.into(),
    }
}

struct Check<'a> {
    file: &'a str,
}

impl Check<'_> {
    fn pos(&self, field: &str, v: f64) -> Result<f64, RobotError> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(fail(
                self.file,
                Some(field),
                format!("must be a finite number > 0, got {v}"),
            ))
        }
    }
    fn non_neg(&self, field: &str, v: f64) -> Result<f64, RobotError> {
        if v.is_finite() && v >= 0.0 {
            Ok(v)
        } else {
            Err(fail(
                self.file,
                Some(field),
                format!("must be a finite number >= 0, got {v}"),
            ))
        }
    }
}
