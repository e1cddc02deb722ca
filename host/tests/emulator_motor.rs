//! The emulator's rotor (`tests/emulator/lib/rotor.js`, the `swimbot-motor`
//! crate compiled to WebAssembly) loads the robot file's calibrated motor
//! and tail 1's load from `tests/emulator/lib/motor.json`. This test
//! derives those numbers from `host/data/robot.toml` and its model and
//! fails when the file is stale; with `SWIMBOT_WRITE_EMULATOR_MOTOR=1` it
//! writes the file instead. The file also carries operating points of the
//! host's steady motor (voltage -> rate), which the emulator's `17-motor`
//! scenario checks against the WebAssembly rotor.

use serde_json::{json, Value};
use std::f64::consts::TAU;
use swimbot::sim::default_robot;
use swimbot::sim::hydro::Hydro;

const VOLTS: [f64; 4] = [1.0, 2.0, 3.0, 3.65];

fn expected() -> Value {
    let robot = default_robot();
    let tail = 0;
    let h = Hydro::new(&robot.model, &robot.case(tail, 1.0)).expect("model");
    let motor = robot.motor_with(tail);
    let p = motor.params;
    let points: Vec<Value> = VOLTS
        .iter()
        .map(|&v| {
            let s = motor
                .steady_state(v, h.tau0_n_m, h.damping_n_m_s)
                .expect("turns");
            json!({ "volts": v, "rate_hz": s.speed_rad_s / TAU, "current_a": s.current_a })
        })
        .collect();
    json!({
        "about": "generated from host/data/robot.toml (tail-1, the file's [model]) by host/tests/emulator_motor.rs: SWIMBOT_WRITE_EMULATOR_MOTOR=1 cargo test -p swimbot --test integration emulator_motor",
        "tail": robot.tails[tail].id,
        "resistance_ohm": p.resistance_ohm,
        "inductance_h": p.inductance_h,
        "torque_constant_n_m_per_a": p.torque_constant_n_m_per_a,
        "rotor_inertia_kg_m2": p.rotor_inertia_kg_m2,
        "viscous_friction_n_m_s": p.viscous_friction_n_m_s,
        "coulomb_friction_n_m": p.coulomb_friction_n_m,
        "load_inertia_kg_m2": motor.load_inertia_kg_m2,
        "load_tau0_n_m": h.tau0_n_m,
        "load_damping_n_m_s": h.damping_n_m_s,
        "steady": points,
    })
}

fn close(a: &Value, b: &Value) -> bool {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            (x - y).abs() <= 1e-9 * y.abs().max(1e-30)
        }
        (Value::Object(x), Value::Object(y)) => {
            x.len() == y.len() && x.iter().all(|(k, v)| y.get(k).is_some_and(|w| close(v, w)))
        }
        (Value::Array(x), Value::Array(y)) => {
            x.len() == y.len() && x.iter().zip(y).all(|(v, w)| close(v, w))
        }
        _ => a == b,
    }
}

#[test]
fn the_emulator_motor_file_is_the_robot_files() {
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/emulator/lib/motor.json");
    let want = expected();
    if std::env::var_os("SWIMBOT_WRITE_EMULATOR_MOTOR").is_some() {
        let text = serde_json::to_string_pretty(&want).unwrap() + "\n";
        std::fs::write(&path, text).expect("write motor.json");
    }
    let text = std::fs::read_to_string(&path).expect("tests/emulator/lib/motor.json");
    let have: Value = serde_json::from_str(&text).expect("motor.json is JSON");
    assert!(
        close(&have, &want),
        "{} is stale: regenerate it with SWIMBOT_WRITE_EMULATOR_MOTOR=1 cargo test -p swimbot \
         --test integration emulator_motor\nhave {have}\nwant {want}",
        path.display()
    );
}

/// The host's integrator, through the shared rotor, lands on the host's
/// analytic steady state: the model the emulator runs is the one the host
/// simulates.
#[test]
fn the_shared_rotor_reaches_the_host_steady_state() {
    let robot = default_robot();
    let h = Hydro::new(&robot.model, &robot.case(0, 1.0)).expect("model");
    let motor = robot.motor_with(0);
    let load = swimbot_motor::TailLoad {
        tau0_n_m: h.tau0_n_m,
        damping_n_m_s: h.damping_n_m_s,
    };
    for v in VOLTS {
        let mut r = swimbot_motor::Rotor::new(motor, load, 16);
        let mut buf = [swimbot_motor::Crossing::default(); 4];
        for _ in 0..1_000 {
            r.step(v, 1e-3, &mut buf);
        }
        let s = motor.steady_state(v, h.tau0_n_m, h.damping_n_m_s).unwrap();
        assert!(
            (r.speed_rad_s() / s.speed_rad_s - 1.0).abs() < 1e-6,
            "{v} V: {} vs {}",
            r.speed_rad_s(),
            s.speed_rad_s
        );
        assert!((r.current_a() / s.current_a - 1.0).abs() < 1e-6);
    }
}
