//! The shared crate's main loop (the firmware's decisions: the NEC command
//! protocol, the rate controller, the supervisor, the battery monitor)
//! closed around the simulated motor of `swimbot-motor`: the same
//! `Rotor` the emulator's board runs as WebAssembly, here at the calibrated
//! tail-1 motor of `tests/emulator/lib/motor.json` (robot file's fit), not
//! the controller's own assumed line, so the controller has to learn it.
//!
//! Each 1 ms tick: the pass's duty times the supply's voltage is the mean
//! motor voltage (the PWM period is 40 us, far shorter than the winding's
//! L/R and the rotor's time constant), the rotor steps, its Gray-coded
//! edges go to the next pass with the timer's microseconds while the pass
//! powers the latches, and the ADC reads the supply through the board's
//! divider.

use swimbot_motor::{Crossing, Motor, MotorParams, Rotor, TailLoad};
use swimbot_shared::nec::{for_each_edge, frame_pulses_us};
use swimbot_shared::rate::SensorFault;
use swimbot_shared::{
    board, BatteryLevel, Command, HallEdge, Level, MainLoop, MainLoopConfig, MotorState,
};

const TICK_US: u64 = 1_000;

/// tail 1 on the robot file's calibrated motor (tests/emulator/lib/motor.json).
fn tail_one() -> Rotor {
    let params = MotorParams {
        resistance_ohm: 7.0,
        inductance_h: 25e-6,
        torque_constant_n_m_per_a: 2.44e-3,
        rotor_inertia_kg_m2: 1e-9,
        viscous_friction_n_m_s: 1.18e-4,
        coulomb_friction_n_m: 1.2e-5,
    };
    let load = TailLoad {
        tau0_n_m: 0.0,
        damping_n_m_s: 1.274e-5,
    };
    Rotor::new(
        Motor::new(params, 8.14e-9),
        load,
        board::HALL.edges_per_turn(),
    )
}

/// The supply's voltage at a time (a stiff source: the cell's sag is
/// modelled as a voltage that falls with time).
type Supply = fn(u64) -> f64;

struct Bench {
    main_loop: MainLoop,
    rotor: Rotor,
    supply: Supply,
    t_us: u64,
    ir: Vec<(Level, u64)>,
    hall: Vec<HallEdge>,
    powered: bool,
    volts: f64,
    faults: Vec<(u64, SensorFault)>,
    commands: Vec<(u64, Command)>,
    max_motor_v: f64,
}

impl Bench {
    fn new(cfg: MainLoopConfig, supply: Supply) -> Self {
        Self {
            main_loop: MainLoop::with_config(cfg, false),
            rotor: tail_one(),
            supply,
            t_us: 0,
            ir: Vec::new(),
            hall: Vec::new(),
            powered: false,
            volts: 0.0,
            faults: Vec::new(),
            commands: Vec::new(),
            max_motor_v: 0.0,
        }
    }

    /// Queue a frame from `address` starting now; returns its end.
    fn press(&mut self, address: u8, command: u8) -> u64 {
        let start = self.t_us + 1_000;
        let end = for_each_edge(start as u32, &frame_pulses_us(address, command), |l, t| {
            self.ir.push((l, u64::from(t)))
        });
        u64::from(end)
    }

    fn tick(&mut self) {
        let now = self.t_us;
        let due = self.ir.iter().take_while(|(_, t)| *t <= now).count();
        let edges: Vec<_> = self.ir.drain(..due).map(|(l, t)| (l, t as u32)).collect();
        let hall = std::mem::take(&mut self.hall);
        let cell_v = (self.supply)(now);
        let counts = board::BATTERY.mv_to_counts((cell_v * 1e3) as u32);
        let out = self.main_loop.pass(now, edges, hall, || counts);
        if let Some(c) = out.command {
            self.commands.push((now, c));
        }
        if let Some(f) = out.fault {
            self.faults.push((now, f));
        }
        self.powered = out.hall_power;
        self.volts = out.duty.as_f64() * cell_v;
        self.max_motor_v = self.max_motor_v.max(self.volts);
        let mut crossings = [Crossing::default(); 64];
        let n = self
            .rotor
            .step(self.volts, TICK_US as f64 * 1e-6, &mut crossings);
        if self.powered {
            for c in &crossings[..n] {
                self.hall.push(HallEdge {
                    t_us: (now as f64 + c.after_s * 1e6) as u32,
                    a: c.a,
                    b: c.b,
                });
            }
        }
        self.t_us += TICK_US;
    }

    fn run_for(&mut self, us: u64) {
        let until = self.t_us + us;
        while self.t_us < until {
            self.tick();
        }
    }

    /// The rotor's mean rate over the next `us` (turns / time).
    fn mean_rate_hz(&mut self, us: u64) -> f64 {
        let turns = self.rotor.turns();
        self.run_for(us);
        (self.rotor.turns() - turns) / (us as f64 * 1e-6)
    }

    fn on(&mut self) {
        self.run_for(200_000);
        let end = self.press(board::KEYS.address, board::KEYS.on);
        self.run_for(end - self.t_us + 1_000);
        assert_eq!(self.commands.last().map(|c| c.1), Some(Command::On));
    }
}

