//! The main loop: each pass hands the queued IR and Hall edges, the clock
//! and (when a reading is due) the ADC to the shared `MainLoop::pass`, then
//! applies what it decided: the PWM duty, the Hall latches' power, the LED, the cut-off latch's copy in the
//! watchdog scratch registers, the watchdog feed. A defmt line for every
//! state change (commands, controller events, sensor faults, battery
//! level, LED mode, and the rate once a second while running),
//! so a probe log tells the whole story of a run.
//!
//! Around the pass: the paired remote read from its flash sector at boot
//! and a new pairing stored; the run log's recorder fed every pass and its
//! records appended to the flash slot (a page programmed every 16 records,
//! 1.6 s, and when the motor stops); one flash erase per pass when the
//! pass allows it (motor off), the pass told of a pending erase so that
//! DORMANT waits for the whole sequence; VBUS read before the pass (USB
//! connected = motor held off) and the readout port served after it.
//!
//! Between passes the core sleeps until an IR edge or the 1 kHz wake-up
//! alarm (`sleep`): a pass every 1 ms plus the pass's own few microseconds.
//! Timing comes from the 1 MHz timer, so a late pass only delays, never
//! distorts. The watchdog is fed only here, after a complete pass, so a
//! stall anywhere stops the feeding.

use crate::battery_adc::BatterySense;
use crate::board;
use crate::flash::LogRegion;
use crate::ir;
use crate::motor::Motor;
use crate::pairing::{self, PairingStore};
use crate::power::{Power, Speed};
use crate::sleep;
use crate::usb::Usb;
use embedded_hal::digital::OutputPin;
use rp2040_hal::gpio::{
    bank0::Gpio12, bank0::Gpio22, bank0::Gpio25, FunctionSioOutput, Pin, PullDown,
};
use rp2040_hal::watchdog::ScratchRegister;
use rp2040_hal::{Timer, Watchdog};
use swimbot_shared::rate::SensorFault;
use swimbot_shared::run_log::status::{bootsel_allowed, PairingState, Status};
use swimbot_shared::run_log::{Events, LogStore, Record, Recorder};
use swimbot_shared::{reset_memory, BatteryLevel, LedMode, MainLoop, PassOutput, PreStart};

const _: () = assert!(board::LED_GPIO == 25, "the typed LED pin is GPIO25");
const _: () = assert!(
    board::HALL_POWER_GPIO == 12,
    "the typed power pin is GPIO12"
);

pub type LedPin = Pin<Gpio25, FunctionSioOutput, PullDown>;
pub type HallPowerPin = Pin<Gpio12, FunctionSioOutput, PullDown>;
pub type PowerHoldPin = Pin<Gpio22, FunctionSioOutput, PullDown>;
const _: () = assert!(
    board::POWER_HOLD_GPIO == 22,
    "the typed power-hold pin is GPIO22"
);

/// How long the chip waits, fed, for its own supply to go after it opened
/// the load switch; still running after that, it has no switch (or USB or
/// a charger powers it) and goes DORMANT instead.
const POWER_OFF_WAIT_MS: u32 = 50;

// The four registers named one by one, not mapped over an array of
// `ScratchRegister`s: through `map`/`zip` the HAL's eight-way match was
// kept in the image (about 0.3 kB more flash).

/// The cut-off latch remembered in SCRATCH0-3 (cleared by power-on).
pub fn remembered_cutoff(watchdog: &Watchdog) -> bool {
    use ScratchRegister::{Scratch0, Scratch1, Scratch2, Scratch3};
    reset_memory::cutoff_latched([
        watchdog.read_scratch(Scratch0),
        watchdog.read_scratch(Scratch1),
        watchdog.read_scratch(Scratch2),
        watchdog.read_scratch(Scratch3),
    ])
}

