//! `swimbot-motor`'s [`Rotor`] behind a C ABI for WebAssembly: the RP2040
//! emulator's board (`tests/emulator/lib/rotor.js`) instantiates this
//! module once per simulated rotor (each instance has its own memory, so
//! one rotor per instance) and steps it every millisecond with the mean
//! motor voltage the chip's PWM produced.
//!
//! Build: `cargo build -p swimbot-motor-wasm --target wasm32-unknown-unknown
//! --release` (`cargo xtask test` does it before the emulator step).
//! The module imports nothing; plain `f64`/`u32` arguments, no allocation
//! crosses the boundary.

use std::cell::RefCell;
use swimbot_motor::{Crossing, Motor, MotorParams, Rotor, TailLoad};

/// The most edges one step reports (a 1 ms step at 2 Hz passes 0.03).
const MAX_CROSSINGS: usize = 64;

thread_local! {
    static ROTOR: RefCell<Option<Rotor>> = const { RefCell::new(None) };
    static CROSSINGS: RefCell<[Crossing; MAX_CROSSINGS]> =
        const { RefCell::new([Crossing { after_s: 0.0, a: false, b: false }; MAX_CROSSINGS]) };
}

fn with<T: Default>(f: impl FnOnce(&mut Rotor) -> T) -> T {
    ROTOR.with(|r| r.borrow_mut().as_mut().map(f).unwrap_or_default())
}

/// Sets up the rotor at rest: the motor's constants (SI), the coupler and
/// tail inertia, the tail's load `tau_0 + c w` and the ring's edges a turn.
#[no_mangle]
#[allow(clippy::too_many_arguments)]
pub extern "C" fn rotor_init(
    resistance_ohm: f64,
    inductance_h: f64,
    torque_constant_n_m_per_a: f64,
    rotor_inertia_kg_m2: f64,
    viscous_friction_n_m_s: f64,
    coulomb_friction_n_m: f64,
    load_inertia_kg_m2: f64,
    load_tau0_n_m: f64,
    load_damping_n_m_s: f64,
    edges_per_turn: u32,
) {
    let params = MotorParams {
        resistance_ohm,
        inductance_h,
        torque_constant_n_m_per_a,
        rotor_inertia_kg_m2,
        viscous_friction_n_m_s,
        coulomb_friction_n_m,
    };
    let load = TailLoad {
        tau0_n_m: load_tau0_n_m,
        damping_n_m_s: load_damping_n_m_s,
    };
    let rotor = Rotor::new(
        Motor::new(params, load_inertia_kg_m2),
        load,
        edges_per_turn as usize,
    );
    ROTOR.with(|r| *r.borrow_mut() = Some(rotor));
}

#[no_mangle]
pub extern "C" fn rotor_set_load_scale(factor: f64) {
    with(|r| r.set_load_scale(factor));
}

#[no_mangle]
pub extern "C" fn rotor_set_brake_n_m(torque_n_m: f64) {
    with(|r| r.set_brake_n_m(torque_n_m));
}

#[no_mangle]
pub extern "C" fn rotor_set_edge_offset(index: u32, pitches: f64) {
    with(|r| r.set_edge_offset(index as usize, pitches));
}

/// One step; returns the number of edges passed (read them with
/// `rotor_crossing_after_s` and `rotor_crossing_levels`).
#[no_mangle]
pub extern "C" fn rotor_step(volts: f64, dt_s: f64) -> u32 {
    CROSSINGS.with(|c| with(|r| r.step(volts, dt_s, &mut c.borrow_mut()[..]) as u32))
}

#[no_mangle]
pub extern "C" fn rotor_crossing_after_s(i: u32) -> f64 {
    CROSSINGS.with(|c| c.borrow().get(i as usize).map_or(f64::NAN, |x| x.after_s))
}

/// Bit 0: latch A, bit 1: latch B.
#[no_mangle]
pub extern "C" fn rotor_crossing_levels(i: u32) -> u32 {
    CROSSINGS.with(|c| {
        c.borrow()
            .get(i as usize)
            .map_or(0, |x| u32::from(x.a) | (u32::from(x.b) << 1))
    })
}

#[no_mangle]
pub extern "C" fn rotor_rate_hz() -> f64 {
    with(|r| r.rate_hz())
}

#[no_mangle]
pub extern "C" fn rotor_current_a() -> f64 {
    with(|r| r.current_a())
}

#[no_mangle]
pub extern "C" fn rotor_turns() -> f64 {
    with(|r| r.turns())
}

#[no_mangle]
pub extern "C" fn rotor_volts_for_rate(rate_hz: f64) -> f64 {
    with(|r| r.volts_for_rate(rate_hz))
}

/// The load scale giving `rate_hz` at `volts`; NaN if none does.
#[no_mangle]
pub extern "C" fn rotor_load_scale_for(volts: f64, rate_hz: f64) -> f64 {
    ROTOR.with(|r| {
        r.borrow()
            .as_ref()
            .and_then(|r| r.load_scale_for(volts, rate_hz))
            .unwrap_or(f64::NAN)
    })
}