fn full_cell(_: u64) -> f64 {
    4.0
}

fn with_set_point(mhz: u32) -> MainLoopConfig {
    MainLoopConfig {
        set_point_mhz: Some(mhz),
        ..MainLoopConfig::BOARD
    }
}

#[test]
fn set_points_are_reached_on_the_simulated_motor() {
    for mhz in [600u32, 1_000, 1_400] {
        let mut bench = Bench::new(with_set_point(mhz), full_cell);
        bench.on();
        bench.run_for(15_000_000);
        let rate = bench.mean_rate_hz(5_000_000);
        let set = f64::from(mhz) / 1e3;
        assert!(
            (rate / set - 1.0).abs() < 0.05,
            "set {set} Hz: the rotor turned at {rate:.3} Hz"
        );
        assert_eq!(bench.main_loop.state(), MotorState::Running);
        assert!(bench.faults.is_empty(), "{:?}", bench.faults);
        assert!(
            bench.max_motor_v <= f64::from(board::MOTOR_RATED_MV) / 1e3 + 1e-9,
            "mean motor voltage {} V above the rating",
            bench.max_motor_v
        );
    }
}

#[test]
fn off_stops_the_motor_and_another_address_does_nothing() {
    let mut bench = Bench::new(MainLoopConfig::BOARD, full_cell);
    bench.run_for(200_000);
    // A frame from another remote: no command, the rotor stays still.
    let end = bench.press(board::KEYS.address ^ 0x5a, board::KEYS.on);
    bench.run_for(end - bench.t_us + 2_000_000);
    assert!(bench.commands.is_empty());
    assert!(bench.rotor.turns().abs() < 1e-9, "{}", bench.rotor.turns());
    bench.on();
    bench.run_for(5_000_000);
    assert!(bench.rotor.rate_hz() > 0.5, "{}", bench.rotor.rate_hz());
    let end = bench.press(board::KEYS.address, board::KEYS.off);
    bench.run_for(end - bench.t_us + 1_000);
    assert_eq!(bench.main_loop.state(), MotorState::Off);
    assert!(bench.volts == 0.0, "off: no drive the pass after Off");
    bench.run_for(2_000_000);
    assert!(
        bench.rotor.rate_hz().abs() < 0.01,
        "{}",
        bench.rotor.rate_hz()
    );
}

#[test]
fn a_jammed_tail_is_stopped_within_two_seconds() {
    let mut bench = Bench::new(MainLoopConfig::BOARD, full_cell);
    bench.on();
    bench.run_for(5_000_000);
    assert!(bench.faults.is_empty());
    // Ten times the stall torque at 5 V: the coupler is seized.
    bench.rotor.set_brake_n_m(10.0 * 5.0 / 7.0 * 2.44e-3);
    let jammed_at = bench.t_us;
    bench.run_for(3_000_000);
    let (t, fault) = *bench.faults.first().expect("the jam is noticed");
    assert!(
        matches!(fault, SensorFault::Jammed | SensorFault::Stalled),
        "{fault:?}"
    );
    // The supervisor's window is 1.75 s from the drive passing 1.5 V; the
    // controller's own stall timer may be quicker.
    assert!(
        t - jammed_at <= 2_100_000,
        "stopped {} us after",
        t - jammed_at
    );
    assert_eq!(bench.main_loop.state(), MotorState::Off);
    assert_eq!(bench.volts, 0.0);
}

/// A cell sagging from 4.0 V to 3.0 V over 40 s.
fn sagging_cell(t_us: u64) -> f64 {
    4.0 - (t_us as f64 / 40e6).min(1.0)
}

#[test]
fn a_battery_sag_keeps_the_rate_then_cuts_off() {
    let mut bench = Bench::new(MainLoopConfig::BOARD, sagging_cell);
    bench.on();
    bench.run_for(10_000_000);
    // 10-15 s: the cell falls 3.75 -> 3.63 V; the controller raises the
    // duty and the rate holds.
    let rate = bench.mean_rate_hz(5_000_000);
    assert!((rate - 1.0).abs() < 0.05, "{rate:.3} Hz at 3.7 V");
    // The averaged reading passes 3.3 V at 28 s, then the 1 s debounce.
    let mut stopped = None;
    while bench.t_us < 35_000_000 {
        bench.tick();
        if stopped.is_none() && bench.main_loop.state() == MotorState::Off {
            stopped = Some(bench.t_us);
        }
    }
    let stopped = stopped.expect("cut off");
    assert!(
        (28_500_000..=30_500_000).contains(&stopped),
        "cut off at {stopped} us"
    );
    assert_eq!(
        bench.main_loop.monitor().status().level,
        BatteryLevel::Cutoff
    );
    // On is refused while the cut-off is latched.
    bench.on_refused();
}

impl Bench {
    fn on_refused(&mut self) {
        let end = self.press(board::KEYS.address, board::KEYS.on);
        self.run_for(end - self.t_us + 1_000_000);
        assert_eq!(self.main_loop.state(), MotorState::Off);
        assert_eq!(self.volts, 0.0);
    }
}
