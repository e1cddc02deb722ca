//! A robot file's tables, checked one by one: serde reads the raw tables
//! (rejecting unknown keys), then each table becomes its part of the
//! [`Robot`] here, every value checked so that an error names the file and
//! the field. The ranges that hold across tables (a tail that fits the
//! channel, a motor the cell can drive) are `robot_limits`'.

use super::raw::{
    Raw, RawBattery, RawBody, RawChannel, RawController, RawDivider, RawModel, RawMotor, RawTail,
};
use super::robot::{fail, Cell, Robot, RobotError, Tail};
use crate::data::Case;
use crate::effects::Catalogue;
use crate::model::Model;
use crate::physics::coefficients::CoefficientSet;
use crate::physics::geometry::Handedness;
use crate::robot::{MotorParams, PwmDrive};
use swimbot_shared::{BatteryConfig, ControllerConfig, Duty, KeyMap};

/// Copper, for the tail's inertia when the file does not give it.
const COPPER_KG_M3: f64 = 8960.0;

/// The robot in `text`, the file named `file`; its effects are looked up
/// in `catalogue`.
pub(super) fn parse(text: &str, file: &str, catalogue: &Catalogue) -> Result<Robot, RobotError> {
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
    let v = Check { file, catalogue };
    let motor = v.motor(&raw.motor)?;
    let cell = v.cell(&raw.battery)?;
    let battery = v.divider(&raw.divider)?;
    let (controller, tick_us, adc_period_us) = v.controller(&raw.controller)?;
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
    let setup = v.setup(&raw.body, &raw.channel)?;
    let start_height_mm = match raw.channel.start_height_mm {
        Some(h) => Some(v.non_neg("channel.start_height_mm", h)?),
        None => None,
    };
    let model = v.model(&raw.model)?;
    let tails = v.tails(&raw.tails, &setup)?;
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

/// The file being checked: every error names it.
struct Check<'a> {
    file: &'a str,
    catalogue: &'a Catalogue,
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

    fn motor(&self, m: &RawMotor) -> Result<MotorParams, RobotError> {
        Ok(MotorParams {
            resistance_ohm: self.pos("motor.resistance_ohm", m.resistance_ohm)?,
            inductance_h: self.pos("motor.inductance_h", m.inductance_h)?,
            torque_constant_n_m_per_a: self.pos(
                "motor.torque_constant_n_m_per_a",
                m.torque_constant_n_m_per_a,
            )?,
            rotor_inertia_kg_m2: self.pos("motor.rotor_inertia_kg_m2", m.rotor_inertia_kg_m2)?,
            viscous_friction_n_m_s: self
                .non_neg("motor.viscous_friction_n_m_s", m.viscous_friction_n_m_s)?,
            coulomb_friction_n_m: self
                .non_neg("motor.coulomb_friction_n_m", m.coulomb_friction_n_m)?,
        })
    }

    fn cell(&self, b: &RawBattery) -> Result<Cell, RobotError> {
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
                self.file,
                Some("battery.ocv"),
                "needs >= 2 [soc, volts] pairs, soc strictly increasing, volts > 0",
            ));
        }
        let soc0 = b.initial_soc.unwrap_or(1.0);
        if !(0.0..=1.0).contains(&soc0) {
            return Err(fail(
                self.file,
                Some("battery.initial_soc"),
                format!("must be within 0..=1, got {soc0}"),
            ));
        }
        Ok(Cell {
            capacity_mah: self.pos("battery.capacity_mah", b.capacity_mah)?,
            internal_resistance_ohm: self
                .non_neg("battery.internal_resistance_ohm", b.internal_resistance_ohm)?,
            initial_soc: soc0,
            ocv,
        })
    }

    fn divider(&self, d: &RawDivider) -> Result<BatteryConfig, RobotError> {
        if d.bottom_ohm == 0 || d.adc_ref_mv == 0 {
            let f = if d.bottom_ohm == 0 {
                "divider.bottom_ohm"
            } else {
                "divider.adc_ref_mv"
            };
            return Err(fail(self.file, Some(f), "must be positive"));
        }
        let mut battery = BatteryConfig::new(d.top_ohm, d.bottom_ohm, d.adc_ref_mv);
        battery.cutoff_mv = d.cutoff_mv.unwrap_or(battery.cutoff_mv);
        battery.warn_mv = d.warn_mv.unwrap_or(battery.warn_mv);
        battery.recharged_mv = d.recharged_mv.unwrap_or(battery.recharged_mv);
        battery.cutoff_debounce_us = d
            .cutoff_debounce_ms
            .map_or(battery.cutoff_debounce_us, |ms| ms * 1000);
        Ok(battery)
    }

    /// The controller, the main loop's tick and the battery's sampling
    /// period (never shorter than a tick).
    fn controller(&self, c: &RawController) -> Result<(ControllerConfig, u64, u64), RobotError> {
        if !(0.0..=1.0).contains(&c.max_duty) {
            return Err(fail(
                self.file,
                Some("controller.max_duty"),
                format!("must be within 0..=1, got {}", c.max_duty),
            ));
        }
        if c.target_motor_mv == 0 {
            return Err(fail(
                self.file,
                Some("controller.target_motor_mv"),
                "must be positive",
            ));
        }
        let controller = ControllerConfig {
            ramp_us: c.ramp_ms.saturating_mul(1000),
            target_motor_mv: c.target_motor_mv,
            max_duty: Duty::from_ratio((c.max_duty * 65536.0).round() as u32, 65536),
            max_run_us: (self.pos("controller.max_run_s", c.max_run_s)? * 1e6) as u64,
        };
        let tick_us = c.tick_us.unwrap_or(1000);
        if !(10..=100_000).contains(&tick_us) {
            return Err(fail(
                self.file,
                Some("controller.tick_us"),
                format!("must be within 10..=100000, got {tick_us}"),
            ));
        }
        let adc_period_us = c.adc_period_us.unwrap_or(20_000).max(tick_us);
        Ok((controller, tick_us, adc_period_us))
    }

    /// A template case: body, channel and fluid; the tail is filled per use.
    fn setup(&self, bd: &RawBody, ch: &RawChannel) -> Result<Case, RobotError> {
        let setup = Case {
            id: String::new(),
            wavelength_mm: 1.0,
            amplitude_mm: 1.0,
            tail_length_mm: 1.0,
            wire_diameter_mm: 1.0,
            handedness: Handedness::Right,
            frequency_hz: 1.0,
            channel_diameter_mm: self.pos("channel.diameter_mm", ch.diameter_mm)?,
            channel_length_mm: self.pos("channel.length_mm", ch.length_mm)?,
            channel_closed: ch.closed,
            orientation: ch.orientation,
            viscosity_pa_s: self.pos("channel.viscosity_pa_s", ch.viscosity_pa_s)?,
            density_kg_m3: self.pos("channel.density_kg_m3", ch.density_kg_m3)?,
            body_diameter_mm: self.pos("body.diameter_mm", bd.diameter_mm)?,
            body_length_mm: self.pos("body.length_mm", bd.length_mm)?,
            coupler_diameter_mm: self
                .non_neg("body.coupler_diameter_mm", bd.coupler_diameter_mm)?,
            coupler_length_mm: self.non_neg("body.coupler_length_mm", bd.coupler_length_mm)?,
            coupler_gap_mm: crate::data::DEFAULT_COUPLER_GAP_MM,
            body_profile: None,
            net_weight_g: 0.0,
            u_mm_s: None,
            omega_body_hz: None,
            inputs: Default::default(),
            recorded: Default::default(),
            derived: Default::default(),
        };
        // The body model (a prolate spheroid, physics::body) needs length
        // >= diameter; found only when the first case was simulated, the
        // error named that case rather than this field.
        if setup.body_length_mm < setup.body_diameter_mm {
            return Err(fail(
                self.file,
                Some("body.length_mm"),
                format!(
                    "{} mm is shorter than the body's diameter ({} mm, body.diameter_mm): the prolate-spheroid body model needs length >= diameter",
                    crate::data::limits::show(setup.body_length_mm),
                    crate::data::limits::show(setup.body_diameter_mm)
                ),
            ));
        }
        if setup.body_diameter_mm >= setup.channel_diameter_mm {
            return Err(fail(
                self.file,
                Some("body.diameter_mm"),
                "the body must fit in the channel",
            ));
        }
        Ok(setup)
    }

    fn model(&self, m: &RawModel) -> Result<Model, RobotError> {
        let mut model = Model::base();
        model.coefficients = CoefficientSet::from_name(&m.coefficients).ok_or_else(|| {
            fail(
                self.file,
                Some("model.coefficients"),
                format!(
                    "unknown set `{}`; known: gray-hancock, lighthill",
                    m.coefficients
                ),
            )
        })?;
        for (i, spec) in m.effects.iter().enumerate() {
            let e = self.catalogue.parse_effect_spec(spec).map_err(|e| {
                fail(
                    self.file,
                    Some(&format!("model.effects[{i}]")),
                    e.to_string(),
                )
            })?;
            model.effects.push(e);
        }
        Ok(model)
    }

    fn tails(&self, raw: &[RawTail], setup: &Case) -> Result<Vec<Tail>, RobotError> {
        if raw.is_empty() {
            return Err(fail(
                self.file,
                Some("tail"),
                "the robot needs at least one [[tail]]",
            ));
        }
        raw.iter()
            .enumerate()
            .map(|(i, t)| self.tail(i, t, setup))
            .collect()
    }

    fn tail(&self, i: usize, t: &RawTail, setup: &Case) -> Result<Tail, RobotError> {
        let f = |name: &str| format!("tail[{i}].{name}");
        let (lambda, amp, len, wire) = (
            self.pos(&f("wavelength_mm"), t.wavelength_mm)?,
            self.pos(&f("amplitude_mm"), t.amplitude_mm)?,
            self.pos(&f("length_mm"), t.length_mm)?,
            self.pos(&f("wire_diameter_mm"), t.wire_diameter_mm)?,
        );
        if 2.0 * amp + wire >= setup.channel_diameter_mm {
            return Err(fail(
                self.file,
                Some(&f("amplitude_mm")),
                "the helix must fit in the channel",
            ));
        }
        let load_inertia_kg_m2 = match t.load_inertia_kg_m2 {
            Some(j) => self.non_neg(&f("load_inertia_kg_m2"), j)?,
            None => helix_inertia_kg_m2(lambda, amp, len, wire),
        };
        let observed_f_hz = match t.observed_f_hz {
            Some(x) => Some(self.pos(&f("observed_f_hz"), x)?),
            None => None,
        };
        Ok(Tail {
            id: t.id.clone(),
            wavelength_mm: lambda,
            amplitude_mm: amp,
            length_mm: len,
            wire_diameter_mm: wire,
            handedness: t.handedness.unwrap_or(Handedness::Right),
            load_inertia_kg_m2,
            observed_f_hz,
        })
    }
}

/// A copper helix at radius `B_o` about its axis: `m B_o^2`.
fn helix_inertia_kg_m2(lambda_mm: f64, amp_mm: f64, len_mm: f64, wire_mm: f64) -> f64 {
    let chord_m =
        len_mm * 1e-3 * (1.0 + (std::f64::consts::TAU * amp_mm / lambda_mm).powi(2)).sqrt();
    let mass_kg = COPPER_KG_M3 * std::f64::consts::PI * (0.5e-3 * wire_mm).powi(2) * chord_m;
    mass_kg * (amp_mm * 1e-3).powi(2)
}
