//! The run log's readout over USB: a CDC-ACM serial port (usb-device with
//! usbd-serial's `CdcAcmClass` on rp2040-hal's `UsbBus`) that answers the
//! requests of `swimbot_shared::run_log` (`LOG`: the log image; `INFO`: one
//! line about the log and the robot; `BOOTSEL`: reboot into the ROM's USB
//! bootloader, honoured only with the motor off and its gate low).
//!
//! The descriptor is the composite form (device class 0xEF/0x02/0x01, an
//! interface association around the two CDC interfaces), as TinyUSB and
//! pico-sdk declare a CDC port: Windows 10/11 load usbser.sys for it without
//! an INF, Linux binds cdc_acm and macOS AppleUSBCDCACM. The serial number
//! is the flash chip's 64-bit unique ID (`flash::unique_id`, read at boot),
//! so two robots on one PC keep their port names.
//!
//! VBUS is sensed on GPIO24 (the Pico's divider from the USB connector):
//! the D+ pull-up is on only while it is present (a board on battery does
//! not announce itself to a dead bus, and an unplugged cable leaves the
//! controller detached). The controller's own VBUS detect is forced on
//! (the Pico does not route VBUS to it); GPIO24 decides.
//!
//! While VBUS is present the main loop tells the pass, which holds the
//! motor off and refuses On, forbids flash erases (the host would time
//! out) and DORMANT; the USB clock is kept running in sleep, and the USB
//! interrupt wakes the core (its handler only masks itself; the main loop
//! polls the device and unmasks it), so each pass serves the port. A
//! suspended bus (the PC asleep, no SOF for 3 ms) is reported by
//! `suspended`: the main loop then holds the motor off as well and the
//! power module drops the system clock to the crystal (USB 2.0 7.2.3: at
//! most 2.5 mA from the bus). An image is streamed from flash in 64-byte
//! packets as the host takes them.
//!
//! RP2040-E5 (B0/B1 chips enumerating behind a hub): rp2040-hal's
//! `rp2040-e5` workaround borrows GPIO15, the IR receiver's pin, for about
//! 1 ms after each bus reset (it forces the line state J through that
//! pad). Only with a cable in, when the motor is held off; an IR frame in
//! that millisecond may be lost, never turned into a command (the NEC
//! decoder checks every frame's inverted bytes).

use crate::board;
use crate::flash::LogRegion;
use rp2040_hal::clocks::{ClocksManager, UsbClock};
use rp2040_hal::gpio::{bank0::Gpio24, FunctionSioInput, Pin, PullNone};
use rp2040_hal::pac::{self, interrupt, RESETS, USBCTRL_DPRAM, USBCTRL_REGS};
use rp2040_hal::usb::UsbBus;
use swimbot_shared::run_log::readout::{info_line, Line, UNKNOWN_ANSWER};
use swimbot_shared::run_log::status::{Status, BOOTSEL_ANSWER, BOOTSEL_REFUSED};
use swimbot_shared::run_log::store::{LogFlash, LogStore, ReadoutImage};
use swimbot_shared::run_log::{Request, RequestReader};
use usb_device::class_prelude::UsbBusAllocator;
use usb_device::device::{
    StringDescriptors, UsbDevice, UsbDeviceBuilder, UsbDeviceState, UsbVidPid,
};
use usb_device::UsbError;
use usbd_serial::CdcAcmClass;

const _: () = assert!(board::VBUS_SENSE_GPIO == 24, "the typed pin is GPIO24");

pub type VbusPin = Pin<Gpio24, FunctionSioInput, PullNone>;

/// Every endpoint's packet size (control and bulk): full speed's largest.
const MAX_PACKET: u16 = 64;

/// What is being sent. One lives in `Usb` for the whole run and there is
/// no heap to box the text line into: its size is the price of one line.
#[allow(clippy::large_enum_variant)]
enum Answer {
    None,
    Image { image: ReadoutImage, pos: usize },
    Text { line: Line, pos: usize },
}

pub struct Usb {
    vbus: VbusPin,
    device: UsbDevice<'static, UsbBus>,
    port: CdcAcmClass<'static, UsbBus>,
    pulled_up: bool,
    /// The last packet sent was a full one: end the answer with a
    /// zero-length packet.
    zlp_due: bool,
    reader: RequestReader,
    answer: Answer,
    /// `BOOTSEL` was honoured: reboot once its answer has gone out.
    bootsel_due: bool,
    #[cfg(feature = "hil-faults")]
    faults: crate::hil_faults::Faults,
}

