//! The documented ranges of a robot file beyond "positive and finite": the
//! motor, cell and drive constants a cm-scale robot can have, unique and
//! printable tail ids, every tail's case inside the dataset limits
//! (`data::limits`: lengths, turns, the robot fitting in the channel) and a
//! start height inside the channel. Values outside make the motor
//! equations stiff beyond the tick, or the climb meaningless, so they are
//! refused with the file, the field, the value and the range.

use super::robot::{fail, Robot, RobotError};
use crate::data::limits::{check_case, check_id};

/// `(field, min, max, why)` of the motor, cell and drive constants.
const RANGES: &[(&str, f64, f64, &str)] = &[
    (
        "motor.resistance_ohm",
        1e-3,
        1e4,
        "winding resistance of a small DC motor",
    ),
    (
        "motor.inductance_h",
        1e-8,
        1.0,
        "below 10 nH the electrical time constant is far shorter than any PWM period",
    ),
    (
        "motor.torque_constant_n_m_per_a",
        1e-6,
        10.0,
        "torque constant of a motor from micro to kW size",
    ),
    (
        "motor.rotor_inertia_kg_m2",
        1e-14,
        1e-2,
        "rotor inertia from a 2 mm to a 20 cm motor",
    ),
    (
        "motor.viscous_friction_n_m_s",
        0.0,
        1.0,
        "bearing friction per rad/s",
    ),
    (
        "motor.coulomb_friction_n_m",
        0.0,
        10.0,
        "bearing friction torque",
    ),
    (
        "battery.capacity_mah",
        1e-3,
        1e6,
        "from a coin cell to a car battery",
    ),
    (
        "battery.internal_resistance_ohm",
        0.0,
        1e3,
        "cell internal resistance",
    ),
    ("drive.carrier_hz", 1.0, 1e7, "PWM carrier frequency"),
    (
        "drive.diode_drop_v",
        0.0,
        10.0,
        "free-wheel diode forward drop",
    ),
];

fn check_range(file: &str, field: &str, v: f64) -> Result<(), RobotError> {
    let Some(&(_, min, max, why)) = RANGES.iter().find(|r| r.0 == field) else {
        return Ok(());
    };
    if (min..=max).contains(&v) {
        return Ok(());
    }
    Err(fail(
        file,
        Some(field),
        format!(
            "{} is outside the allowed range {min:e}..={max:e} ({why})",
            crate::data::limits::show(v)
        ),
    ))
}

/// Checks a parsed robot against the documented ranges.
pub(super) fn check(r: &Robot, file: &str) -> Result<(), RobotError> {
    let m = &r.motor;
    for (f, v) in [
        ("motor.resistance_ohm", m.resistance_ohm),
        ("motor.inductance_h", m.inductance_h),
        (
            "motor.torque_constant_n_m_per_a",
            m.torque_constant_n_m_per_a,
        ),
        ("motor.rotor_inertia_kg_m2", m.rotor_inertia_kg_m2),
        ("motor.viscous_friction_n_m_s", m.viscous_friction_n_m_s),
        ("motor.coulomb_friction_n_m", m.coulomb_friction_n_m),
        ("battery.capacity_mah", r.cell.capacity_mah),
        (
            "battery.internal_resistance_ohm",
            r.cell.internal_resistance_ohm,
        ),
        ("drive.carrier_hz", r.drive.carrier_hz),
        ("drive.diode_drop_v", r.drive.diode_drop_v),
    ] {
        check_range(file, f, v)?;
    }
    if let Some(&(soc, v)) = r.cell.ocv.iter().find(|p| p.1 > 100.0) {
        return Err(fail(
            file,
            Some("battery.ocv"),
            format!("{v} V at soc {soc}: a single cell is below 100 V"),
        ));
    }
    for (i, t) in r.tails.iter().enumerate() {
        let field = |name: &str| format!("tail[{i}].{name}");
        check_id(&t.id).map_err(|e| fail(file, Some(&field("id")), e.to_string()))?;
        if r.tails[..i].iter().any(|o| o.id == t.id) {
            return Err(fail(
                file,
                Some(&field("id")),
                format!("duplicate tail id `{}`", t.id),
            ));
        }
        // Adjacent turns touch when the wire is as thick as the pitch: no
        // helix, and the local drag coefficients' logarithm ln(lambda/D_t)
        // loses its meaning well before (Gray & Hancock, eqs. 4-5).
        if t.wire_diameter_mm >= t.wavelength_mm {
            return Err(fail(
                file,
                Some(&field("wire_diameter_mm")),
                format!(
                    "{} mm is not thinner than the wavelength ({} mm): adjacent turns of the helix would touch",
                    crate::data::limits::show(t.wire_diameter_mm),
                    crate::data::limits::show(t.wavelength_mm)
                ),
            ));
        }
        // Any rate inside the limits will do: the geometry is what is checked.
        let case = r.case(i, 1.0);
        check_case(&case).map_err(|(f, e)| {
            let name = match f {
                "tail_length_mm" => field("length_mm"),
                "id" | "wavelength_mm" | "amplitude_mm" | "wire_diameter_mm" => field(f),
                "channel_diameter_mm" => "channel.diameter_mm".into(),
                "channel_length_mm" => "channel.length_mm".into(),
                "body_diameter_mm" => "body.diameter_mm".into(),
                "body_length_mm" => "body.length_mm".into(),
                "coupler_diameter_mm" | "coupler_length_mm" => format!("body.{f}"),
                other => format!("channel.{other}"),
            };
            fail(file, Some(&name), e)
        })?;
        let start = r.start_height_mm(i);
        if start >= r.setup.channel_length_mm {
            return Err(fail(
                file,
                Some("channel.start_height_mm"),
                format!(
                    "the nose starts at {start} mm, not below the top of the {} mm channel (with tail `{}`)",
                    r.setup.channel_length_mm, t.id
                ),
            ));
        }
    }
    Ok(())
}
