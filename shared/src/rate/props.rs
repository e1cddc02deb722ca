//! Properties of the rate estimator and controller over arbitrary inputs:
//! no panic, the duty within its clamp, the motor never started without an
//! On and a set-point, every fault stopping it at once, and exact rates
//! wherever the timer stands.

use super::*;
use crate::battery::{BatteryLevel, BatteryStatus};
use crate::command::Command;
use crate::controller::{Duty, Event, MotorState};
use proptest::prelude::*;

const OK: BatteryStatus = BatteryStatus {
    mv: 3_900,
    level: BatteryLevel::Ok,
};

fn levels(k: u32) -> (bool, bool) {
    [(false, false), (false, true), (true, true), (true, false)][(k % 4) as usize]
}

#[derive(Clone, Copy, Debug)]
enum Input {
    Wait(u64),
    Command(Option<Command>),
    Set(Option<u32>),
    Battery(u16, BatteryLevel),
    /// An edge `dt` after the previous one, with arbitrary levels.
    Edge(u32, bool, bool),
}

fn any_input() -> impl Strategy<Value = Input> {
    let level = prop_oneof![
        Just(BatteryLevel::Ok),
        Just(BatteryLevel::Low),
        Just(BatteryLevel::Cutoff),
        Just(BatteryLevel::Fault)
    ];
    prop_oneof![
        (0u64..5_000_000).prop_map(Input::Wait),
        prop_oneof![
            Just(None),
            Just(Some(Command::On)),
            Just(Some(Command::Off))
        ]
        .prop_map(Input::Command),
        proptest::option::of(any::<u32>()).prop_map(Input::Set),
        (any::<u16>(), level).prop_map(|(mv, l)| Input::Battery(mv, l)),
        (any::<u32>(), any::<bool>(), any::<bool>()).prop_map(|(t, a, b)| Input::Edge(t, a, b)),
    ]
}

fn any_config() -> impl Strategy<Value = RateConfig> {
    (
        0u32..=1 << 17,
        0u32..=1 << 17,
        0u32..=100,
        0u32..1_000_000,
        any::<u16>(),
    )
        .prop_map(|(kp, ki, max_pct, ramp_us, intercept_max_mv)| {
            let mut c = RateConfig::DEFAULT;
            c.intercept_max_mv = intercept_max_mv;
            c.kp_q16 = kp;
            c.ki_per_turn_q16 = ki;
            c.motor.max_duty = Duty::percent(max_pct);
            c.motor.ramp_us = ramp_us;
            c.motor.max_run_us = 60_000_000;
            c
        })
}

