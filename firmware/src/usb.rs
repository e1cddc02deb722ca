//! The run log's readout over USB: a CDC-ACM serial port ([`device`], on
//! the USB controller's registers) that answers the requests of
//! `swimbot_shared::run_log` (`LOG`: the log image; `INFO`: one line).
//!
//! VBUS is sensed on GPIO24 (the Pico's divider from the USB connector).
//! While it is present the main loop tells the pass, which holds the motor
//! off and refuses On, forbids flash erases (the host would time out) and
//! DORMANT; the USB clock is kept running in sleep, and the USB interrupt
//! wakes the core (its handler only masks itself; the main loop polls the
//! device and unmasks it), so each pass serves the port. An image is
//! streamed from flash in 64-byte packets as the host takes them.

use crate::board;
use crate::flash::LogRegion;
use rp2040_hal::gpio::{bank0::Gpio24, FunctionSioInput, Pin, PullNone};
use rp2040_hal::pac::{self, interrupt, RESETS, USBCTRL_DPRAM, USBCTRL_REGS};
use swimbot_shared::run_log::readout::{info_line, Line, UNKNOWN_ANSWER};
use swimbot_shared::run_log::store::{LogFlash, LogStore, ReadoutImage};
use swimbot_shared::run_log::{Request, RequestReader};

mod device;

use device::CdcDevice;

const _: () = assert!(board::VBUS_SENSE_GPIO == 24, "the typed pin is GPIO24");

pub type VbusPin = Pin<Gpio24, FunctionSioInput, PullNone>;

/// What is being sent.
enum Answer {
    None,
    Image { image: ReadoutImage, pos: usize },
    Text { line: Line, pos: usize },
}

pub struct Usb {
    vbus: VbusPin,
    device: CdcDevice,
    /// The last packet sent was a full one: end the answer with a
    /// zero-length packet.
    zlp_due: bool,
    reader: RequestReader,
    answer: Answer,
}

impl Usb {
    /// The controller reset and on the bus (pulled up); served from the
    /// first pass with VBUS present.
    pub fn new(
        regs: USBCTRL_REGS,
        dpram: USBCTRL_DPRAM,
        resets: &mut RESETS,
        vbus: VbusPin,
    ) -> Self {
        Self {
            vbus,
            device: CdcDevice::new(regs, dpram, resets),
            reader: RequestReader::new(),
            answer: Answer::None,
            zlp_due: false,
        }
    }

    /// VBUS present (a USB cable powers the board).
    pub fn connected(&mut self) -> bool {
        use embedded_hal::digital::InputPin;
        self.vbus.is_high().unwrap_or(true)
    }

    /// Serve the port: take requests, send what is due. `foreign` and
    /// `paired` go into the image's header.
    // Not inlined into the main loop: that alone saves about 1 kB of flash.
    #[inline(never)]
    pub fn serve(&mut self, store: &LogStore, flash: &LogRegion, foreign: u32, paired: Option<u8>) {
        let mut feed = || flash.feed();
        self.device.poll();
        let mut buf = [0u8; 64];
        loop {
            let n = self.device.read(&mut buf);
            if n == 0 {
                break;
            }
            for &b in &buf[..n] {
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
                            line: info_line(&image.header_fields()),
                            pos: 0,
                        }
                    }
                    Request::Unknown => Answer::Text {
                        line: Line::from_bytes(UNKNOWN_ANSWER),
                        pos: 0,
                    },
                };
            }
        }
        self.send(flash);
        // SAFETY: the handler only masks this interrupt again.
        unsafe { pac::NVIC::unmask(pac::Interrupt::USBCTRL_IRQ) };
    }

    /// One packet per call when the IN endpoint is free (the host takes
    /// one per 1 ms frame or faster; the USB interrupt wakes the next pass).
    fn send(&mut self, flash: &impl LogFlash) {
        let mut chunk = [0u8; 64];
        {
            let n = match &self.answer {
                Answer::None if self.zlp_due => {
                    if self.device.write(&[]) {
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
            if !self.device.write(&chunk[..n]) {
                return; // the host has not taken the last packet yet
            }
            self.zlp_due = n == chunk.len();
            match &mut self.answer {
                Answer::Image { pos, .. } | Answer::Text { pos, .. } => *pos += n,
                Answer::None => {}
            }
        }
    }
}

#[interrupt]
fn USBCTRL_IRQ() {
    // Wake the core only: the main loop polls the device.
    pac::NVIC::mask(pac::Interrupt::USBCTRL_IRQ);
}