fn remember_cutoff(watchdog: &mut Watchdog, latched: bool) {
    use ScratchRegister::{Scratch0, Scratch1, Scratch2, Scratch3};
    let [w0, w1, w2, w3] = reset_memory::encode(latched);
    watchdog.write_scratch(Scratch0, w0);
    watchdog.write_scratch(Scratch1, w1);
    watchdog.write_scratch(Scratch2, w2);
    watchdog.write_scratch(Scratch3, w3);
}

pub struct Robot {
    pub motor: Motor,
    pub battery: BatterySense,
    pub led: LedPin,
    pub hall_power: HallPowerPin,
    pub power_hold: PowerHoldPin,
    pub timer: Timer,
    pub power: Power,
    pub usb: Usb,
}

/// The run log and the pairing on their way to flash.
struct Keeping {
    recorder: Recorder,
    store: LogStore,
    pairing: PairingStore,
    /// The record of the pass that started the motor, and whether it closes
    /// the run: appended in the next pass (see `after_pass`).
    held: Option<(Record, bool)>,
}

impl Keeping {
    // `open` and `after_pass` are kept out of the main loop's body: about
    // 1 kB less flash with `serve` (the fw profile inlines everything).
    #[inline(never)]
    fn open(watchdog: &mut Watchdog) -> Self {
        let period_ms = (board::LOG_PERIOD_US / 1_000) as u16;
        let store = LogStore::open(&LogRegion::new(watchdog), board::LOG_LAYOUT, period_ms);
        defmt::info!(
            "run log: slot ready {}, erase pending {}",
            store.ready(),
            store.erase_pending()
        );
        Self {
            recorder: Recorder::new(board::LOG_PERIOD_US),
            store,
            pairing: PairingStore::new(),
            held: None,
        }
    }

    /// A log block or the pairing sector is still to be erased: no DORMANT
    /// until it is (`MainLoop::set_erase_pending`).
    fn erase_pending(&self) -> bool {
        self.pairing.erase_pending() || self.store.erase_pending()
    }

    #[inline(never)]
    fn append(&mut self, watchdog: &mut Watchdog, record: &Record, closing: bool) {
        let dropped = self.store.dropped();
        self.store
            .append(&mut LogRegion::new(watchdog), record, closing);
        if self.store.dropped() != dropped {
            defmt::warn!("run log: record dropped ({} so far)", self.store.dropped());
        }
    }

    /// After a pass: store a new pairing, record, and erase if allowed.
    #[inline(never)]
    fn after_pass(&mut self, now_us: u64, out: &PassOutput, watchdog: &mut Watchdog) {
        if let Some(remote) = out.newly_paired {
            self.pairing.save(remote);
            defmt::info!(
                "paired with the remote at address {=u16:#06x}, On {=u8:#04x}, Off {=u8:#04x}",
                remote.address.0,
                remote.on,
                remote.off
            );
        }
        let new = self.recorder.observe(now_us, out);
        let new = new.map(|r| (r, !self.recorder.recording()));
        // The pass that starts the motor asks for the pass that gives the
        // first PWM pulse; a page program now (the slot's header, at a
        // power-up's first run) would hold that pass back by its stall, 0.4 ms
        // typical and 3 ms at worst with interrupts masked (emulator: On ->
        // first pulse 0.86 / 3.46 ms instead of 0.46 ms). Its record waits
        // one pass.
        if out.next_pass_in_us.is_some() && self.held.is_none() {
            self.held = new;
            return;
        }
        if let Some((record, closing)) = self.held.take() {
            self.append(watchdog, &record, closing);
        }
        if let Some((record, closing)) = new {
            self.append(watchdog, &record, closing);
        }
        if !out.may_erase_flash {
            return;
        }
        if self.pairing.erase_pending() {
            if !self.pairing.erase_step(watchdog) {
                defmt::error!("pairing: not kept in flash (kept until power-off)");
            }
        } else if self.store.erase_pending() {
            self.store.erase_step(&mut LogRegion::new(watchdog));
            defmt::info!("run log: a block erased");
        }
    }
}

