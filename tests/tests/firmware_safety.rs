//! Safety properties of the firmware's main-loop pass
//! (`swimbot_shared::MainLoop`, the very code `firmware/src/run.rs` calls),
//! driven by arbitrary sequences of ADC readings (including 0, 4095 and
//! sudden jumps), IR edges and Hall edges (any levels, any gaps: a turning,
//! stalled, reversed, bouncing or half-wired sensor):
//!
//! 1. without a valid On frame, the motor never starts (duty stays 0),
//!    whatever noise, foreign frames, corrupted On frames or repeat codes
//!    arrive;
//! 2. once every reading of a full averaging window is a plausible cell
//!    voltage below the cut-off,
//!    the motor is off within the cut-off's debounce time and stays off
//!    while the readings stay low, even if On frames keep arriving;
//! 3. the duty is zero whenever the monitor's status forbids running;
//! 4. after a reset that remembered a cut-off (watchdog scratch), On frames
//!    never start the motor until a reading of a recharged cell (the
//!    monitor's `recharged_mv`, at rest) has come in;
//! 5. the duty never exceeds full scale, is never non-zero with the Hall
//!    latches unpowered, and after a rate-sensor fault stays zero until
//!    the next decoded On (no Hall edge restarts the motor);
//! 6. while USB is connected the duty is zero from the first pass that
//!    knows it, whatever arrives (On frames included), and a flash erase
//!    (which stalls the chip) is never allowed while the motor can run;
//! 7. an unpaired robot (nothing in its pairing sector) never runs until
//!    a pass reports a remote newly paired, whatever frames arrive, holds
//!    of any key from any address included.

use proptest::prelude::*;
use swimbot_shared::battery::AVERAGE_SAMPLES;
use swimbot_shared::board::{BATTERY, BATTERY_SAMPLE_PERIOD_US as SAMPLE_PERIOD_US, KEYS};
use swimbot_shared::nec::{for_each_edge, frame_pulses_us, raw_frame_pulses_us, REPEAT_PULSES_US};
use swimbot_shared::{Command, Duty, HallEdge, Level, MainLoop, MotorState};

/// What happens next to the firmware.
#[derive(Debug, Clone)]
enum Input {
    /// An ADC reading (0..=4095 and beyond: the ADC saturates).
    Adc(u16),
    /// A raw receiver edge after `gap_us`.
    Edge(bool, u32),
    /// A Hall edge (levels of A and B) after `gap_us`.
    Hall(bool, bool, u32),
    /// A whole NEC frame that is not our On: another key, another address,
    /// a corrupted checksum, or a repeat code.
    NotOn(NotOn),
    /// Our On frame (only where the property allows it).
    On,
    /// Time passes without input.
    Wait(u32),
    /// USB connected or disconnected (VBUS).
    Usb(bool),
    /// A key held: its frame, then this many repeat frames 108 ms apart.
    Hold(u8, u8, u8),
}

#[derive(Debug, Clone)]
enum NotOn {
    Key(u8),
    Address(u8),
    BadInverse(u8),
    Repeat,
}

fn not_on() -> impl Strategy<Value = NotOn> {
    prop_oneof![
        any::<u8>()
            .prop_filter("not the On key", |c| *c != KEYS.on)
            .prop_map(NotOn::Key),
        any::<u8>()
            .prop_filter("another remote", |a| *a != KEYS.address)
            .prop_map(NotOn::Address),
        (1u8..=255).prop_map(NotOn::BadInverse),
        Just(NotOn::Repeat),
    ]
}

/// ADC codes: the rails, values near the cut-off and anything else.
fn adc() -> impl Strategy<Value = u16> {
    let cut = BATTERY.mv_to_counts(u32::from(BATTERY.cutoff_mv));
    prop_oneof![
        Just(0u16),
        Just(4095u16),
        Just(u16::MAX),
        (cut - 40)..(cut + 40),
        0u16..=4095,
    ]
}