/// What the port needs of the robot to answer.
pub struct Robot<'a> {
    pub foreign: u32,
    pub paired: Option<u8>,
    pub status: &'a Status,
    /// `status::bootsel_allowed` for this pass.
    pub bootsel_allowed: bool,
}

/// Bytes of the serial number: the domain, a colon, 16 hex digits.
const SERIAL_LEN: usize = board::USB_SERIAL_DOMAIN.len() + 1 + 16;

/// The serial number's text: `board::USB_SERIAL_DOMAIN`, `:`, then 16 hex
/// digits of the flash chip's unique ID (the shared ID pair's rule,
/// `board::USB_VID`).
fn serial_text(id: [u8; 8]) -> &'static str {
    static mut TEXT: [u8; SERIAL_LEN] = [0; SERIAL_LEN];
    const HEX: &[u8; 16] = b"0123456789ABCDEF";
    // SAFETY: called once, from `Usb::new` (which takes the peripherals it
    // needs by value, so it cannot run twice), before anything reads TEXT.
    let text = unsafe { &mut *core::ptr::addr_of_mut!(TEXT) };
    let domain = board::USB_SERIAL_DOMAIN.as_bytes();
    text[..domain.len()].copy_from_slice(domain);
    text[domain.len()] = b':';
    let digits = &mut text[domain.len() + 1..];
    for (i, b) in id.iter().enumerate() {
        digits[2 * i] = HEX[usize::from(b >> 4)];
        digits[2 * i + 1] = HEX[usize::from(b & 0xf)];
    }
    // ASCII only: always UTF-8.
    core::str::from_utf8(text).unwrap_or("0")
}

/// The USB clock's token `UsbBus::new` asks for, as proof that clk_usb is
/// configured. The firmware's `ClocksManager` stays whole in `Power`
/// (DORMANT stops and restores clk_usb through it), so the token is made
/// from a second manager over the same registers: its constructor only
/// clears CLK_SYS_RESUS_CTRL, which nothing here uses, and `UsbBus` only
/// keeps the token.
fn usb_clock_token() -> UsbClock {
    // SAFETY: see above; no clock is configured through this manager.
    ClocksManager::new(unsafe { pac::CLOCKS::steal() }).usb_clock
}

impl Usb {
    /// The controller up and the port built; the D+ pull-up follows VBUS
    /// from here on. `serial` is the flash chip's unique ID.
    pub fn new(
        regs: USBCTRL_REGS,
        dpram: USBCTRL_DPRAM,
        resets: &mut RESETS,
        vbus: VbusPin,
        serial: [u8; 8],
    ) -> Self {
        let bus = UsbBus::new(regs, dpram, usb_clock_token(), true, resets);
        // `singleton!` is `None` only on a second call; there is one.
        let alloc: &'static UsbBusAllocator<UsbBus> =
            cortex_m::singleton!(: UsbBusAllocator<UsbBus> = UsbBusAllocator::new(bus)).unwrap();
        let port = CdcAcmClass::new(alloc, MAX_PACKET);
        let strings = StringDescriptors::default()
            .manufacturer("swimbot")
            .product(board::USB_PRODUCT)
            .serial_number(serial_text(serial));
        // Neither builder step can fail with these constants (one string
        // set; 64 is a valid control packet size).
        let device = UsbDeviceBuilder::new(alloc, UsbVidPid(board::USB_VID, board::USB_PID))
            .composite_with_iads()
            .strings(&[strings])
            .unwrap()
            .max_packet_size_0(MAX_PACKET as u8)
            .unwrap()
            .max_power(100)
            .unwrap()
            .build();
        // `build` switched the pull-up on (`UsbBus::enable`): off until VBUS.
        set_pullup(false);
        Self {
            vbus,
            device,
            port,
            pulled_up: false,
            reader: RequestReader::new(),
            answer: Answer::None,
            zlp_due: false,
            bootsel_due: false,
            #[cfg(feature = "hil-faults")]
            faults: Default::default(),
        }
    }

    /// VBUS present (a USB cable powers the board); the pull-up follows.
    pub fn connected(&mut self) -> bool {
        use embedded_hal::digital::InputPin;
        let vbus = self.vbus.is_high().unwrap_or(true);
        if vbus != self.pulled_up {
            set_pullup(vbus);
            self.pulled_up = vbus;
            if !vbus {
                self.answer = Answer::None;
                self.zlp_due = false;
                self.bootsel_due = false;
            }
        }
        if !vbus {
            release_ir_pin();
        }
        vbus
    }

