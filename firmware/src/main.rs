//! Swimbot firmware entry point (placeholder until the controller lands):
//! drives the motor pin low at reset and idles.
#![no_std]
#![no_main]

use defmt_rtt as _;
use panic_probe as _;
use rp2040_hal as hal;

use embedded_hal::digital::OutputPin;
use hal::pac;

#[link_section = ".boot2"]
#[used]
pub static BOOT2: [u8; 256] = rp2040_boot2::BOOT_LOADER_GENERIC_03H;

const XOSC_HZ: u32 = 12_000_000;

#[hal::entry]
fn main() -> ! {
    let mut p = pac::Peripherals::take().unwrap();
    let sio = hal::Sio::new(p.SIO);
    let pins = hal::gpio::Pins::new(p.IO_BANK0, p.PADS_BANK0, sio.gpio_bank0, &mut p.RESETS);
    let mut motor = pins.gpio16.into_push_pull_output();
    motor.set_low().ok();
    let mut watchdog = hal::Watchdog::new(p.WATCHDOG);
    let _clocks = hal::clocks::init_clocks_and_plls(
        XOSC_HZ,
        p.XOSC,
        p.CLOCKS,
        p.PLL_SYS,
        p.PLL_USB,
        &mut p.RESETS,
        &mut watchdog,
    )
    .ok()
    .unwrap();
    defmt::info!("swimbot firmware up");
    loop {
        cortex_m::asm::wfi();
    }
}
