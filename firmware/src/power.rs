//! Power: which clocks run while the core sleeps between passes, and the
//! DORMANT state after a long idle (or a cut-off), woken by the IR pin or
//! by a USB cable (VBUS).
//!
//! Between passes (WFI with SLEEPDEEP set, so the clock gates below apply)
//! only what a sleeping robot needs keeps its clock: the PWM (the motor's
//! carrier), the timer and the watchdog (the 1 kHz wake-up alarm and its
//! tick), IO and pads (the IR edge interrupt, pin levels), the SRAM (a
//! debug probe may read the RTT buffer while the core sleeps), and the bus,
//! clock, reset and power controllers themselves. The ADC, USB, UART, SPI,
//! I2C, PIO, DMA, RTC, ROM, XIP and the rest are gated; the USB
//! controller's clocks only while no USB host is connected (`usb_awake`).
//!
//! clk_sys (`Speed`): 125 MHz from PLL_SYS only while the motor may run,
//! a USB host is served or IR frames arrive (`run::speed_after`, which
//! gives the measured reasons); the 12 MHz crystal with PLL_SYS powered
//! down otherwise, between idle passes included. Not the crystal with the
//! motor on: the PWM counts clk_sys, 5000 steps a 25 kHz period at 125 MHz
//! but at most 480 on the crystal (the floor is 1024). Not while IR frames
//! arrive: decoded on the crystal, On took 0.92 ms to its first pulse
//! (0.45 ms at 125 MHz; the contract is 1 ms), and 2.50 ms after a block
//! erase that had queued the frame (emulator, `2-on` and `12-stalls`). PLL_USB and clk_usb run
//! only while VBUS is present (`usb_awake`); clk_adc is on the crystal
//! after boot and clk_rtc is stopped.
//!
//! DORMANT stops the crystal and every clock; only a GPIO edge restarts
//! them. Before it: motor off (the caller's condition), the system clock
//! on the crystal, both PLLs stopped (the sequence of the C SDK's
//! `sleep_run_from_xosc` and `sleep_goto_dormant_until_pin`). After the
//! wake the chip runs on the stable crystal until a pass needs PLL_SYS,
//! which is relocked before any duty is applied, so the PWM divider and
//! every timing stay valid. The 1 MHz timer stops during DORMANT (its tick
//! comes from the crystal): time simply resumes.
//!
//! Two wake-ups (the IO bank's DORMANT_WAKE_INTE, RP2040 datasheet 2.19.3
//! and 2.19.6: the same raw events as the GPIO interrupts, pin levels and
//! latched edges):
//! - VBUS high on GPIO24: a cable plugged in to read the log. The pass
//!   that follows sees VBUS, holds the motor off and serves the port,
//!   which the host then enumerates (it waits at least 100 ms after the
//!   connect before its bus reset, USB 2.0 7.1.7.3; the wake takes the
//!   crystal's start-up and the PLLs' lock, about 1 ms). A level, not the
//!   rising edge: a cable plugged in between the pass's VBUS read and the
//!   DORMANT write wakes the chip at once instead of being missed, and no
//!   edge latched by an earlier plug-in (INTR keeps it until cleared) can
//!   wake it again and again. Unplugged, the level is low: no wake-up; a
//!   blip shorter than a pass wakes it once, and the next pass, seeing no
//!   VBUS, goes DORMANT again.
//! - The IR receiver's first falling edge (a frame's leader burst). The IR
//!   interrupt also latches it, but on the chip its timestamp is taken
//!   only once the clocks run again (crystal start-up, about 1 ms, and PLL
//!   lock): the leader reads short by that much, within the decoder's
//!   9 ms +-25 % window. Should the first frame be lost on a given board,
//!   the next press works.
//!
//! Current: computed per state in firmware/README.md ("Current budget"),
//! to be measured on a board; no figure is claimed here.

use crate::board;
use fugit::RateExtU32;
use rp2040_hal::clocks::{Clock, ClockGate, ClocksManager, StoppableClock};
use rp2040_hal::pac::{self, CLOCKS, PLL_SYS, PLL_USB, RESETS, XOSC};
use rp2040_hal::pll::common_configs::{PLL_SYS_125MHZ, PLL_USB_48MHZ};
use rp2040_hal::pll::{setup_pll_blocking, start_pll_blocking, Disabled, Locked, PhaseLockedLoop};
use rp2040_hal::xosc::{setup_xosc_blocking, CrystalOscillator, Stable};
use rp2040_hal::Watchdog;

