//! The main-loop pass on the host: sampling schedule, start, cut-off
//! latch, dormant condition, Hall edges, the stall fault and the rate keys.
use super::*;
use crate::battery::{BatteryLevel, BatteryStatus};
use crate::nec::{for_each_edge, frame_pulses_us};
use crate::rate::SensorFault;

fn counts(mv: u32) -> u16 {
    board::BATTERY.mv_to_counts(mv)
}

/// Passes every millisecond up to `until_us`, at `mv`, no edges.
fn idle<C: MotorControl>(m: &mut MainLoop<C>, from_us: u64, until_us: u64, mv: u32) -> PassOutput {
    let mut last = m.pass(from_us, [], [], || counts(mv));
    let mut t = from_us;
    while t < until_us {
        t += 1_000;
        last = m.pass(t, [], [], || counts(mv));
    }
    last
}

fn on_frame() -> heapless::Vec<(Level, u32), 80> {
    let mut v = heapless::Vec::new();
    for_each_edge(
        300_000,
        &frame_pulses_us(board::NEC_ADDRESS, board::NEC_CMD_ON),
        |l, t| {
            let _ = v.push((l, t));
        },
    );
    v
}

#[test]
fn samples_on_schedule_and_starts_on_a_frame() {
    let mut m = MainLoop::new(false);
    let o = m.pass(0, [], [], || counts(3_900));
    assert_eq!(o.sample, Some(counts(3_900)));
    assert_eq!(m.pass(19_999, [], [], || unreachable!()).sample, None);
    assert!(m.pass(20_000, [], [], || counts(3_900)).sample.is_some());
    idle(&mut m, 20_000, 290_000, 3_900);
    let o = m.pass(400_000, on_frame(), [], || counts(3_900));
    assert_eq!(o.command, Some(Command::On));
    assert_eq!(o.event, Some(Event::Started));
    let o = idle(&mut m, 400_000, 800_000, 3_900);
    assert_eq!(o.state, MotorState::Running);
    assert!(m.motor_on());
}

#[test]
fn a_wake_from_dormant_reads_the_cell_at_once() {
    let mut m = MainLoop::new(false);
    idle(&mut m, 0, 10_000, 3_900);
    // The timer stood still in DORMANT: the next pass is 1 us later on it.
    m.woke();
    let o = m.pass(10_001, [], [], || counts(3_100));
    assert_eq!(o.sample, Some(counts(3_100)), "no reading on the wake-up");
    // Then the schedule again: every 20 ms from the wake-up's reading.
    assert!(m.pass(29_000, [], [], || counts(3_100)).sample.is_none());
    assert!(m.pass(30_001, [], [], || counts(3_100)).sample.is_some());
}

#[test]
fn another_robot_samples_on_its_own_period() {
    let cfg = MainLoopConfig {
        sample_period_us: 5_000,
        ..MainLoopConfig::BOARD
    };
    let mut m = MainLoop::with_config(cfg, false);
    assert!(m.pass(0, [], [], || counts(3_900)).sample.is_some());
    assert!(m.pass(4_999, [], [], || counts(3_900)).sample.is_none());
    assert!(m.pass(5_000, [], [], || counts(3_900)).sample.is_some());
}

#[test]
fn a_remembered_cutoff_refuses_on_and_reports_its_release() {
    let mut m = MainLoop::new(true);
    idle(&mut m, 0, 300_000, 3_600);
    let o = m.pass(400_000, on_frame(), [], || counts(3_600));
    assert_eq!(o.battery.level, BatteryLevel::Cutoff);
    assert_eq!(o.duty, Duty::ZERO);
    let o = idle(&mut m, 400_000, 420_000, 4_100);
    assert_eq!(o.latch_changed, None, "the average still reads low");
    let mut released = None;
    let mut t = 420_000;
    while released.is_none() && t < 1_000_000 {
        t += 1_000;
        released = m.pass(t, [], [], || counts(4_100)).latch_changed;
    }
    assert_eq!(released, Some(false));
}