    /// The host has suspended the bus (or never resumed it).
    pub fn suspended(&self) -> bool {
        self.device.state() == UsbDeviceState::Suspend
    }

    /// Serve the port: take requests, send what is due. `robot`'s foreign
    /// count and pairing go into the image's header.
    // Not inlined into the main loop: that alone saves about 1 kB of flash.
    #[inline(never)]
    pub fn serve(&mut self, store: &LogStore, flash: &LogRegion, robot: &Robot) {
        let (foreign, paired) = (robot.foreign, robot.paired);
        let mut feed = || flash.feed();
        self.device.poll(&mut [&mut self.port]);
        if self.device.state() != UsbDeviceState::Configured {
            // A reset or an unplugged cable ends what was being sent.
            self.answer = Answer::None;
            self.zlp_due = false;
        }
        let mut buf = [0u8; MAX_PACKET as usize];
        while let Ok(n) = self.port.read_packet(&mut buf) {
            if n == 0 {
                break;
            }
            for &b in &buf[..n] {
                #[cfg(feature = "hil-faults")]
                let mut fault_text = [0u8; crate::hil_faults::ANSWER_MAX];
                #[cfg(feature = "hil-faults")]
                let fault_len = self.faults.push(b, now_us(), &mut fault_text);
                let Some(request) = self.reader.push(b) else {
                    continue;
                };
                // A new request replaces an answer still being sent.
                self.answer = match request {
                    Request::Log => Answer::Image {
                        image: store.readout(flash, foreign, paired, &mut feed),
                        pos: 0,
                    },
                    Request::Info => {
                        let image = store.readout(flash, foreign, paired, &mut feed);
                        Answer::Text {
                            line: info_line(&image.header_fields(), Some(robot.status)),
                            pos: 0,
                        }
                    }
                    Request::Bootsel => {
                        // Decided now; the reboot itself waits for the answer.
                        self.bootsel_due = robot.bootsel_allowed;
                        let answer = if robot.bootsel_allowed {
                            BOOTSEL_ANSWER
                        } else {
                            BOOTSEL_REFUSED
                        };
                        Answer::Text {
                            line: Line::from_bytes(answer),
                            pos: 0,
                        }
                    }
                    Request::Unknown => Answer::Text {
                        line: Line::from_bytes(UNKNOWN_ANSWER),
                        pos: 0,
                    },
                };
                #[cfg(feature = "hil-faults")]
                if let Some(len) = fault_len {
                    self.answer = Answer::Text {
                        line: Line::from_bytes(&fault_text[..len]),
                        pos: 0,
                    };
                }
            }
        }
        self.send(flash);
        #[cfg(feature = "hil-faults")]
        self.faults.poll(now_us());
        if self.bootsel_due && matches!(self.answer, Answer::None) && !self.zlp_due {
            self.reboot_to_bootsel();
        }
        // SAFETY: the handler only masks this interrupt again.
        unsafe { pac::NVIC::unmask(pac::Interrupt::USBCTRL_IRQ) };
    }

    /// The answer is queued: give the host a few frames to take it, then
    /// the ROM's `reset_to_usb_boot` (RP2040 datasheet 2.8.5.3.3): the
    /// chip comes back as the RPI-RP2 drive and PICOBOOT. The gate is low
    /// (the request's condition) and stays so: the ROM leaves GPIO16 to its
    /// reset state, an input, and the board's gate pull-down holds it.
    fn reboot_to_bootsel(&mut self) -> ! {
        defmt::warn!("BOOTSEL requested over USB: rebooting into the ROM's bootloader");
        // SAFETY: reads of the free-running timer.
        let timer = unsafe { &*pac::TIMER::ptr() };
        let start = timer.timerawl().read().bits();
        // 20 ms of polls (the watchdog allows 80 ms).
        while timer.timerawl().read().bits().wrapping_sub(start) < 20_000 {
            self.device.poll(&mut [&mut self.port]);
        }
        rp2040_hal::rom_data::reset_to_usb_boot(0, 0)
    }

    /// Queue one packet on the bulk IN endpoint; false if the host has not
    /// taken the last one yet.
    fn write(&mut self, data: &[u8]) -> bool {
        !matches!(self.port.write_packet(data), Err(UsbError::WouldBlock))
    }