impl Robot {
    pub fn run(mut self, watchdog: &mut Watchdog) -> ! {
        let cutoff = remembered_cutoff(watchdog);
        if cutoff {
            defmt::warn!("battery: cut-off remembered from before the reset");
        }
        let mut main_loop = MainLoop::new(cutoff);
        let paired = pairing::stored();
        main_loop.set_paired(paired);
        match paired {
            Some(r) => defmt::info!(
                "remote: address {=u16:#06x}, On {=u8:#04x}, Off {=u8:#04x}",
                r.address.0,
                r.on,
                r.off
            ),
            None => defmt::warn!("remote: none paired (hold Off for 1 s within 5 s of power-up)"),
        }
        let mut keeping = Keeping::open(watchdog);
        let mut level = BatteryLevel::Fault;
        let mut led_mode = LedMode::Off;
        let mut next_rate_log_us = 0;
        let mut foreign = 0;
        let mut faults = Faults::default();
        let mut ir_full_until_us = 0;
        loop {
            let now_us = self.timer.get_counter().ticks();
            // IR edges waiting: decoded at full speed (see `IR_FULL_SPEED_US`).
            if critical_section::with(ir::has_edges) {
                ir_full_until_us = now_us + IR_FULL_SPEED_US;
                self.power.set_speed(Speed::Full);
            }
            let usb = self.usb.connected();
            main_loop.set_usb_connected(usb);
            main_loop.set_erase_pending(keeping.erase_pending());
            main_loop.set_prestart(prestart(&self.motor));
            self.power.usb_awake(usb);
            let (motor, battery) = (&self.motor, &mut self.battery);
            let out = main_loop.pass(now_us, ir::drain(), ir::drain_hall(), || {
                battery.read(motor.timing())
            });
            let ir_active = now_us < ir_full_until_us;
            let speed = speed_after(&out, usb && !self.usb.suspended(), ir_active);
            if speed != self.power.speed() {
                defmt::info!("clocks: {}", speed);
                self.power.set_speed(speed);
            }
            self.motor.set(out.duty);
            let _ = self.hall_power.set_state(out.hall_power.into());
            if let Some(latched) = out.latch_changed {
                remember_cutoff(watchdog, latched);
            }
            if log(&out, &mut level, &mut led_mode) {
                keeping.recorder.note(Events::EDGES_DROPPED);
            }
            if out.may_erase_flash && keeping.erase_pending() {
                // A frame queued during the erase's stall is decoded by the
                // passes right after it: at full speed, not on the crystal
                // (emulator, `12-stalls`: an On's first pulse 0.87 ms after
                // a 150 ms block with the erase pass on the crystal, 0.60 ms
                // with it at 125 MHz; the board adds PLL_SYS's relock).
                self.power.set_speed(Speed::Full);
            }
            keeping.after_pass(now_us, &out, watchdog);
            faults.note(&out);
            if usb {
                let region = LogRegion::new(watchdog);
                let status = status(&out, &faults);
                let robot = crate::usb::Robot {
                    foreign: out.foreign_frames,
                    // The log header's field: the address's first byte.
                    paired: out.paired.map(|r| r.address.low()),
                    status: &status,
                    bootsel_allowed: bootsel_allowed(out.state, out.duty, self.motor.gate_high()),
                };
                self.usb.serve(&keeping.store, &region, &robot);
            }
            if out.foreign_frames != foreign {
                foreign = out.foreign_frames;
                defmt::warn!("ir: another remote's frame ignored ({} so far)", foreign);
            }
            if out.hall_power && now_us >= next_rate_log_us {
                next_rate_log_us = now_us + 1_000_000;
                defmt::info!(
                    "rate: {} mHz, reference {} mHz, duty {}/65536",
                    out.rate_mhz,
                    out.reference_mhz,
                    out.duty.raw()
                );
            }
            let _ = self.led.set_state(out.led_lit.into());
            #[cfg(feature = "fault-test")]
            fault_test::act();
            watchdog.feed();
            if out.may_go_dormant {
                // Motor off (the condition), LED dark, until an IR edge.
                let _ = self.led.set_low();
                if level == BatteryLevel::Cutoff {
                    self.power_off(watchdog);
                }
                defmt::info!("dormant until an IR edge or VBUS");
                self.power.dormant_until_wake();
                let _ = self.power_hold.set_high();
                main_loop.woke();
                defmt::info!("awake");
                watchdog.feed();
                continue;
            }
            sleep::until_next_event(out.next_pass_in_us.unwrap_or(board::WAKE_PERIOD_US));
        }
    }
}