#[test]
fn dormant_only_after_a_quiet_idle_stretch() {
    let mut m = MainLoop::new(false);
    let quiet = board::DORMANT_AFTER_IDLE_US;
    assert!(!idle(&mut m, 0, quiet - 1_000, 3_900).may_go_dormant);
    assert!(idle(&mut m, quiet - 1_000, quiet, 3_900).may_go_dormant);
    // An edge (even noise) restarts the count.
    let o = m.pass(quiet + 1_000, [(Level::Low, 5)], [], || counts(3_900));
    assert!(!o.may_go_dormant);
}

#[test]
fn a_stalled_motor_is_stopped_shown_and_needs_a_new_on() {
    let mut m = MainLoop::new(false);
    idle(&mut m, 0, 290_000, 3_900);
    let o = m.pass(400_000, on_frame(), [], || counts(3_900));
    assert_eq!(o.event, Some(Event::Started));
    assert!(o.hall_power, "the latches are powered with the start");
    // The duty is zero on the starting pass; the next pass comes when
    // the ramp's reference first is non-zero, and its duty is.
    assert_eq!(o.duty, Duty::ZERO);
    let soon = o.next_pass_in_us.expect("an early pass after the start");
    assert!(soon < board::WAKE_PERIOD_US);
    let o = m.pass(400_000 + u64::from(soon), [], [], || counts(3_900));
    assert!(o.duty > Duty::ZERO && o.next_pass_in_us.is_none());
    // No Hall edge: driven past the soft start for the stall time.
    let stall_us = u64::from(board::RATE.stall_us);
    let ramp_us = u64::from(board::RATE.motor.ramp_us);
    let before = idle(&mut m, 400_000, 400_000 + ramp_us + stall_us, 3_900);
    assert!(before.duty > Duty::ZERO && before.fault.is_none());
    let o = m.pass(400_000 + ramp_us + stall_us + 1_000, [], [], || {
        counts(3_900)
    });
    assert_eq!(o.fault, Some(SensorFault::Stalled));
    assert_eq!(
        (o.duty, o.state, o.hall_power),
        (Duty::ZERO, MotorState::Off, false)
    );
    assert_eq!(o.led, LedMode::Fault);
    let later = idle(&mut m, 6_000_000, 8_000_000, 3_900);
    assert_eq!((later.duty, later.led), (Duty::ZERO, LedMode::Fault));
}

#[test]
fn quadrature_edges_become_the_rate() {
    let mut m = MainLoop::new(false);
    idle(&mut m, 0, 290_000, 3_900);
    m.pass(400_000, on_frame(), [], || counts(3_900));
    // 0.5 Hz: 16 edges a turn, one every 125 ms, Gray order A leads B.
    let gray = [(false, false), (false, true), (true, true), (true, false)];
    let mut out = None;
    for k in 0..40u32 {
        let t = 500_000 + u64::from(k) * 125_000;
        let (a, b) = gray[k as usize % 4];
        let e = HallEdge {
            t_us: t as u32,
            a,
            b,
        };
        out = Some(m.pass(t, [], [e], || counts(3_900)));
    }
    let o = out.unwrap_or_else(|| unreachable!());
    assert_eq!(o.rate_mhz, Some(500));
    assert_eq!(o.fault, None);
    assert!(o.reference_mhz > 0 && o.reference_mhz <= board::DEFAULT_RATE_MHZ);
}

fn frame(address: u8, command: u8, at_us: u32) -> heapless::Vec<(Level, u32), 80> {
    let mut v = heapless::Vec::new();
    for_each_edge(at_us, &frame_pulses_us(address, command), |l, t| {
        let _ = v.push((l, t));
    });
    v
}