    /// One packet per call when the IN endpoint is free (the host takes
    /// one per 1 ms frame or faster; the USB interrupt wakes the next pass).
    fn send(&mut self, flash: &impl LogFlash) {
        let mut chunk = [0u8; MAX_PACKET as usize];
        let n = match &self.answer {
            Answer::None if self.zlp_due => {
                if self.write(&[]) {
                    self.zlp_due = false;
                }
                return;
            }
            Answer::None => return,
            Answer::Image { image, pos } => image.read(flash, *pos, &mut chunk),
            Answer::Text { line, pos } => {
                let rest = &line[(*pos).min(line.len())..];
                let n = rest.len().min(chunk.len());
                chunk[..n].copy_from_slice(&rest[..n]);
                n
            }
        };
        if n == 0 {
            self.answer = Answer::None;
            return;
        }
        if !self.write(&chunk[..n]) {
            return; // the host has not taken the last packet yet
        }
        self.zlp_due = n == chunk.len();
        match &mut self.answer {
            Answer::Image { pos, .. } | Answer::Text { pos, .. } => *pos += n,
            Answer::None => {}
        }
    }
}

/// The 1 MHz timer's low word (the `hil-faults` schedule).
#[cfg(feature = "hil-faults")]
fn now_us() -> u32 {
    // SAFETY: a read of the free-running timer.
    unsafe { &*pac::TIMER::ptr() }.timerawl().read().bits()
}

/// The D+ pull-up (SIE_CTRL.PULLUP_EN, RP2040 datasheet 4.1.4): the
/// device's presence on the bus. `UsbBus` switches it on once, in
/// `enable`; it is left to VBUS here.
fn set_pullup(on: bool) {
    // SAFETY: one bit of SIE_CTRL, changed in a critical section so that
    // it cannot interleave with `UsbBus`'s own read-modify-writes, which
    // run in critical sections too.
    critical_section::with(|_| {
        let regs = unsafe { &*pac::USBCTRL_REGS::ptr() };
        regs.sie_ctrl().modify(|_, w| w.pullup_en().bit(on));
    });
}

/// GPIO15 back to the IR receiver if the E5 workaround holds it. The
/// workaround (rp2040-hal `usb::errata5`) switches the pad to function 8
/// (USB muxing) at the end of a bus reset and gives it back only once the
/// controller reports `connected`; a cable pulled in that millisecond
/// leaves it there, the receiver cut off from SIO, and the remote dead
/// until a reset. Without VBUS nothing needs the pad: it is given back to
/// SIO (function 5) as a pulled-up input, as `ir::start` made it, and the
/// controller's muxing back to its PHY. Each pass without VBUS checks it:
/// one register read when nothing is wrong. When the host comes back, the
/// workaround's own restore writes the same SIO settings it saved.
fn release_ir_pin() {
    const FUNC_USB_MUXING: u8 = 8;
    // SAFETY: GPIO15's control and pad registers, and USB_MUXING, are only
    // written by `ir::start` at boot and by the E5 workaround, which runs
    // from `UsbDevice::poll`, never between passes without VBUS.
    let io = unsafe { &*pac::IO_BANK0::ptr() };
    let ctrl = io.gpio(usize::from(board::IR_GPIO)).gpio_ctrl();
    if ctrl.read().funcsel().bits() != FUNC_USB_MUXING {
        return;
    }
    let pads = unsafe { &*pac::PADS_BANK0::ptr() };
    let regs = unsafe { &*pac::USBCTRL_REGS::ptr() };
    critical_section::with(|_| {
        regs.usb_muxing()
            .write(|w| w.to_phy().set_bit().softcon().set_bit());
        // SAFETY: funcsel 5 is SIO; no overrides.
        ctrl.write(|w| unsafe { w.funcsel().bits(5) });
        pads.gpio(usize::from(board::IR_GPIO)).write(|w| {
            w.ie()
                .set_bit()
                .pue()
                .set_bit()
                .pde()
                .clear_bit()
                .schmitt()
                .set_bit()
        });
    });
    defmt::warn!("usb: GPIO15 recovered from an interrupted E5 workaround");
}

#[interrupt]
fn USBCTRL_IRQ() {
    // Wake the core only: the main loop polls the device.
    pac::NVIC::mask(pac::Interrupt::USBCTRL_IRQ);
}
