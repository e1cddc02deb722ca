//! The pass's pairing window, the unpaired robot, the USB hold-off and the
//! flash-erase condition.
use super::*;
use crate::nec::{for_each_edge, frame_pulses_us, Address, REPEAT_PULSES_US};

/// A standard remote at `address` with the board's keys.
fn remote(address: u8) -> PairedRemote {
    PairedRemote {
        address: Address::standard(address),
        ..PairedRemote::of_keys(board::KEYS)
    }
}

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
    assert_eq!(o.newly_paired, Some(remote(0x5a)));
    // Open for teaching an On key until 5 s after the pairing.
    assert_eq!((o.paired, o.pairing_window), (Some(remote(0x5a)), true));
    assert_eq!(on(&mut m, 0x5a, 3_500_000).state, MotorState::Ramping);
    let o = m.pass(3_700_000 + board::PAIRING.learn_us, [], [], || {
        counts(3_900)
    });
    assert!(!o.pairing_window, "closed after the teaching time");
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
    m.set_paired(Some(remote(0x5a)));
    let o = hold(&mut m, 1_000_000, 0x5a, board::NEC_CMD_OFF, 1_200_000);
    assert_eq!((o.newly_paired, o.paired), (None, Some(remote(0x5a))));
}

/// Two robots paired with two remotes of one make (one standard address,
/// 0x00), each taught its own On key: each remote's On starts its own robot
/// only, and the make's usual On key starts neither.
#[test]
fn two_remotes_of_one_make_are_told_apart() {
    const MINE: u8 = 0x43;
    const NEIGHBOURS: u8 = 0x40;
    let pair = |on_key: u8| {
        let mut m = MainLoop::new(false);
        m.set_paired(None);
        m.pass(0, [], [], || counts(3_900));
        let o = hold(&mut m, 500_000, 0x00, board::NEC_CMD_OFF, 1_100_000);
        assert_eq!(o.newly_paired, Some(remote(0x00)));
        let o = hold(&mut m, 2_500_000, 0x00, on_key, 1_100_000);
        let taught = PairedRemote {
            on: on_key,
            ..remote(0x00)
        };
        assert_eq!((o.newly_paired, o.paired), (Some(taught), Some(taught)));
        assert_eq!(o.state, MotorState::Off, "teaching starts nothing");
        m
    };
    let (mut a, mut b) = (pair(MINE), pair(NEIGHBOURS));
    let key = |m: &mut MainLoop, code: u8, t0: u64| {
        m.pass(t0 + 80_000, frame(0x00, code, t0), [], || counts(3_900))
    };
    // After the windows: the usual On key is nobody's now.
    let t = 9_000_000;
    assert_eq!(key(&mut a, board::NEC_CMD_ON, t).state, MotorState::Off);
    assert_eq!(key(&mut b, board::NEC_CMD_ON, t).state, MotorState::Off);
    // The neighbour's On: robot b starts, robot a does not.
    assert_eq!(key(&mut a, NEIGHBOURS, t + 200_000).state, MotorState::Off);
    assert_eq!(
        key(&mut b, NEIGHBOURS, t + 200_000).state,
        MotorState::Ramping
    );
    // Mine: robot a starts; Off (the make's, shared) stops either.
    assert_eq!(key(&mut a, MINE, t + 400_000).state, MotorState::Ramping);
    assert_eq!(
        key(&mut a, board::NEC_CMD_OFF, t + 600_000).state,
        MotorState::Off
    );
    assert_eq!(
        key(&mut b, board::NEC_CMD_OFF, t + 600_000).state,
        MotorState::Off
    );
}

/// An extended-NEC remote is paired by its whole 16-bit address: a standard
/// remote whose address byte is the extended one's first byte is another.
#[test]
fn an_extended_address_is_kept_whole() {
    let mut m = MainLoop::new(false);
    m.set_paired(Some(PairedRemote {
        address: Address(0x1280),
        ..PairedRemote::of_keys(board::KEYS)
    }));
    m.pass(0, [], [], || counts(3_900));
    let frame16 = |address: u16, t0: u64| {
        let [lo, hi] = address.to_le_bytes();
        let c = board::NEC_CMD_ON;
        let mut v = Edges::new();
        let pulses = crate::nec::raw_frame_pulses_us(u32::from_le_bytes([lo, hi, c, !c]));
        for_each_edge(t0 as u32, &pulses, |l, t| {
            let _ = v.push((l, t));
        });
        v
    };
    let t = board::PAIRING.window_us + 1_000_000;
    let o = on(&mut m, 0x80, t);
    assert_eq!((o.state, o.foreign_frames), (MotorState::Off, 1));
    let o = m.pass(t + 300_000, frame16(0x1280, t + 200_000), [], || {
        counts(3_900)
    });
    assert_eq!(o.state, MotorState::Ramping);
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
