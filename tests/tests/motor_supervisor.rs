//! The motor supervisor in the whole main loop, against the host's motor
//! and cell: a tail that jams while running, one that only crawls, and a
//! healthy run that it must leave alone. See `swimbot_shared::supervisor`.

use swimbot_integration::{Rig, Supply, KEYS, TAIL_DAMPING_N_M_S};
use swimbot_shared::rate::SensorFault;
use swimbot_shared::{board, MotorState};

const TAU: f64 = std::f64::consts::TAU;

/// Running at the default 1 Hz, 3 s after On.
fn running() -> Rig {
    let mut rig = Rig::new(Supply::full_cell());
    rig.run_for(200_000);
    let frame_end = rig.press(KEYS.on);
    rig.run_for(frame_end - rig.t_us + 3_000_000);
    assert_eq!(rig.main_loop.state(), MotorState::Running);
    assert!(rig.faults.is_empty(), "{:?}", rig.faults);
    rig
}

/// The tail's load grows to `damping` at the current time; when the motor
/// was stopped after that and why, and the rotor's mean rate meanwhile.
fn load_until_stopped(rig: &mut Rig, damping: f64, limit_us: u64) -> (u64, SensorFault, f64) {
    rig.tail_damping_n_m_s = damping;
    let (t0, a0) = (rig.t_us, rig.angle_turns);
    let stop = rig
        .run_until(limit_us, |s| s.state == MotorState::Off)
        .expect("the motor stops");
    let after = stop.t_us - t0;
    let rate_hz = (rig.angle_turns - a0) / (after as f64 * 1e-6);
    let fault = rig.faults.last().expect("a fault").1;
    (after, fault, rate_hz)
}

#[test]
fn a_tail_jammed_while_running_stops_within_two_seconds() {
    let mut rig = running();
    let (after, fault, rate_hz) = load_until_stopped(&mut rig, 1.0, 6_000_000);
    assert_eq!(fault, SensorFault::Jammed);
    assert!(after <= 2_100_000, "{after} us");
    assert!(rate_hz < 0.1, "{rate_hz} Hz");
    // Off, and stays off.
    let later = rig.run_for(2_000_000);
    assert!(later.iter().all(|s| s.duty.raw() == 0));
}

#[test]
fn a_tail_crawling_at_a_tenth_of_a_hertz_stops_within_two_seconds() {
    // Thirteen times the nominal load: at the 3.7 V ceiling (0.53 A near
    // stall, 0.42 mN m) the rotor settles near 0.1 Hz, beyond the
    // controller's 8x line factor, so the controller saturates.
    let mut rig = running();
    let damping = 13.0 * TAIL_DAMPING_N_M_S;
    let (after, fault, rate_hz) = load_until_stopped(&mut rig, damping, 10_000_000);
    assert_eq!(fault, SensorFault::Jammed);
    assert!(after <= 2_100_000 + 1_000_000, "{after} us");
    assert!((0.05..0.2).contains(&rate_hz), "{rate_hz} Hz");
    let s = rig.last.expect("a sample");
    assert!(s.speed_rad_s.abs() / TAU < 1.0);
}

#[test]
fn the_mean_motor_voltage_stays_under_the_rating_from_a_full_cell() {
    // The heaviest load the controller may meet: it asks for more than
    // the rating, the controller's clamp and the supervisor hold it.
    let mut rig = running();
    rig.tail_damping_n_m_s = 4.0 * TAIL_DAMPING_N_M_S;
    let samples = rig.run_for(1_500_000);
    let rated = f64::from(board::MOTOR_RATED_MV) / 1e3;
    let worst = samples.iter().map(|s| s.motor_v).fold(0.0, f64::max);
    assert!(worst <= rated + 0.02, "{worst} V");
}

#[test]
fn a_healthy_minute_is_left_alone() {
    let mut rig = running();
    let samples = rig.run_for(60_000_000);
    assert!(rig.faults.is_empty(), "{:?}", rig.faults);
    assert!(samples.iter().all(|s| s.state == MotorState::Running));
    let heat = rig.main_loop.supervisor().heating();
    assert!(heat.winding_uk > 0, "the run heats the winding");
}
