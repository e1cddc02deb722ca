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
//! DORMANT stops the crystal and every clock; only a GPIO edge restarts
//! them. Before it: motor off (the caller's condition), the system clock
//! moved to the crystal, the clocks fed by the USB PLL stopped, both PLLs
//! stopped (the sequence of the C SDK's `sleep_run_from_xosc` and
//! `sleep_goto_dormant_until_pin`). After the wake the chip runs on the
//! stable crystal (`Speed::Crystal`) until the next pass asks for the
//! boot's tree (125 MHz system, 48 MHz ADC) and the PLLs relock, before
//! any duty is applied, so the PWM divider and every timing stay valid. The 1 MHz timer stops
//! during DORMANT (its tick comes from the crystal): time simply resumes.
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
//! Current: not measured for this configuration (clk_sys 125 MHz from
//! PLL_SYS and PLL_USB at 48 MHz for clk_adc and clk_usb between passes,
//! whether or not VBUS is present), and no figure is claimed: the RP2040
//! datasheet's 5.4 table and the MicroPython developers' Pico figures
//! (commit b004e7e) describe other clock configurations. The board's
//! bring-up measures it (firmware/README.md, bring-up step 5).

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

/// How fast the chip runs between passes.
#[derive(Clone, Copy, PartialEq, Eq, defmt::Format)]
pub enum Speed {
    /// The boot's tree: 125 MHz system (PLL_SYS), 48 MHz USB and ADC
    /// (PLL_USB). Whenever the motor may run: its PWM divider and the
    /// ADC's mid-pulse timing are set for it.
    Full,
    /// USB suspended: the system clock on the 12 MHz crystal, PLL_SYS off;
    /// PLL_USB keeps clk_usb, which the controller needs to see the host
    /// resume the bus.
    UsbSuspended,
    /// Everything on the crystal (system, peripherals, ADC), both PLLs
    /// off: the state DORMANT is entered from and left in. Usable between
    /// idle passes too (`run::speed_after` explains why it is not).
    Crystal,
}

/// The clock tree and what it is built from, kept so that the idle speeds
/// and DORMANT can take it down and put it back.
pub struct Power {
    pub clocks: ClocksManager,
    xosc: Option<CrystalOscillator<Stable>>,
    pll_sys: Pll<PLL_SYS>,
    pll_usb: Pll<PLL_USB>,
    /// Handed over once every peripheral is out of reset (`keep_resets`).
    resets: Option<RESETS>,
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
    /// ADC), keeping the crystal and the PLLs for the idle speeds and
    /// DORMANT; then the sleep clock gates, applied by SLEEPDEEP. A clock
    /// that does not start is a panic: the fail-safe handler keeps the
    /// motor off and resets.
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
            usb_awake: false,
            speed: Speed::Full,
        }
    }

    /// Keep the USB controller's clocks running in sleep (while USB is
    /// connected: it answers the host between passes), or gate them again.
    pub fn usb_awake(&mut self, awake: bool) {
        if awake == self.usb_awake {
            return;
        }
        let mut gates = sleep_clock_gates();
        gates.set_sys_usbctrl(awake);
        gates.set_usb_usbctrl(awake);
        self.clocks.configure_sleep_enable(gates);
        self.usb_awake = awake;
    }

    /// The reset controller, needed to restart the PLLs.
    pub fn keep_resets(&mut self, resets: RESETS) {
        self.resets = Some(resets);
    }

    pub fn speed(&self) -> Speed {
        self.speed
    }

    /// Run at `speed` from now on. Going up relocks the PLLs first (the
    /// PLL's lock takes tens of microseconds; the caller does this before
    /// it drives the motor); going down moves every clock off a PLL before
    /// stopping it (RP2040 datasheet 2.15.3.2: glitchless muxes for
    /// clk_sys and clk_ref; the aux sources are switched with the clock
    /// briefly stopped, as `configure_clock` does). Nothing is done before
    /// `keep_resets`.
    pub fn set_speed(&mut self, speed: Speed) {
        if speed == self.speed || self.resets.is_none() {
            return;
        }
        self.full_speed();
        if speed != Speed::Full {
            self.slow_down(speed == Speed::UsbSuspended);
        }
        self.speed = speed;
    }

    /// The boot's tree again, from any speed.
    fn full_speed(&mut self) {
        let Some(resets) = self.resets.as_mut() else {
            return;
        };
        if self.pll_sys.locked().is_some() && self.pll_usb.locked().is_some() {
            return;
        }
        self.pll_sys.start(resets);
        self.pll_usb.start(resets);
        let (Some(xosc), Some(pll_sys), Some(pll_usb)) = (
            self.xosc.as_ref(),
            self.pll_sys.locked(),
            self.pll_usb.locked(),
        ) else {
            panic!("the clock tree is incomplete");
        };
        if self.clocks.init_default(xosc, pll_sys, pll_usb).is_err() {
            panic!("the clock tree did not come back");
        }
        self.speed = Speed::Full;
    }

    /// From the boot's tree: clk_sys (and clk_peri with it) on clk_ref,
    /// the crystal; PLL_SYS stopped; unless `keep_usb`, clk_adc on the
    /// crystal too (a conversion then takes 96 x 83 ns = 8 us instead of
    /// 2 us: the motor is off, so there is no pulse to fit it in), clk_usb
    /// and clk_rtc stopped and PLL_USB stopped.
    fn slow_down(&mut self, keep_usb: bool) {
        let Some(xosc) = self.xosc.as_ref() else {
            return;
        };
        let freq = xosc.operating_frequency();
        let _ = self
            .clocks
            .system_clock
            .configure_clock(&self.clocks.reference_clock, freq);
        let _ = self
            .clocks
            .peripheral_clock
            .configure_clock(&self.clocks.system_clock, freq);
        self.pll_sys.stop();
        if !keep_usb {
            let _ = self.clocks.adc_clock.configure_clock(xosc, freq);
            self.clocks.usb_clock.disable();
            self.clocks.rtc_clock.disable();
            self.pll_usb.stop();
        }
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