proptest! {
    /// Whatever arrives in whatever order: no panic; the duty within the
    /// clamp; zero duty when off, without a set-point, on a fault, or when
    /// the battery forbids; and a non-zero duty only in a run that an On
    /// with a set-point started.
    #[test]
    fn the_motor_runs_only_when_asked_and_safe(
        cfg in any_config(),
        pole_pairs in 0u8..=12,
        t0 in any::<u64>(),
        inputs in proptest::collection::vec(any_input(), 1..400),
    ) {
        let mut ctl = RateController::new(cfg);
        let mut est = RateEstimator::new(HallConfig { pole_pairs, ..HallConfig::RING_8_POLE });
        let (mut now, mut edge_t) = (t0, t0 as u32);
        let mut battery = OK;
        let mut started = false;
        for input in inputs {
            let mut command = None;
            match input {
                Input::Wait(dt) => now = now.saturating_add(dt),
                Input::Command(c) => command = c,
                Input::Set(s) => ctl.set_rate_mhz(s),
                Input::Battery(mv, level) => battery = BatteryStatus { mv, level },
                Input::Edge(dt, a, b) => {
                    edge_t = edge_t.wrapping_add(dt);
                    est.edge(edge_t, a, b);
                }
            }
            let out = ctl.step(now, command, battery, &mut est);
            match out.event {
                Some(RateEvent::Motor(Event::Started)) => started = true,
                Some(RateEvent::Motor(Event::Stopped(_)) | RateEvent::Fault(_)) => started = false,
                _ => {}
            }
            prop_assert!(out.duty <= cfg.motor.max_duty);
            if let Some(RateEvent::Fault(_)) = out.event {
                prop_assert_eq!((out.duty, out.state), (Duty::ZERO, MotorState::Off));
            }
            if out.state == MotorState::Off || ctl.set_rate().is_none() || !battery.allows_motor() || command == Some(Command::Off) {
                prop_assert_eq!(out.duty, Duty::ZERO);
            }
            if out.duty != Duty::ZERO {
                prop_assert!(started, "duty without a started run");
                prop_assert!(out.reference_mhz > 0);
            }
            if out.state == MotorState::Off {
                started = false;
            }
        }
    }

    /// A steady rotation anywhere on the 32-bit timer (zero, the wrap, huge
    /// values) is measured to the rounding of the integer division.
    #[test]
    fn steady_rotation_is_measured_exactly(
        t0 in any::<u32>(),
        pole_pairs in 1u8..=8,
        interval_us in 1_000u32..2_000_000,
        turns in 1u32..4,
    ) {
        let cfg = HallConfig { pole_pairs, max_plausible_mhz: u32::MAX, window_reset_us: u32::MAX, ..HallConfig::RING_8_POLE };
        let e = cfg.edges_per_turn() as u32;
        let mut est = RateEstimator::new(cfg);
        est.edge(t0, false, false);
        let mut t = t0;
        for k in 1..=e * turns {
            t = t.wrapping_add(interval_us);
            let (a, b) = levels(k);
            est.edge(t, a, b);
        }
        let r = est.estimate().expect("a rate after a turn");
        prop_assert!(r.whole_turn);
        let want = 1e9 / (f64::from(e) * f64::from(interval_us));
        prop_assert!((f64::from(r.rate_mhz) - want).abs() <= 1.0, "{} vs {}", r.rate_mhz, want);
        prop_assert_eq!(est.fault(), None);
    }

    /// No edges, one edge, or edges with equal or backward timestamps give
    /// no rate and no panic.
    #[test]
    fn degenerate_edges_give_no_rate(t in any::<u32>(), a: bool, b: bool) {
        let mut est = RateEstimator::new(HallConfig::RING_8_POLE);
        prop_assert_eq!(est.estimate(), None);
        est.edge(t, a, b);
        prop_assert_eq!(est.estimate(), None);
        // The next forward level at the same timestamp: a zero interval.
        let next = match (a, b) { (false, false) => (false, true), (false, true) => (true, true), (true, true) => (true, false), (true, false) => (false, false) };
        est.edge(t, next.0, next.1);
        prop_assert_eq!(est.estimate(), None);
    }
}

/// A run without any edge ends in a stall fault after the stall time, with
/// the motor off and a new On needed.
#[test]
fn no_edges_while_driven_is_a_stall() {
    let cfg = RateConfig::DEFAULT;
    let mut ctl = RateController::new(cfg);
    let mut est = RateEstimator::new(HallConfig::RING_8_POLE);
    ctl.set_rate_mhz(Some(1_000));
    assert_eq!(
        ctl.step(0, Some(Command::On), OK, &mut est).event,
        Some(RateEvent::Motor(Event::Started))
    );
    let limit = u64::from(cfg.motor.ramp_us) + u64::from(cfg.stall_us);
    let before = ctl.step(limit, None, OK, &mut est);
    assert!(before.duty > Duty::ZERO && before.state == MotorState::Running);
    let after = ctl.step(limit + 1, None, OK, &mut est);
    assert_eq!(after.event, Some(RateEvent::Fault(SensorFault::Stalled)));
    assert_eq!((after.duty, after.state), (Duty::ZERO, MotorState::Off));
    assert_eq!(ctl.step(limit + 2, None, OK, &mut est).duty, Duty::ZERO);
}