fn input(with_on: bool) -> BoxedStrategy<Input> {
    let base = prop_oneof![
        4 => adc().prop_map(Input::Adc),
        4 => (any::<bool>(), 0u32..20_000).prop_map(|(l, g)| Input::Edge(l, g)),
        4 => (any::<bool>(), any::<bool>(), 0u32..300_000).prop_map(|(a, b, g)| Input::Hall(a, b, g)),
        2 => not_on().prop_map(Input::NotOn),
        1 => (0u32..3_000_000).prop_map(Input::Wait),
    ];
    if with_on {
        prop_oneof![8 => base, 1 => Just(Input::On)].boxed()
    } else {
        base.boxed()
    }
}

/// The firmware's main loop, with simulated time: passes at every edge and
/// at every battery reading (the passes in between change nothing here).
struct Firmware {
    t_us: u64,
    /// When the main loop will next read the ADC (from its `sample` output).
    next_sample_us: u64,
    main_loop: MainLoop,
    /// Latest ADC code; read whenever the pass asks.
    adc: u16,
    /// Cell mV of every sample taken, with its time.
    readings: Vec<(u64, u32)>,
}

fn input_usb() -> BoxedStrategy<Input> {
    prop_oneof![
        6 => input(true),
        1 => any::<bool>().prop_map(Input::Usb),
        1 => (any::<u8>(), prop_oneof![Just(KEYS.off), Just(KEYS.on), any::<u8>()], 0u8..14)
            .prop_map(|(a, c, n)| Input::Hold(a, c, n)),
    ]
    .boxed()
}

struct Step {
    t_us: u64,
    state: MotorState,
    duty: u32,
    allows_motor: bool,
    command: Option<Command>,
    faulted: bool,
    hall_power: bool,
    usb: bool,
    may_erase: bool,
    newly_paired: bool,
}

impl Firmware {
    fn new(adc: u16) -> Self {
        Self::after_reset(adc, false)
    }

    fn after_reset(adc: u16, cutoff_remembered: bool) -> Self {
        Firmware {
            t_us: 0,
            next_sample_us: 0,
            main_loop: MainLoop::new(cutoff_remembered),
            adc,
            readings: Vec::new(),
        }
    }

    /// One main-loop pass at `t_us` with the receiver edges since the last.
    fn pass(&mut self, edges: &[(Level, u32)], out: &mut Vec<Step>) {
        self.pass_with(edges, None, out);
    }

    fn pass_with(&mut self, edges: &[(Level, u32)], hall: Option<HallEdge>, out: &mut Vec<Step>) {
        let adc = self.adc;
        let o = self
            .main_loop
            .pass(self.t_us, edges.iter().copied(), hall, || adc);
        if let Some(counts) = o.sample {
            self.next_sample_us = self.t_us + SAMPLE_PERIOD_US;
            self.readings
                .push((self.t_us, BATTERY.counts_to_mv(counts)));
        }
        out.push(Step {
            t_us: self.t_us,
            state: o.state,
            duty: o.duty.raw(),
            allows_motor: o.battery.allows_motor(),
            command: o.command,
            faulted: o.fault.is_some(),
            hall_power: o.hall_power,
            usb: o.usb_connected,
            may_erase: o.may_erase_flash,
            newly_paired: o.newly_paired.is_some(),
        });
    }

    /// Advance to `until_us` in main-loop passes of one sample period.
    fn idle_until(&mut self, until_us: u64, out: &mut Vec<Step>) {
        while self.next_sample_us <= until_us {
            self.t_us = self.t_us.max(self.next_sample_us);
            self.pass(&[], out);
        }
        self.t_us = self.t_us.max(until_us);
    }

    fn edges(&mut self, pulses: &[u32], out: &mut Vec<Step>) {
        let mut edges = Vec::new();
        for_each_edge(0, pulses, |l, t| edges.push((l, t)));
        let start = self.t_us + 1_000;
        for (l, t) in edges {
            self.edge(l, start + u64::from(t), out);
        }
    }

