//! The pass's pairing window, the unpaired robot, the USB hold-off and the
//! flash-erase condition.
use super::*;
use crate::nec::{for_each_edge, frame_pulses_us, REPEAT_PULSES_US};

fn counts(mv: u32) -> u16 {
    board::BATTERY.mv_to_counts(mv)
}

type Edges = heapless::Vec<(Level, u32), 80>;

fn frame(address: u8, command: u8, at_us: u64) -> Edges {
    let mut v = Edges::new();
    for_each_edge(at_us as u32, &frame_pulses_us(address, command), |l, t| {
        let _ = v.push((l, t));
    });
    v
}

fn repeat(at_us: u64) -> Edges {
    let mut v = Edges::new();
    for_each_edge(at_us as u32, &REPEAT_PULSES_US, |l, t| {
        let _ = v.push((l, t));
    });
    v
}

/// Hold `command` of `address` from `t0`: a frame, then a repeat every
/// 108 ms for `held_us`, each decoded by a pass 80 ms after it began.
fn hold(m: &mut MainLoop, t0: u64, address: u8, command: u8, held_us: u64) -> PassOutput {
    let mut out = m.pass(t0 + 80_000, frame(address, command, t0), [], || {
        counts(3_900)
    });
    let mut newly = out.newly_paired;
    let mut t = t0 + 108_000;
    while t <= t0 + held_us {
        out = m.pass(t + 15_000, repeat(t), [], || counts(3_900));
        newly = newly.or(out.newly_paired);
        t += 108_000;
    }
    PassOutput {
        newly_paired: newly,
        ..out
    }
}

fn on(m: &mut MainLoop, address: u8, t0: u64) -> PassOutput {
    m.pass(
        t0 + 80_000,
        frame(address, board::NEC_CMD_ON, t0),
        [],
        || counts(3_900),
    )
}

#[test]
fn an_unpaired_robot_obeys_nobody_until_a_hold_pairs_it() {
    let mut m = MainLoop::new(false);
    m.set_paired(None);
    let o = m.pass(0, [], [], || counts(3_900));
    assert!(o.pairing_window && o.paired.is_none());
    assert_eq!(o.led, LedMode::Pairing);
    let o = on(&mut m, 0x00, 200_000);
    assert_eq!((o.state, o.foreign_frames), (MotorState::Off, 1));
    // Holding On pairs nothing; holding Off for 1 s does.
    let o = hold(&mut m, 500_000, 0x5a, board::NEC_CMD_ON, 1_200_000);
    assert_eq!((o.newly_paired, o.state), (None, MotorState::Off));
    let o = hold(&mut m, 2_000_000, 0x5a, board::NEC_CMD_OFF, 1_100_000);
    assert_eq!(o.newly_paired, Some(0x5a));
    assert_eq!((o.paired, o.pairing_window), (Some(0x5a), false));
    assert_eq!(o.led, LedMode::Off, "the pairing pattern stops");
    assert_eq!(on(&mut m, 0x5a, 3_500_000).state, MotorState::Ramping);
    // The old address is now a foreign remote's; Off from ours stops.
    let o = m.pass(
        3_800_000,
        frame(0x00, board::NEC_CMD_OFF, 3_700_000),
        [],
        || counts(3_900),
    );
    assert_ne!(o.state, MotorState::Off);
    let o = m.pass(
        4_000_000,
        frame(0x5a, board::NEC_CMD_OFF, 3_900_000),
        [],
        || counts(3_900),
    );
    assert_eq!(o.state, MotorState::Off);
}

#[test]
fn after_the_window_an_unpaired_robot_stays_unpaired() {
    let mut m = MainLoop::new(false);
    m.set_paired(None);
    m.pass(0, [], [], || counts(3_900));
    let o = hold(&mut m, 5_100_000, 0x5a, board::NEC_CMD_OFF, 1_500_000);
    assert_eq!((o.newly_paired, o.paired), (None, None));
    assert_eq!(o.led, LedMode::Unpaired);
    assert_eq!(on(&mut m, 0x5a, 7_000_000).state, MotorState::Off);
}

#[test]
fn re_pairing_the_same_remote_stores_nothing() {
    let mut m = MainLoop::new(false);
    m.set_paired(Some(0x5a));
    let o = hold(&mut m, 1_000_000, 0x5a, board::NEC_CMD_OFF, 1_200_000);
    assert_eq!(
        (o.newly_paired, o.paired, o.pairing_window),
        (None, Some(0x5a), false)
    );
}

#[test]
fn usb_holds_the_motor_off() {
    let mut m = MainLoop::new(false);
    m.pass(0, [], [], || counts(3_900));
    assert_eq!(
        on(&mut m, board::NEC_ADDRESS, 100_000).state,
        MotorState::Ramping
    );
    m.set_usb_connected(true);
    let o = m.pass(300_000, [], [], || counts(3_900));
    assert_eq!(
        (o.state, o.duty, o.usb_connected),
        (MotorState::Off, Duty::ZERO, true)
    );
    let o = on(&mut m, board::NEC_ADDRESS, 400_000);
    assert_eq!((o.command, o.state), (Some(Command::On), MotorState::Off));
    m.set_usb_connected(false);
    assert_eq!(
        on(&mut m, board::NEC_ADDRESS, 600_000).state,
        MotorState::Ramping
    );
}

#[test]
fn flash_may_be_erased_only_off_quiet_and_after_the_window() {
    let mut m = MainLoop::new(false);
    let o = m.pass(0, [], [], || counts(3_900));
    assert!(!o.may_erase_flash, "pairing window");
    let o = m.pass(board::PAIRING.window_us, [], [], || counts(3_900));
    assert!(o.may_erase_flash);
    let t = board::PAIRING.window_us + 100_000;
    let o = on(&mut m, board::NEC_ADDRESS, t);
    assert!(!o.may_erase_flash, "running");
    let o = m.pass(
        t + 200_000,
        frame(board::NEC_ADDRESS, board::NEC_CMD_OFF, t + 100_000),
        [],
        || counts(3_900),
    );
    assert_eq!(o.state, MotorState::Off);
    assert!(!o.may_erase_flash, "an IR frame just now");
    let o = m.pass(t + 200_000 + ERASE_QUIET_US - 1, [], [], || counts(3_900));
    assert!(!o.may_erase_flash);
    let o = m.pass(t + 200_000 + ERASE_QUIET_US, [], [], || counts(3_900));
    assert!(o.may_erase_flash);
}