impl Robot {
    /// The cell is below its cut-off and the robot idle: open the load
    /// switch, so that a stored robot stops drawing its cell. Returns (after
    /// `POWER_OFF_WAIT_MS`, fed) only if the chip is still powered.
    #[inline(never)]
    fn power_off(&mut self, watchdog: &mut Watchdog) {
        defmt::warn!("battery: cut-off while idle: opening the load switch");
        let _ = self.power_hold.set_low();
        let until = self.timer.get_counter().ticks() + u64::from(POWER_OFF_WAIT_MS) * 1_000;
        while self.timer.get_counter().ticks() < until {
            watchdog.feed();
        }
        defmt::warn!("still powered: no load switch (or USB); DORMANT instead");
    }
}

/// How long the chip stays on PLL_SYS after an IR edge was queued: a NEC
/// frame (67.5 ms) and the 108 ms repeat period of a held key. Decoding on
/// the crystal was measured in the emulator: an On frame's end to its first
/// PWM pulse took 0.92 ms (0.46 ms at 125 MHz), and an On queued during a
/// block erase, its 67 edges decoded in one pass, 2.50 ms after the erase
/// (the 1 ms contract: scenarios `2-on`, `12-stalls`).
const IR_FULL_SPEED_US: u64 = 120_000;

/// The clock speed the pass's decision needs: PLL_SYS's 125 MHz whenever
/// the motor may run or a USB host is served, else the crystal. Set before
/// the duty is applied, so a motor never starts on the crystal.
///
/// Not the crystal while the motor runs: the PWM counter is clocked by
/// clk_sys. At 125 MHz the 25 kHz carrier has 5000 steps (divider 1, TOP
/// 4999); on the 12 MHz crystal the same setting gives 2.4 kHz, and no
/// divider gives 25 kHz with more than 480 steps, under the 1024 that
/// `motor.rs` asserts (and the emulator's `2-on` checks). Changing clk_sys
/// between the passes of a running motor would change its carrier, and
/// relocking PLL_SYS every 1 ms pass costs its lock time each time.
/// Not the crystal with USB connected and its bus active (`usb_active`):
/// the board then runs from VBUS, not from the cell, and a 64-byte packet
/// goes out per pass at full speed. A suspended bus (the PC asleep) is
/// idle: crystal. Nor while IR frames arrive (`ir_active`).
fn speed_after(out: &PassOutput, usb_active: bool, ir_active: bool) -> Speed {
    let motor_idle = out.duty.raw() == 0 && !out.hall_power && out.next_pass_in_us.is_none();
    if motor_idle && !usb_active && !ir_active {
        Speed::Crystal
    } else {
        Speed::Full
    }
}

/// The last fault that stopped the motor since power-up, for `INFO`.
#[derive(Default)]
struct Faults {
    last: Option<SensorFault>,
}

impl Faults {
    fn note(&mut self, out: &PassOutput) {
        if let Some(f) = out.fault {
            self.last = Some(f);
        }
    }
}

/// The pins the pre-start self-test reads (`swimbot_shared::PreStart`):
/// the gate's level and both Hall lines (SIO.GPIO_IN, one read).
fn prestart(motor: &Motor) -> PreStart {
    // SAFETY: a read of the input register.
    let inputs = unsafe { &*rp2040_hal::pac::SIO::ptr() }
        .gpio_in()
        .read()
        .bits();
    PreStart {
        gate_high: motor.gate_high(),
        hall_a_high: inputs & (1 << board::HALL_A_GPIO) != 0,
        hall_b_high: inputs & (1 << board::HALL_B_GPIO) != 0,
    }
}