/// The clocks that keep running while the core sleeps between passes.
pub fn sleep_clock_gates() -> ClockGate {
    let mut g = ClockGate::default();
    g.set_sys_clock(true);
    g.set_sys_busctrl(true);
    g.set_sys_busfabric(true);
    g.set_sys_io(true);
    g.set_sys_pads(true);
    g.set_sys_vreg_and_chip_reset(true);
    g.set_sys_pll_sys(true);
    g.set_sys_pll_usb(true);
    g.set_sys_psm(true);
    g.set_sys_pwm(true);
    g.set_sys_resets(true);
    g.set_sys_sio(true);
    g.set_sys_sram0(true);
    g.set_sys_sram1(true);
    g.set_sys_sram2(true);
    g.set_sys_sram3(true);
    g.set_sys_sram4(true);
    g.set_sys_sram5(true);
    g.set_sys_timer(true);
    g.set_sys_watchdog(true);
    g.set_sys_xosc(true);
    g
}

/// A DORMANT wake-up source: one event bit of a pin's 4-bit field in
/// DORMANT_WAKE_INTE0-3 and INTR0-3 (8 pins a register; bit 0 level low,
/// 1 level high, 2 edge low, 3 edge high).
#[derive(Clone, Copy)]
struct WakeEvent {
    reg: usize,
    bit: u32,
}

impl WakeEvent {
    const fn new(gpio: u8, event: u32) -> Self {
        Self {
            reg: gpio as usize / 8,
            bit: 1 << ((gpio as u32 % 8) * 4 + event),
        }
    }
}

const LEVEL_HIGH: u32 = 1;
const EDGE_LOW: u32 = 2;
const IR_WAKE: WakeEvent = WakeEvent::new(board::IR_GPIO, EDGE_LOW);
const VBUS_WAKE: WakeEvent = WakeEvent::new(board::VBUS_SENSE_GPIO, LEVEL_HIGH);

/// What clk_sys runs from.
#[derive(Clone, Copy, PartialEq, Eq, defmt::Format)]
pub enum Speed {
    /// 125 MHz from PLL_SYS: whenever the motor may run (the PWM counter
    /// and its divider are set for it) or a USB host is served.
    Full,
    /// The 12 MHz crystal, PLL_SYS off: idle passes, and the state DORMANT
    /// is entered from and left in.
    Crystal,
}

/// The clock tree and what it is built from, kept so that the idle speed,
/// the USB clocks and DORMANT can take it down and put it back.
pub struct Power {
    pub clocks: ClocksManager,
    xosc: Option<CrystalOscillator<Stable>>,
    pll_sys: Pll<PLL_SYS>,
    pll_usb: Pll<PLL_USB>,
    /// Handed over once every peripheral is out of reset (`keep_resets`).
    resets: Option<RESETS>,
    /// PLL_USB and clk_usb run (VBUS present); until `keep_resets`, the
    /// boot's tree.
    usb_awake: bool,
    speed: Speed,
}

/// A PLL, running or stopped (its typestate as a value).
enum Pll<P: rp2040_hal::pll::PhaseLockedLoopDevice> {
    Locked(PhaseLockedLoop<Locked, P>),
    Off(PhaseLockedLoop<Disabled, P>),
    Gone,
}

impl<P: rp2040_hal::pll::PhaseLockedLoopDevice> Pll<P> {
    fn stop(&mut self) {
        if let Pll::Locked(p) = core::mem::replace(self, Pll::Gone) {
            *self = Pll::Off(p.disable());
        }
    }

    /// Relock a stopped PLL; a PLL that does not relock is a panic: the
    /// fail-safe handler keeps the motor off and resets.
    fn start(&mut self, resets: &mut RESETS) {
        if let Pll::Off(p) = core::mem::replace(self, Pll::Gone) {
            match start_pll_blocking(p, resets) {
                Ok(p) => *self = Pll::Locked(p),
                Err(_) => panic!("a PLL did not relock"),
            }
        }
    }

