//! The battery reading against the cell's PWM ripple. Each on-pulse draws
//! about half an ampere through the cell's 0.6 ohm, so the terminal swings
//! by ~0.3 V at 25 kHz. The firmware converts in the middle of the
//! on-pulse (`firmware/src/battery_adc.rs`), where the cell is loaded as the
//! motor sees it, which is the voltage the rate controller's feed-forward
//! divides by. A reading of the cycle mean (an RC-filtered tap) or at a
//! phase in the off-time (what a free-running conversion hits part of the
//! time) overestimates it.

use swimbot::robot::{LiPo, LiPoParams};
use swimbot_integration::{AdcPhase, Rig, Supply, KEYS};
use swimbot_shared::board;
use swimbot_shared::MotorState;

const TAU: f64 = std::f64::consts::TAU;

/// After the rate has settled (8 s from the On frame), over the next
/// second: the mean battery reading against the mean on-pulse voltage
/// (relative), the mean ripple (rest minus on-pulse voltage), and the
/// largest relative rate error, for a half-charged cell.
fn reading_and_rate(phase: AdcPhase) -> (f64, f64, f64) {
    let mut rig = Rig::new(Supply::Cell(LiPo::with_soc(LiPoParams::CELL_70MAH, 0.5)));
    rig.adc_phase = phase;
    rig.run_for(200_000);
    let frame_end = rig.press(KEYS.on);
    rig.run_for(frame_end - rig.t_us + 8_000_000);
    let held = rig.run_for(1_000_000);
    assert!(held.iter().all(|s| s.state == MotorState::Running));
    let n = held.len() as f64;
    let reading = held
        .iter()
        .map(|s| f64::from(s.battery.mv) / 1e3 / s.supply_on_v - 1.0)
        .sum::<f64>()
        / n;
    let ripple = held
        .iter()
        .map(|s| s.supply_v + s.supply_current_a * 0.6 / s.duty.as_f64() - s.supply_on_v)
        .sum::<f64>()
        / n;
    let set_hz = f64::from(board::DEFAULT_RATE_MHZ) / 1e3;
    let rate_err = held
        .iter()
        .map(|s| (s.speed_rad_s / TAU / set_hz - 1.0).abs())
        .fold(0.0, f64::max);
    (reading, ripple, rate_err)
}

#[test]
fn reading_mid_on_pulse_sees_the_loaded_cell() {
    let (mid, ripple, mid_rate) = reading_and_rate(AdcPhase::MidOnPulse);
    // The ripple is real: about 0.3 V.
    assert!((0.2..0.45).contains(&ripple), "ripple {ripple} V");
    // Within 1 %: the mid-pulse reading sees the settled on-current, while
    // the on-pulse mean includes the current's rise (L/R = 3.3 us of a
    // ~35 us pulse), so the reading comes out slightly low.
    assert!(mid.abs() < 0.01, "mid-pulse reading off by {mid}");
    // The cycle mean (an RC-filtered tap) or a reading late in the period
    // (switch off: the rest voltage) overestimate the cell by the ripple.
    let (mean, _, mean_rate) = reading_and_rate(AdcPhase::CycleMean);
    let (rest, _, rest_rate) = reading_and_rate(AdcPhase::Fixed(0.99));
    println!("reading vs on-pulse voltage: mid-pulse {mid:+.4}, cycle-mean {mean:+.4}, rest {rest:+.4}; ripple {ripple:.3} V");
    assert!(mean > 0.01 && mean > mid.abs(), "cycle mean: {mean}");
    assert!(rest > 0.05, "rest reading: {rest}");
    // The rate loop absorbs a biased reading into its learned line: the
    // rate holds within 1 % whichever phase the reading takes; the
    // reading's bias only costs feed-forward accuracy after a step.
    for (name, e) in [("mid", mid_rate), ("mean", mean_rate), ("rest", rest_rate)] {
        assert!(e < 0.01, "{name}: rate off by {e}");
    }
}