#[test]
fn rate_keys_change_only_the_set_point_and_other_remotes_are_counted() {
    use crate::nec::REPEAT_PULSES_US;
    let keys = board::SET_POINT_KEYS;
    let mut m = MainLoop::new(false);
    idle(&mut m, 0, 290_000, 3_900);
    let o = m.pass(
        400_000,
        frame(board::NEC_ADDRESS, keys.presets[0].0, 300_000),
        [],
        || counts(3_900),
    );
    assert_eq!(o.set_point_changed, Some(keys.presets[0].1));
    assert_eq!(
        (o.state, o.duty),
        (MotorState::Off, Duty::ZERO),
        "a key never starts"
    );
    let o = m.pass(
        500_000,
        frame(board::NEC_ADDRESS, keys.faster, 400_000),
        [],
        || counts(3_900),
    );
    assert_eq!(o.set_point_changed, Some(keys.presets[0].1 + keys.step_mhz));
    // A held key's repeat frames step nothing.
    let mut rep = heapless::Vec::<(Level, u32), 8>::new();
    for_each_edge(520_000, &REPEAT_PULSES_US, |l, t| {
        let _ = rep.push((l, t));
    });
    assert_eq!(
        m.pass(600_000, rep, [], || counts(3_900)).set_point_changed,
        None
    );
    assert_eq!(
        m.controller().set_rate(),
        Some(keys.presets[0].1 + keys.step_mhz)
    );
    // Another remote's On: ignored, counted.
    let o = m.pass(800_000, frame(0x5a, board::NEC_CMD_ON, 700_000), [], || {
        counts(3_900)
    });
    assert_eq!(
        (o.command, o.state, o.foreign_frames),
        (None, MotorState::Off, 1)
    );
}

/// A controller that wants the motor on at a fixed duty whenever the
/// battery allows and has no set-point or sensor, to see the pass's
/// decisions around any controller (the host sim's voltage mode is one).
#[derive(Clone, Debug)]
struct Fixed(Duty);

impl MotorControl for Fixed {
    fn hall_edge(&mut self, _: HallEdge) {}
    fn step(
        &mut self,
        _: u64,
        _: Option<Command>,
        battery: BatteryStatus,
    ) -> crate::rate::RateOutput {
        let on = battery.allows_motor();
        crate::rate::RateOutput {
            duty: if on { self.0 } else { Duty::ZERO },
            state: if on {
                MotorState::Running
            } else {
                MotorState::Off
            },
            event: None,
            reference_mhz: 0,
            saturated: false,
        }
    }
    fn set_rate(&self) -> Option<u32> {
        None
    }
    fn set_rate_mhz(&mut self, _: Option<u32>) {}
    fn senses_rotor(&self) -> bool {
        false
    }
    fn fault(&self) -> Option<SensorFault> {
        None
    }
    fn rate_mhz(&self) -> Option<u32> {
        None
    }
}

#[test]
fn another_controller_gets_the_same_sampling_latch_and_led() {
    let mut m = MainLoop::with_control(MainLoopConfig::BOARD, Fixed(Duty::percent(50)), false);
    let o = m.pass(0, [], [], || counts(3_900));
    assert_eq!(o.sample, Some(counts(3_900)));
    assert_eq!(
        (o.duty, o.led, o.hall_power),
        (
            Duty::percent(50),
            LedMode::of(o.state, o.battery, false),
            true
        )
    );
    assert!(
        m.motor_on(),
        "its duty is what the next reading was loaded by"
    );
    assert_eq!(m.pass(19_999, [], [], || unreachable!()).sample, None);
    // A cell under the cut-off for the debounce: the pass latches it and
    // the controller is handed a status that stops the motor.
    let o = idle(&mut m, 20_000, 1_400_000, 3_100);
    assert_eq!(o.battery.level, BatteryLevel::Cutoff);
    assert_eq!((o.duty, o.hall_power), (Duty::ZERO, false));
    assert!(m.monitor().cutoff_latched());
}
