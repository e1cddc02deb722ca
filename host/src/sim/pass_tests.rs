//! `swimbot sim` runs the firmware's own main-loop pass
//! (`swimbot_shared::MainLoop`), and the battery input it feeds is the
//! loaded voltage the firmware converts in the middle of the PWM on-pulse.

use super::rate::Driver;
use super::{default_robot, simulate, BatteryReading, Options, Outcome, Robot, Script};
use swimbot_shared::{Controller, Event, MainLoop, MainLoopConfig, StopReason};

fn board(robot: &Robot) -> MainLoopConfig {
    MainLoopConfig {
        keys: robot.keys,
        battery: robot.battery,
        sample_period_us: robot.adc_period_us,
        ..MainLoopConfig::BOARD
    }
}

/// A fresh shared pass, fed the script's edges and the readings the sim
/// took, makes every decision the sim made: same ticks asking for a
/// reading, same events, the same duty at every tick. So there is no
/// second copy of the loop in the sim to drift from the chip's.
#[test]
fn a_fresh_shared_pass_replays_the_sims_decisions() {
    let mut robot = default_robot();
    // A nearly empty cell, so the replay crosses the warning and cut-off
    // decisions too, and a short debounce to reach them in seconds.
    robot.cell.initial_soc = 0.02;
    robot.battery.cutoff_debounce_us = 200_000;
    let script = Script::parse("on@0s,off@1.5s,on@2s").expect("script");
    let opts = Options {
        max_time_s: 8.0,
        sample_every_s: 1e-3,
        stop_at_top: false,
        ..Options::default()
    };
    let o = simulate(&robot, &script, &opts).expect("simulation");
    let stops: Vec<_> = o
        .events
        .iter()
        .filter(|e| matches!(e.1, Event::Stopped(_)))
        .collect();
    assert!(
        stops
            .iter()
            .any(|e| e.1 == Event::Stopped(StopReason::LowBattery)),
        "the run should reach the cut-off: {:?}",
        o.events
    );

    // The voltage mode in the chip's pass, as the sim carries it.
    let voltage = Driver::new(Controller::new(robot.controller), None);
    let mut pass = MainLoop::with_control(board(&robot), voltage, false);
    let edges = script.edges(&robot.keys);
    let (mut next_edge, mut readings) = (0, o.battery_readings.iter().peekable());
    let mut events = Vec::new();
    for (k, sample) in o.samples.iter().enumerate().take(o.ticks as usize) {
        let t_us = (k as u64 + 1) * robot.tick_us;
        assert_eq!(sample.t_s, t_us as f64 * 1e-6, "one sample a tick");
        let first = next_edge;
        while edges.get(next_edge).is_some_and(|e| e.1 <= t_us) {
            next_edge += 1;
        }
        let tick_edges = edges[first..next_edge].iter().map(|&(l, t)| (l, t as u32));
        let out = pass.pass(t_us, tick_edges, [], || match readings.next() {
            Some(&(t, counts)) if t == t_us => counts,
            other => panic!("the pass reads at {t_us} us, the sim read {other:?}"),
        });
        if let Some(e) = out.event {
            events.push((t_us as f64 * 1e-6, e));
        }
        assert_eq!(sample.duty, out.duty.as_f64(), "duty at {t_us} us");
        assert_eq!(sample.state, out.state, "state at {t_us} us");
    }
    assert!(readings.peek().is_none(), "the sim read more often");
    assert_eq!(events, o.events);
}

/// A quick discharge: a 7 mAh cell from 30 % at 2.0 V to the motor (duty
/// 0.55-0.65: the ripple's gap between the loaded and the mean voltage is
/// widest at middling duty), stopped by the cut-off.
fn discharge(reading: BatteryReading) -> (Outcome, f64) {
    let mut robot = default_robot();
    robot.cell.capacity_mah = 7.0;
    robot.cell.initial_soc = 0.3;
    robot.controller.target_motor_mv = 2_000;
    let opts = Options {
        max_time_s: 120.0,
        sample_every_s: 0.01,
        stop_at_top: false,
        battery_reading: reading,
        ..Options::default()
    };
    let o = simulate(&robot, &Script::on_at_zero(), &opts).expect("simulation");
    let cut_s = o
        .events
        .iter()
        .find(|e| e.1 == Event::Stopped(StopReason::LowBattery))
        .map(|e| e.0)
        .expect("the cut-off stops the motor");
    (o, cut_s)
}

/// The cut-off is specified under load (3.3 V): the monitor averages 160 ms
/// of readings and needs 1 s below, so it must trip 1.0-1.3 s after the
/// voltage in the middle of the on-pulse first falls under 3.3 V. Read as
/// the cycle mean (an RC-filtered tap), the same cell trips seconds late,
/// with the loaded voltage already well under the cut-off.
#[test]
fn the_cut_off_trips_on_the_loaded_voltage_read_mid_pulse() {
    let lag = |o: &Outcome, cut_s: f64| {
        let below = o
            .samples
            .iter()
            .find(|s| s.duty > 0.0 && s.loaded_v < 3.3)
            .expect("the loaded voltage reaches the cut-off");
        cut_s - below.t_s
    };
    let (mid, cut_mid) = discharge(BatteryReading::MidOnPulse);
    let (mean, cut_mean) = discharge(BatteryReading::CycleMean);
    let (lag_mid, lag_mean) = (lag(&mid, cut_mid), lag(&mean, cut_mean));
    let at_cut = |o: &Outcome, t: f64| {
        let s = o
            .samples
            .iter()
            .rev()
            .find(|s| s.t_s < t - 0.05)
            .expect("sample");
        (s.loaded_v, s.battery_v, s.duty)
    };
    eprintln!(
        "mid-pulse: cut at {cut_mid:.2} s, {lag_mid:.2} s after the loaded voltage crossed 3.3 V, \
         (loaded, mean, duty) just before {:?}; cycle mean: cut at {cut_mean:.2} s, {lag_mean:.2} s after, {:?}",
        at_cut(&mid, cut_mid),
        at_cut(&mean, cut_mean)
    );
    assert!(
        (1.0..1.3).contains(&lag_mid),
        "mid-pulse reading: {lag_mid} s"
    );
    assert!(
        lag_mean > 2.0,
        "the cycle mean should trip late: {lag_mean} s"
    );
    // The sim's two voltages: the pulse's middle sags below the mean.
    let s = mid.samples.iter().find(|s| s.duty > 0.5).expect("running");
    assert!(s.battery_v - s.loaded_v > 0.05, "{s:?}");
}