/// The robot's part of the `INFO` line.
fn status(out: &PassOutput, faults: &Faults) -> Status {
    Status {
        firmware: env!("CARGO_PKG_VERSION"),
        commit: env!("SWIMBOT_COMMIT"),
        battery_mv: out.battery.mv,
        battery: out.battery.level,
        rate_mhz: out.rate_mhz,
        set_point_mhz: out.set_point_mhz,
        fault: faults.last,
        trips: out.trips,
        locked_out: out.locked_out,
        pairing: if out.pairing_window {
            PairingState::Window
        } else if out.paired.is_some() {
            PairingState::Paired
        } else {
            PairingState::Unpaired
        },
    }
}

/// Log the pass's news; true if an interrupt queue dropped edges.
fn log(out: &PassOutput, level: &mut BatteryLevel, led_mode: &mut LedMode) -> bool {
    if let Some(c) = out.command {
        defmt::info!("ir: {}", c);
    }
    let dropped = ir::take_dropped();
    if dropped > 0 {
        defmt::warn!("ir: queue full, {} edges dropped", dropped);
    }
    let hall_dropped = ir::take_hall_dropped();
    if hall_dropped > 0 {
        defmt::warn!("hall: queue full, {} edges dropped", hall_dropped);
    }
    if let Some(mhz) = out.set_point_changed {
        defmt::info!("set-point: {} mHz", mhz);
    }
    if let Some(fault) = out.fault {
        if out.locked_out {
            defmt::error!(
                "{}: trip {} since power-up, motor locked out until the next power-up",
                fault,
                out.trips
            );
        } else {
            defmt::error!("rate sensor: {}, motor stopped (a new On retries)", fault);
        }
    }
    if let Some(f) = out.refused_self_test {
        defmt::error!("On refused: pre-start self-test failed ({})", f);
    }
    if out.refused_no_set_point {
        defmt::warn!("On ignored: no rate set-point selected");
    }
    if let Some(counts) = out.sample {
        if out.battery.level != *level {
            *level = out.battery.level;
            defmt::info!(
                "battery: {} at {} mV ({} counts)",
                *level,
                out.battery.mv,
                counts
            );
        }
    }
    if let Some(event) = out.event {
        defmt::info!(
            "motor: {} -> {}, duty {}/65536, battery {} mV",
            event,
            out.state,
            out.duty.raw(),
            out.battery.mv
        );
    }
    if out.led != *led_mode {
        *led_mode = out.led;
        defmt::info!("led: {}", out.led);
    }
    dropped > 0 || hall_dropped > 0
}

/// `fault-test` images only: the emulator writes `SWIMBOT_FAULT_TEST`
/// (found by its symbol) to make the main loop hang (1), panic (2) or
/// overflow its stack (3).
#[cfg(feature = "fault-test")]
mod fault_test {
    use core::sync::atomic::{AtomicU32, Ordering};

    #[no_mangle]
    static SWIMBOT_FAULT_TEST: AtomicU32 = AtomicU32::new(0);

    /// Recurses until the stack runs off the bottom of RAM (flip-link puts
    /// it there), 64 bytes a frame; `black_box` keeps every frame real.
    #[allow(unconditional_recursion)]
    #[inline(never)]
    fn overflow(depth: u32) -> u32 {
        let frame = core::hint::black_box([depth; 16]);
        overflow(depth + 1).wrapping_add(frame[(depth & 15) as usize])
    }

    pub fn act() {
        match SWIMBOT_FAULT_TEST.load(Ordering::Relaxed) {
            1 => {
                defmt::warn!("fault-test: main loop hangs, motor left as it is");
                #[allow(clippy::empty_loop)]
                loop {}
            }
            2 => panic!("fault-test: forced panic"),
            3 => {
                defmt::warn!("fault-test: unbounded recursion");
                overflow(0);
            }
            _ => {}
        }
    }
}