/// An edge whose timestamp is later than the pass's clock (it arrived
/// after the firmware read the timer and before it drained the Hall queue)
/// is a fresh edge, not one 71 minutes old: no stall fault. The emulator's
/// run-log scenario stopped the motor this way, 7.4 s into a run at 1 Hz.
#[test]
fn an_edge_newer_than_the_pass_clock_is_no_stall() {
    let cfg = RateConfig::DEFAULT;
    let mut ctl = RateController::new(cfg);
    let mut est = RateEstimator::new(HallConfig::RING_8_POLE);
    ctl.set_rate_mhz(Some(1_000));
    ctl.step(0, Some(Command::On), OK, &mut est);
    // At 1 Hz (16 edges a turn) past the soft start and the stall time.
    let (mut t_us, mut k) = (0u64, 0u32);
    while t_us < u64::from(cfg.motor.ramp_us + cfg.stall_us) + 1_000_000 {
        t_us += 62_500;
        k += 1;
        let (a, b) = levels(k);
        est.edge(t_us as u32, a, b);
        let o = ctl.step(t_us + 300, None, OK, &mut est);
        assert_ne!(
            o.state,
            MotorState::Off,
            "stopped at {t_us} us: {:?}",
            o.event
        );
    }
    let (a, b) = levels(k + 1);
    est.edge((t_us + 62_520) as u32, a, b);
    let o = ctl.step(t_us + 62_500, None, OK, &mut est);
    assert_eq!((o.event, o.state), (None, MotorState::Running));
    // Silence from that edge on is still a stall, after the stall time.
    let last = t_us + 62_520 + u64::from(cfg.stall_us);
    assert_eq!(
        ctl.step(last, None, OK, &mut est).state,
        MotorState::Running
    );
    let o = ctl.step(last + 1, None, OK, &mut est);
    assert_eq!(o.event, Some(RateEvent::Fault(SensorFault::Stalled)));
}

/// On without a set-point starts nothing; the soft start ramps the
/// reference; removing the set-point stops the motor.
#[test]
fn set_point_gates_the_start_and_the_ramp_shapes_it() {
    let cfg = RateConfig::DEFAULT;
    let mut ctl = RateController::new(cfg);
    let mut est = RateEstimator::new(HallConfig::RING_8_POLE);
    let o = ctl.step(0, Some(Command::On), OK, &mut est);
    assert_eq!((o.event, o.duty), (Some(RateEvent::NoSetPoint), Duty::ZERO));
    ctl.set_rate_mhz(Some(5_000));
    assert_eq!(ctl.set_rate(), Some(cfg.max_rate_mhz), "clamped");
    ctl.set_rate_mhz(Some(800));
    ctl.step(10, Some(Command::On), OK, &mut est);
    let half = ctl.step(10 + u64::from(cfg.motor.ramp_us) / 2, None, OK, &mut est);
    assert_eq!(half.reference_mhz, 400);
    // 175 mV + 0.7 V/Hz x 0.4 Hz = 455 mV of 3.9 V.
    assert_eq!(half.duty, Duty::from_ratio(455, 3_900));
    // Once running, a set-point change slews at 1 Hz/s whatever the pass
    // rate: 100 ms after a 10 ms pass, 100 mHz further.
    let run_from = 10 + u64::from(cfg.motor.ramp_us);
    assert_eq!(ctl.step(run_from, None, OK, &mut est).reference_mhz, 800);
    ctl.set_rate_mhz(Some(1_500));
    assert_eq!(
        ctl.step(run_from + 10_000, None, OK, &mut est)
            .reference_mhz,
        810
    );
    assert_eq!(
        ctl.step(run_from + 110_000, None, OK, &mut est)
            .reference_mhz,
        910
    );
    ctl.set_rate_mhz(None);
    let o = ctl.step(run_from + 200_000, None, OK, &mut est);
    assert_eq!((o.duty, o.state), (Duty::ZERO, MotorState::Off));
}

proptest! {
    /// The learned line from any points: no panic, `g` within its bounds,
    /// the intercept never above the plausible maximum nor above a point's
    /// voltage.
    #[test]
    fn the_learned_line_stays_in_bounds(
        intercept_max_mv in any::<u16>(),
        points in proptest::collection::vec((0u32..=20_000, 0u32..=65_535, 0u32..=2_000), 1..6),
    ) {
        let cfg = RateConfig { intercept_max_mv, ..RateConfig::DEFAULT };
        let mut line = line::LearnedLine::new(&cfg);
        let mut last: Option<line::LinePoint> = None;
        for (mv, rate_mhz, ref_mhz) in points {
            let at = line::LinePoint { mv, rate_mhz };
            match last {
                Some(a) if line.secant(&cfg, a, at) => {
                    prop_assert!(line.intercept_mv <= u32::from(intercept_max_mv).min(a.mv));
                }
                _ => line.one_point(&cfg, at, ref_mhz),
            }
            prop_assert!((cfg.gain_min_q16..=cfg.gain_max_q16).contains(&line.gain_q16));
            let _ = line.voltage_mv(&cfg, ref_mhz, 1 << 16);
            last = Some(at);
        }
    }
}
