//! Swimbot firmware: binds the shared controller (`swimbot_shared`) to the
//! RP2040. Every decision is made by the shared, host-tested code; this
//! crate only moves pins, clocks, the ADC, the PWM and the watchdog.
//!
//! Boot order matters: the motor gate is driven low before the clocks are
//! touched, then the peripherals come up, and the watchdog starts last so
//! that slow clock start-up cannot trip it. A panic or HardFault at any
//! point forces the gate low and resets (`safety`).
#![cfg_attr(target_os = "none", no_std, no_main)]
// The `hil` image stops in `hil::run`: what follows it is never used there.
#![cfg_attr(feature = "hil", allow(unused, unreachable_code))]

// Everything below exists only on the chip (`cargo fw`). On a host the crate
// is an empty program, so `cargo clippy --workspace` can pass over it; the
// test command lints it for thumbv6m-none-eabi, where its assembly and
// panic handler belong.
#[cfg(target_os = "none")]
mod battery_adc;
#[cfg(target_os = "none")]
mod board;
#[cfg(target_os = "none")]
mod flash;
#[cfg(all(target_os = "none", feature = "hil"))]
mod hil;
#[cfg(all(target_os = "none", feature = "hil-faults"))]
mod hil_faults;
#[cfg(target_os = "none")]
mod ir;
#[cfg(target_os = "none")]
mod motor;
#[cfg(target_os = "none")]
mod pairing;
#[cfg(target_os = "none")]
mod power;
#[cfg(target_os = "none")]
mod run;
#[cfg(target_os = "none")]
mod safety;
#[cfg(target_os = "none")]
mod sleep;
#[cfg(target_os = "none")]
mod usb;

#[cfg(target_os = "none")]
use defmt_rtt as _;
#[cfg(all(target_os = "none", feature = "probe"))]
use panic_probe as _;
#[cfg(target_os = "none")]
use rp2040_hal as hal;

#[cfg(not(target_os = "none"))]
fn main() {
    eprintln!("the firmware runs on the RP2040 only: build it with `cargo fw`");
    std::process::exit(2);
}

/// The second-stage bootloader: the flash chip's read mode (plain 03h
/// reads, the one every flash chip supports). `flash` re-runs a RAM copy
/// of it after each flash write.
#[cfg(target_os = "none")]
pub const BOOT2_IMAGE: [u8; 256] = rp2040_boot2::BOOT_LOADER_GENERIC_03H;

#[cfg(target_os = "none")]
#[link_section = ".boot2"]
#[used]
pub static BOOT2: [u8; 256] = BOOT2_IMAGE;

// Log lines carry the 1 MHz timer's microseconds. Read through the PAC
// (TIMERAWL/H, no latching side effects): the HAL's Timer is owned by the
// main loop.
#[cfg(target_os = "none")]
defmt::timestamp!("{=u64:us}", {
    // SAFETY: reads of the free-running timer's raw registers.
    let timer = unsafe { &*hal::pac::TIMER::ptr() };
    loop {
        let hi = timer.timerawh().read().bits();
        let lo = timer.timerawl().read().bits();
        if timer.timerawh().read().bits() == hi {
            break (u64::from(hi) << 32) | u64::from(lo);
        }
    }
});

#[cfg(target_os = "none")]
#[hal::entry]
fn main() -> ! {
    use fugit::ExtU32;
    use hal::gpio::PinState;
    use hal::pac;

    // `take` cannot fail this early: nothing else has taken them.
    let mut p = pac::Peripherals::take().unwrap();
    let mut cortex = pac::CorePeripherals::take().unwrap();
    #[allow(unused_mut)]
    let mut sio = hal::Sio::new(p.SIO);
    // Before anything could be fetched from flash behind our back
    // (interrupts are still off): the serial number of the USB port.
    let flash_id = flash::unique_id();
    let pins = hal::gpio::Pins::new(p.IO_BANK0, p.PADS_BANK0, sio.gpio_bank0, &mut p.RESETS);
    let motor_pin = pins.gpio16.into_push_pull_output_in_state(PinState::Low);
    // Keep the load switch (if the board has one) closed: see `board`.
    let power_hold = pins.gpio22.into_push_pull_output_in_state(PinState::High);

    let reason = p.WATCHDOG.reason().read();
    let (watchdog_reset, forced_reset) = (reason.timer().bit_is_set(), reason.force().bit_is_set());
    let mut watchdog = hal::Watchdog::new(p.WATCHDOG);
    let mut power = power::Power::start(
        (p.XOSC, p.CLOCKS, p.PLL_SYS, p.PLL_USB),
        &mut p.RESETS,
        &mut watchdog,
        &mut cortex.SCB,
    );
    power::rosc_off();
    let clocks = &power.clocks;
    let sys_hz = hal::Clock::freq(&clocks.system_clock).to_Hz();
    #[cfg(feature = "hil-faults")]
    {
        // The previous boot's record first, then core 1 times the gate's
        // falls on the jig's loopback (GPIO17, pulled down: no wire, no fall).
        static CORE1_STACK: hal::multicore::Stack<256> = hal::multicore::Stack::new();
        hil_faults::take_record(watchdog_reset, forced_reset);
        let _loopback = pins.gpio17.into_pull_down_input();
        let mut mc = hal::multicore::Multicore::new(&mut p.PSM, &mut p.PPB, &mut sio.fifo);
        let stack = CORE1_STACK.take().unwrap();
        let _ = mc.cores()[1].spawn(stack, || hil_faults::watch());
    }
    if watchdog_reset {
        defmt::warn!("reset by the watchdog");
    }
    if forced_reset {
        defmt::warn!("reset after a panic or fault (motor was forced off)");
    }

    let mut timer = hal::Timer::new(p.TIMER, &mut p.RESETS, clocks);
    let slices = hal::pwm::Slices::new(p.PWM, &mut p.RESETS);
    let motor = motor::Motor::new(slices.pwm0, motor_pin, sys_hz);
    let adc = hal::Adc::new(p.ADC, &mut p.RESETS);
    let battery_pin = hal::adc::AdcPin::new(pins.gpio26.into_floating_input()).unwrap();
    let battery = battery_adc::BatterySense::new(adc, battery_pin);
    let led = pins.gpio25.into_push_pull_output_in_state(PinState::Low);
    let mut hall_power = pins.gpio12.into_push_pull_output_in_state(PinState::Low);
    // Two latches draw up to 7 mA: past the default 4 mA drive (`board`).
    hall_power.set_drive_strength(hal::gpio::OutputDriveStrength::TwelveMilliAmps);
    let hall = (
        pins.gpio13.into_pull_up_input(),
        pins.gpio14.into_pull_up_input(),
    );
    ir::start(pins.gpio15.into_pull_up_input(), hall);
    sleep::start(&mut timer);
    let usb = usb::Usb::new(
        p.USBCTRL_REGS,
        p.USBCTRL_DPRAM,
        &mut p.RESETS,
        pins.gpio24.into_floating_input(),
        flash_id,
    );

    power.keep_resets(p.RESETS);
    #[cfg(feature = "hil")]
    hil::run(&mut power, &mut watchdog);
    watchdog.start((board::WATCHDOG_MS * 1_000).micros());
    safety::watchdog_runs_under_debugger();
    defmt::info!(
        "swimbot up: sys {} Hz, watchdog {} ms",
        sys_hz,
        board::WATCHDOG_MS
    );
    let robot = run::Robot {
        motor,
        battery,
        led,
        hall_power,
        power_hold,
        timer,
        power,
        usb,
    };
    robot.run(&mut watchdog)
}