    fn locked(&self) -> Option<&PhaseLockedLoop<Locked, P>> {
        match self {
            Pll::Locked(p) => Some(p),
            _ => None,
        }
    }
}

impl Power {
    /// rp2040-hal's `init_clocks_and_plls` (125 MHz system, 48 MHz USB and
    /// ADC), keeping the crystal and the PLLs for the idle speed, the USB
    /// clocks and DORMANT; then the sleep clock gates, applied by
    /// SLEEPDEEP. Both PLLs run until `keep_resets`: the USB controller and
    /// the ADC leave reset only with their clocks running (RESET_DONE waits
    /// for them). A clock that does not start is a panic: the fail-safe
    /// handler keeps the motor off and resets.
    pub fn start(
        (xosc, clocks, pll_sys, pll_usb): (XOSC, CLOCKS, PLL_SYS, PLL_USB),
        resets: &mut RESETS,
        watchdog: &mut Watchdog,
        scb: &mut pac::SCB,
    ) -> Self {
        let xosc = setup_xosc_blocking(xosc, board::XOSC_HZ.Hz()).ok().unwrap();
        watchdog.enable_tick_generation((board::XOSC_HZ / 1_000_000) as u8);
        let mut clocks = ClocksManager::new(clocks);
        let f = xosc.operating_frequency();
        let pll_sys = setup_pll_blocking(pll_sys, f, PLL_SYS_125MHZ, &mut clocks, resets)
            .ok()
            .unwrap();
        let pll_usb = setup_pll_blocking(pll_usb, f, PLL_USB_48MHZ, &mut clocks, resets)
            .ok()
            .unwrap();
        clocks.init_default(&xosc, &pll_sys, &pll_usb).ok().unwrap();
        clocks.configure_sleep_enable(sleep_clock_gates());
        scb.set_sleepdeep();
        Self {
            clocks,
            xosc: Some(xosc),
            pll_sys: Pll::Locked(pll_sys),
            pll_usb: Pll::Locked(pll_usb),
            resets: None,
            usb_awake: true,
            speed: Speed::Full,
        }
    }

    /// The reset controller, needed to restart the PLLs; every peripheral
    /// is out of reset now, so the boot's tree becomes the running one:
    /// clk_adc on the crystal for good (a conversion takes 96 x 83 ns =
    /// 8 us instead of 2 us; the mid-pulse start still fits, the shortest
    /// running pulse being 24 us), clk_rtc stopped (no RTC is used), and
    /// PLL_USB and clk_usb only while VBUS is present (`usb_awake`).
    pub fn keep_resets(&mut self, resets: RESETS) {
        self.resets = Some(resets);
        if let Some(xosc) = self.xosc.as_ref() {
            let _ = self
                .clocks
                .adc_clock
                .configure_clock(xosc, xosc.operating_frequency());
        }
        self.clocks.rtc_clock.disable();
        self.usb_awake(false);
    }

    /// VBUS present: PLL_USB relocked and clk_usb (48 MHz) on, and the USB
    /// controller's clocks kept running in sleep (it answers the host
    /// between passes); absent: clk_usb and PLL_USB stopped, the
    /// controller's clocks gated. Nothing is done before `keep_resets`.
    pub fn usb_awake(&mut self, awake: bool) {
        if awake == self.usb_awake {
            return;
        }
        let Some(resets) = self.resets.as_mut() else {
            return;
        };
        if awake {
            self.pll_usb.start(resets);
            let Some(pll_usb) = self.pll_usb.locked() else {
                panic!("PLL_USB is not running");
            };
            if self
                .clocks
                .usb_clock
                .configure_clock(pll_usb, pll_usb.operating_frequency())
                .is_err()
            {
                panic!("clk_usb did not start");
            }
        } else {
            self.clocks.usb_clock.disable();
            self.pll_usb.stop();
        }
        let mut gates = sleep_clock_gates();
        gates.set_sys_usbctrl(awake);
        gates.set_usb_usbctrl(awake);
        gates.set_sys_pll_usb(awake);
        self.clocks.configure_sleep_enable(gates);
        self.usb_awake = awake;
    }