    fn edge(&mut self, level: Level, at_us: u64, out: &mut Vec<Step>) {
        self.idle_until(at_us, out);
        self.pass(&[(level, at_us as u32)], out);
    }

    fn apply(&mut self, i: &Input, out: &mut Vec<Step>) {
        match *i {
            Input::Adc(c) => self.adc = c,
            Input::Wait(us) => {
                let until = self.t_us + u64::from(us);
                self.idle_until(until, out);
            }
            Input::Edge(high, gap) => {
                let level = if high { Level::High } else { Level::Low };
                let at = self.t_us + u64::from(gap);
                self.edge(level, at, out);
            }
            Input::Hall(a, b, gap) => {
                let at = self.t_us + u64::from(gap);
                self.idle_until(at, out);
                let t_us = at as u32;
                self.pass_with(&[], Some(HallEdge { t_us, a, b }), out);
            }
            Input::On => self.edges(&frame_pulses_us(KEYS.address, KEYS.on), out),
            Input::Usb(on) => self.main_loop.set_usb_connected(on),
            Input::Hold(address, command, repeats) => {
                self.edges(&frame_pulses_us(address, command), out);
                // NEC repeats come every 108 ms: a 12 ms repeat frame
                // after about 95 ms of silence.
                for _ in 0..repeats {
                    let until = self.t_us + 95_000;
                    self.idle_until(until, out);
                    self.edges(&REPEAT_PULSES_US, out);
                }
            }
            Input::NotOn(ref n) => match *n {
                NotOn::Key(c) => self.edges(&frame_pulses_us(KEYS.address, c), out),
                NotOn::Address(a) => self.edges(&frame_pulses_us(a, KEYS.on), out),
                NotOn::BadInverse(x) => {
                    // NEC payload: address, !address, command, !command
                    // (LSB first); a flipped inverse must not pass.
                    let a = u32::from(KEYS.address);
                    let c = u32::from(KEYS.on);
                    let payload =
                        a | ((!a & 0xff) << 8) | (c << 16) | (((!c ^ u32::from(x)) & 0xff) << 24);
                    self.edges(&raw_frame_pulses_us(payload), out)
                }
                NotOn::Repeat => self.edges(&REPEAT_PULSES_US, out),
            },
        }
    }
}

fn run(start_adc: u16, inputs: &[Input]) -> (Firmware, Vec<Step>) {
    run_from(Firmware::new(start_adc), inputs)
}