    pub fn speed(&self) -> Speed {
        self.speed
    }

    /// Run clk_sys at `speed` from now on. Going up relocks PLL_SYS first
    /// (the caller does this before it drives the motor); going down moves
    /// clk_sys (and clk_peri with it) to clk_ref, the crystal, before
    /// stopping the PLL (RP2040 datasheet 2.15.3.2: clk_sys's glitchless
    /// mux). Nothing is done before `keep_resets`.
    pub fn set_speed(&mut self, speed: Speed) {
        if speed == self.speed {
            return;
        }
        let Some(resets) = self.resets.as_mut() else {
            return;
        };
        match speed {
            Speed::Full => {
                self.pll_sys.start(resets);
                let Some(pll_sys) = self.pll_sys.locked() else {
                    panic!("PLL_SYS is not running");
                };
                if self
                    .clocks
                    .system_clock
                    .configure_clock(pll_sys, pll_sys.operating_frequency())
                    .is_err()
                {
                    panic!("clk_sys did not come back");
                }
            }
            Speed::Crystal => {
                let Some(xosc) = self.xosc.as_ref() else {
                    return;
                };
                let _ = self
                    .clocks
                    .system_clock
                    .configure_clock(&self.clocks.reference_clock, xosc.operating_frequency());
                self.pll_sys.stop();
            }
        }
        // clk_peri follows clk_sys; its recorded frequency with it.
        let f = self.clocks.system_clock.freq();
        let _ = self
            .clocks
            .peripheral_clock
            .configure_clock(&self.clocks.system_clock, f);
        self.speed = speed;
    }

    /// Go DORMANT until the IR pin falls or VBUS is present; return on the
    /// crystal (`Speed::Crystal`: the caller's next pass picks the speed it
    /// needs). The next pass handles the cause as any pass does: the IR
    /// edge is queued by its interrupt, VBUS is read. `false` (nothing
    /// done) if the tree is not complete.
    pub fn dormant_until_wake(&mut self) -> bool {
        if self.resets.is_none() || self.xosc.is_none() {
            return false;
        }
        // Both PLLs stopped: DORMANT's precondition (no VBUS, so no USB).
        self.usb_awake(false);
        self.set_speed(Speed::Crystal);
        let Some(xosc) = self.xosc.take() else {
            return false;
        };
        set_wake(true);
        // SAFETY: the system clock runs from the crystal and both PLLs are
        // stopped (`dormant`'s precondition); the wake-ups are enabled.
        // DORMANT stops the crystal; the ring oscillator is already off
        // (the boot's tree never uses it and `setup_xosc_blocking` leaves
        // it as the ROM left it: see `rosc_off`).
        let unstable = unsafe { xosc.dormant() };
        let token = loop {
            if let Ok(token) = unstable.await_stabilization() {
                break token;
            }
        };
        self.xosc = Some(unstable.get_stable(token));
        set_wake(false);
        true
    }
}

/// Stop the ring oscillator, which the boot ROM started and ran the chip
/// on until the crystal took over: nothing here uses it afterwards, and
/// left running it draws in every state, DORMANT included (it is a
/// separate oscillator: XOSC's DORMANT does not stop it). RP2040
/// datasheet 2.17.8 (ROSC CTRL.ENABLE, the magic value 0xd1e to disable).
pub fn rosc_off() {
    // SAFETY: the system and reference clocks run from the crystal (after
    // `Power::start`); a write of ROSC's CTRL only.
    let rosc = unsafe { &*pac::ROSC::ptr() };
    rosc.ctrl().modify(|_, w| w.enable().disable());
}

fn set_wake(enabled: bool) {
    set_wake_event(IR_WAKE, enabled);
    set_wake_event(VBUS_WAKE, enabled);
}

fn set_wake_event(e: WakeEvent, enabled: bool) {
    // SAFETY: atomic set/clear of the event's own bit; nothing else uses
    // the dormant wake registers.
    let io = unsafe { &*pac::IO_BANK0::ptr() };
    io.dormant_wake_inte(e.reg).modify(|r, w| unsafe {
        w.bits(if enabled {
            r.bits() | e.bit
        } else {
            r.bits() & !e.bit
        })
    });
}