fn run_from(mut fw: Firmware, inputs: &[Input]) -> (Firmware, Vec<Step>) {
    let mut out = Vec::new();
    for i in inputs {
        fw.apply(i, &mut out);
    }
    fw.idle_until(fw.t_us + 2 * SAMPLE_PERIOD_US, &mut out);
    (fw, out)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1024, ..ProptestConfig::default() })]

    /// Property 1: no valid On frame, no motor.
    #[test]
    fn no_on_frame_never_starts_the_motor(
        start in adc(),
        inputs in prop::collection::vec(input(false), 0..120),
    ) {
        let (_, steps) = run(start, &inputs);
        for s in &steps {
            prop_assert_ne!(s.command, Some(Command::On), "decoded On at {} us", s.t_us);
            prop_assert_eq!(s.state, MotorState::Off, "motor on at {} us", s.t_us);
            prop_assert_eq!(s.duty, 0);
        }
    }

    /// Properties 2 and 3: never running on a low or broken cell.
    #[test]
    fn never_runs_below_the_cutoff_or_on_a_fault(
        start in adc(),
        inputs in prop::collection::vec(input(true), 0..160),
    ) {
        let (fw, steps) = run(start, &inputs);
        let cutoff = u32::from(BATTERY.cutoff_mv);
        // The time from which the last AVERAGE_SAMPLES readings, and every
        // later one, were plausible and below the cut-off: their average is
        // then a plausible low voltage, so the debounce runs from there.
        // (Implausible readings, 0 or 4095, are faults: property 3.)
        let mut low_since: Vec<Option<u64>> = Vec::with_capacity(fw.readings.len());
        let mut run_len = 0usize;
        for &(t, mv) in &fw.readings {
            let low = mv >= u32::from(BATTERY.plausible_min_mv) && mv < cutoff;
            run_len = if low { run_len + 1 } else { 0 };
            let prev = low_since.last().copied().flatten();
            low_since.push(match run_len {
                0 => None,
                n if n == AVERAGE_SAMPLES => Some(t),
                n if n > AVERAGE_SAMPLES => prev,
                _ => None,
            });
        }
        for s in &steps {
            if !s.allows_motor {
                prop_assert_eq!(s.duty, 0, "duty with the battery forbidding it at {} us", s.t_us);
            }
            // The reading in force at this pass.
            let k = fw.readings.partition_point(|r| r.0 <= s.t_us);
            if k == 0 {
                prop_assert_eq!(s.state, MotorState::Off);
                continue;
            }
            if let Some(since) = low_since[k - 1] {
                if s.t_us >= since + BATTERY.cutoff_debounce_us {
                    prop_assert_eq!(
                        s.state,
                        MotorState::Off,
                        "running at {} us, readings below the cut-off since {} us",
                        s.t_us,
                        since
                    );
                }
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1024, ..ProptestConfig::default() })]

    /// Property 5: the duty's range, the latches' power, and a sensor
    /// fault holding the motor off until a new On.
    #[test]
    fn a_sensor_fault_holds_until_a_new_on(
        inputs in prop::collection::vec(input(true), 0..200),
    ) {
        let healthy = BATTERY.mv_to_counts(3_900);
        let (_, steps) = run(healthy, &inputs);
        let mut held = false;
        for s in &steps {
            prop_assert!(s.duty <= Duty::FULL.raw());
            if s.duty > 0 {
                prop_assert!(s.hall_power, "driven with the latches off at {} us", s.t_us);
            }
            if s.command == Some(Command::On) {
                held = false;
            }
            held |= s.faulted;
            if held {
                prop_assert_eq!(s.duty, 0, "driven after a sensor fault at {} us", s.t_us);
            }
        }
    }

    /// Property 4: a remembered cut-off holds through any inputs, On frames
    /// included, until a reading at or above the recharged level.
    #[test]
    fn a_remembered_cutoff_holds_until_recharged(
        start in adc(),
        inputs in prop::collection::vec(input(true), 0..160),
    ) {
        let (fw, steps) = run_from(Firmware::after_reset(start, true), &inputs);
        let recharged = u32::from(BATTERY.recharged_mv);
        let first_recharged = fw
            .readings
            .iter()
            .find(|r| r.1 >= recharged && r.1 <= u32::from(BATTERY.plausible_max_mv))
            .map_or(u64::MAX, |r| r.0);
        for s in steps.iter().filter(|s| s.t_us < first_recharged) {
            prop_assert_eq!(s.state, MotorState::Off, "running at {} us on a remembered cut-off", s.t_us);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 1024, ..ProptestConfig::default() })]

    /// Property 6: USB holds the motor off; no erase while it can run.
    #[test]
    fn usb_holds_the_motor_off_and_erases_wait_for_it(
        inputs in prop::collection::vec(input_usb(), 0..160),
    ) {
        let (_, steps) = run(BATTERY.mv_to_counts(3_900), &inputs);
        for s in &steps {
            if s.usb {
                prop_assert_eq!((s.duty, s.state), (0, MotorState::Off), "driven with USB at {} us", s.t_us);
            }
            if s.may_erase {
                prop_assert_eq!((s.duty, s.state), (0, MotorState::Off), "erase allowed while driven at {} us", s.t_us);
            }
        }
    }

    /// Property 7: unpaired, nothing runs before a pairing.
    #[test]
    fn an_unpaired_robot_runs_only_after_a_pairing(
        inputs in prop::collection::vec(input_usb(), 0..160),
    ) {
        let mut fw = Firmware::new(BATTERY.mv_to_counts(3_900));
        fw.main_loop.set_paired(None);
        let (_, steps) = run_from(fw, &inputs);
        for s in steps.iter().take_while(|s| !s.newly_paired) {
            prop_assert_eq!((s.duty, s.state), (0, MotorState::Off), "unpaired and driven at {} us", s.t_us);
        }
    }
}

/// Properties 6 and 7 can fail: with USB off a paired On runs, and a
/// 1.3 s hold of Off in the window pairs (then On from that remote runs).
#[test]
fn a_hold_pairs_and_usb_released_lets_on_run() {
    let healthy = BATTERY.mv_to_counts(3_900);
    let mut fw = Firmware::new(healthy);
    fw.main_loop.set_paired(None);
    let inputs = [
        Input::Wait(300_000),
        Input::Hold(0x5a, KEYS.off, 12),
        Input::Usb(true),
        Input::Wait(300_000),
        Input::Usb(false),
        Input::NotOn(NotOn::Address(0x5a)),
        Input::Wait(100_000),
    ];
    let (_, steps) = run_from(fw, &inputs);
    let paired = steps.iter().position(|s| s.newly_paired).expect("paired");
    assert!(steps[paired..].iter().any(|s| s.duty > 0));
    let usb_on = Firmware::new(healthy);
    let (_, steps) = run_from(
        usb_on,
        &[
            Input::Usb(true),
            Input::Wait(300_000),
            Input::On,
            Input::Wait(100_000),
        ],
    );
    assert!(steps.iter().all(|s| s.duty == 0));
    let (_, steps) = run(
        healthy,
        &[Input::Wait(300_000), Input::On, Input::Wait(100_000)],
    );
    assert!(
        steps.iter().any(|s| s.duty > 0),
        "the same inputs without USB run"
    );
}

#[test]
fn a_remembered_cutoff_is_released_by_a_recharged_cell() {
    let inputs = [Input::Wait(300_000), Input::On, Input::Wait(100_000)];
    let (_, steps) = run_from(
        Firmware::after_reset(BATTERY.mv_to_counts(4_100), true),
        &inputs,
    );
    assert!(steps.iter().any(|s| s.state != MotorState::Off));
    let (_, steps) = run_from(
        Firmware::after_reset(BATTERY.mv_to_counts(3_600), true),
        &inputs,
    );
    assert!(steps.iter().all(|s| s.state == MotorState::Off));
}

/// The property test can fail: a healthy cell with an On frame runs.
#[test]
fn a_valid_on_frame_on_a_healthy_cell_does_start() {
    let healthy = BATTERY.mv_to_counts(4_000);
    let inputs = [Input::Wait(300_000), Input::On, Input::Wait(100_000)];
    let (_, steps) = run(healthy, &inputs);
    assert!(steps
        .iter()
        .any(|s| s.state != MotorState::Off && s.duty > 0));
}

/// Property 5 can fail: a quarter turn backwards while driven is a fault,
/// and the motor is off from that pass on.
#[test]
fn a_reversed_sensor_stops_the_motor() {
    let healthy = BATTERY.mv_to_counts(3_900);
    let mut inputs = vec![Input::Wait(300_000), Input::On, Input::Wait(300_000)];
    let backwards = [(false, false), (true, false), (true, true), (false, true)];
    for k in 0..6 {
        let (a, b) = backwards[k % 4];
        inputs.push(Input::Hall(a, b, 50_000));
    }
    let (_, steps) = run(healthy, &inputs);
    let fault = steps
        .iter()
        .position(|s| s.faulted)
        .expect("a reversal fault");
    assert!(steps[..fault].iter().any(|s| s.duty > 0));
    assert!(steps[fault..].iter().all(|s| s.duty == 0 && !s.hall_power));
}
