//! The RP2040's USB controller as the one CDC-ACM device of the readout,
//! on its registers (RP2040 datasheet, 4.1): endpoint 0 hands the
//! controller the packets `swimbot_shared::usb_cdc::pipe::ControlPipe`
//! decides (host-tested: requests, descriptors, data toggles, packet
//! split); bulk OUT 1 brings the host's bytes, bulk IN 2 takes ours, a
//! packet at a time.
//!
//! Hand-written instead of usb-device + usbd-serial + rp2040-hal's
//! `UsbBus` only for the flash budget (issue 26: 32 KiB). Measured with
//! `cargo fw && cargo xtask size`: that stack made the image 37 136 B, over
//! the budget, and serving the port cost 10.7 kB of it (usb-device and
//! usbd-serial 4 972 B of symbols, the HAL's `UsbBus` 808 B); with this
//! module the image is 28 940 B and serving the port, the log's readout
//! included, 4 888 B (firmware/README.md, "Flash and RAM").
//!
//! Single-buffered endpoints with the buffers at fixed DPRAM offsets; the
//! bulk endpoints' data toggles kept here (DATA0 after SET_CONFIGURATION or
//! a cleared halt). The controller raises its interrupt for a SETUP, a bus
//! reset and each finished buffer; `poll` serves all three and clears them,
//! so the interrupt never stays pending.
//!
//! References: RP2040 datasheet 4.1.2 (DPRAM layout, buffer control,
//! "AVAILABLE" set 3 USB clocks after the rest of the register); USB 2.0
//! specification 8.5.3 (control transfers) and 8.6 (data toggles);
//! pico-examples `usb/device/dev_lowlevel` (the same controller driven the
//! same way in C).

use rp2040_hal::pac::{RESETS, USBCTRL_DPRAM, USBCTRL_REGS};
use swimbot_shared::usb_cdc::descriptors::MAX_PACKET;
use swimbot_shared::usb_cdc::pipe::{ControlPipe, Effect, Packet, Step};

/// DPRAM's bus address: SETUP packet at 0, control words to 0x100, data.
const DPRAM: usize = 0x5010_0000;
/// Endpoint 0's one buffer (both directions: single-buffered).
const EP0_BUF: u16 = 0x100;
const NOTIFY_BUF: u16 = 0x180;
const OUT_BUF: u16 = 0x1c0;
const IN_BUF: u16 = 0x200;

/// Buffer control words (`ep_buffer_control` index: 2 x endpoint + OUT).
const EP0_IN: usize = 0;
const EP0_OUT: usize = 1;
const DATA_OUT: usize = 3;
const DATA_IN: usize = 4;
/// Buffer control bits (buffer 0).
const FULL: u32 = 1 << 15;
const DATA1: u32 = 1 << 13;
const STALL: u32 = 1 << 11;
const AVAILABLE: u32 = 1 << 10;
const LEN_MASK: u32 = 0x3ff;

/// Endpoint control: enabled, an interrupt per buffer, type, buffer offset.
const EP_ENABLE: u32 = 1 << 31;
const EP_IRQ_PER_BUFFER: u32 = 1 << 29;
const EP_BULK: u32 = 2 << 26;
const EP_INTERRUPT: u32 = 3 << 26;

/// BUFF_STATUS bits of endpoint 0.
const EP0_IN_DONE: u32 = 1 << 0;
const EP0_OUT_DONE: u32 = 1 << 1;

pub struct CdcDevice {
    hw: Controller,
    pipe: ControlPipe,
}

/// The registers, and the bulk endpoints' next data PIDs.
struct Controller {
    regs: USBCTRL_REGS,
    dpram: USBCTRL_DPRAM,
    out_data1: bool,
    in_data1: bool,
}

impl CdcDevice {
    /// Reset the controller and connect to the bus as a full-speed device
    /// (pull-up on D+). VBUS is forced present: the board senses it on a
    /// GPIO (`usb.rs`) and serves the port only while it is there.
    pub fn new(regs: USBCTRL_REGS, dpram: USBCTRL_DPRAM, resets: &mut RESETS) -> Self {
        resets.reset().modify(|_, w| w.usbctrl().set_bit());
        resets.reset().modify(|_, w| w.usbctrl().clear_bit());
        while resets.reset_done().read().usbctrl().bit_is_clear() {}
        // DPRAM is RAM, not reset with the controller: clear the control words.
        for i in 0..64 {
            // SAFETY: the first 256 bytes of the controller's own DPRAM.
            unsafe { ((DPRAM + 4 * i) as *mut u32).write_volatile(0) };
        }
        regs.usb_muxing()
            .write(|w| w.to_phy().set_bit().softcon().set_bit());
        regs.usb_pwr().write(|w| {
            w.vbus_detect()
                .set_bit()
                .vbus_detect_override_en()
                .set_bit()
        });
        regs.main_ctrl().write(|w| w.controller_en().set_bit());
        regs.sie_ctrl().write(|w| w.ep0_int_1buf().set_bit());
        regs.inte().write(|w| {
            w.buff_status().set_bit();
            w.bus_reset().set_bit();
            w.setup_req().set_bit()
        });
        let endpoints = [
            EP_INTERRUPT | u32::from(NOTIFY_BUF),
            EP_IRQ_PER_BUFFER | EP_BULK | u32::from(OUT_BUF),
            EP_IRQ_PER_BUFFER | EP_BULK | u32::from(IN_BUF),
        ];
        for (i, control) in endpoints.into_iter().enumerate() {
            // SAFETY: EP1 IN, EP1 OUT, EP2 IN with their own 64-byte buffers.
            dpram
                .ep_control(i)
                .write(|w| unsafe { w.bits(EP_ENABLE | control) });
        }
        regs.sie_ctrl().modify(|_, w| w.pullup_en().set_bit());
        Self {
            hw: Controller {
                regs,
                dpram,
                out_data1: false,
                in_data1: false,
            },
            pipe: ControlPipe::new(),
        }
    }

    /// Serve what the controller reports in the order it can happen: a bus
    /// reset (it ends everything before it), finished buffers (they belong
    /// to the transfer a new SETUP would replace), a SETUP.
    pub fn poll(&mut self) {
        let hw = &mut self.hw;
        let ints = hw.regs.ints().read();
        if ints.bus_reset().bit_is_set() {
            hw.regs
                .sie_status()
                .write(|w| w.bus_reset().clear_bit_by_one());
            // SAFETY: write-1-to-clear of every buffer's status.
            hw.regs.buff_status().write(|w| unsafe { w.bits(!0) });
            // SAFETY: address 0, the default after a reset.
            hw.regs.addr_endp().write(|w| unsafe { w.bits(0) });
            hw.configure(false);
            self.pipe.reset();
        }
        if ints.buff_status().bit_is_set() {
            let done = hw.regs.buff_status().read().bits();
            // SAFETY: write-1-to-clear of the bits just read.
            hw.regs.buff_status().write(|w| unsafe { w.bits(done) });
            if done & EP0_IN_DONE != 0 {
                hw.apply(self.pipe.in_done());
            }
            if done & EP0_OUT_DONE != 0 {
                let mut data = [0u8; 7];
                let n = hw.received(EP0_OUT, EP0_BUF, &mut data);
                hw.apply(self.pipe.out_done(&data[..n]));
            }
        }
        if ints.setup_req().bit_is_set() {
            hw.regs
                .sie_status()
                .write(|w| w.setup_rec().clear_bit_by_one());
            let low = hw.dpram.setup_packet_low().read().bits().to_le_bytes();
            let high = hw.dpram.setup_packet_high().read().bits().to_le_bytes();
            let [a, b, c, d] = low;
            let [e, f, g, h] = high;
            // A STALL left from the last request goes (the controller
            // disarmed it for this SETUP).
            hw.set_buffer_control(EP0_OUT, 0);
            hw.apply(self.pipe.setup([a, b, c, d, e, f, g, h]));
        }
    }

    /// One packet from the host into `buf`, if one has come (0 otherwise).
    pub fn read(&mut self, buf: &mut [u8; MAX_PACKET]) -> usize {
        let control = self.hw.buffer_control(DATA_OUT);
        if !self.pipe.configured() || control & (FULL | AVAILABLE) != FULL {
            return 0;
        }
        let n = self.hw.received(DATA_OUT, OUT_BUF, buf);
        self.hw.arm_out();
        n
    }

    /// Send `data` (at most 64 bytes; empty = a zero-length packet) if the
    /// IN endpoint is free; false while the host has not taken the last one.
    pub fn write(&mut self, data: &[u8]) -> bool {
        let hw = &mut self.hw;
        if !self.pipe.configured() || hw.buffer_control(DATA_IN) & AVAILABLE != 0 {
            return false;
        }
        let len = copy_to_dpram(IN_BUF, data);
        let pid = toggle(&mut hw.in_data1);
        hw.start(DATA_IN, len | FULL | pid);
        true
    }
}

impl Controller {
    /// Carry out the control pipe's step.
    fn apply(&mut self, step: Step) {
        match step.packet {
            Packet::None => {}
            Packet::In { data, data1 } => {
                let len = copy_to_dpram(EP0_BUF, data);
                self.start(EP0_IN, len | FULL | if data1 { DATA1 } else { 0 });
            }
            Packet::Out => self.start(EP0_OUT, MAX_PACKET as u32 | DATA1),
            Packet::Stall => {
                // Both directions answer STALL until the next SETUP (the
                // controller clears EP_STALL_ARM when one comes).
                self.regs
                    .ep_stall_arm()
                    .write(|w| w.ep0_in().set_bit().ep0_out().set_bit());
                self.set_buffer_control(EP0_IN, STALL);
                self.set_buffer_control(EP0_OUT, STALL);
            }
        }
        match step.effect {
            Effect::None => {}
            // SAFETY: a 7-bit address from the decoder.
            Effect::Address(address) => self
                .regs
                .addr_endp()
                .write(|w| unsafe { w.address().bits(address) }),
            Effect::Configured(on) => self.configure(on),
            Effect::ClearHalt(endpoint) if endpoint & 0x80 != 0 => self.in_data1 = false,
            Effect::ClearHalt(_) => {
                self.out_data1 = false;
                self.arm_out();
            }
        }
    }

    /// Configured: the bulk endpoints from DATA0, OUT armed. Not
    /// configured (SET_CONFIGURATION 0, bus reset): both idle.
    fn configure(&mut self, on: bool) {
        self.in_data1 = false;
        self.out_data1 = false;
        self.set_buffer_control(DATA_IN, 0);
        self.set_buffer_control(DATA_OUT, 0);
        if on {
            self.arm_out();
        }
    }

    fn arm_out(&mut self) {
        let pid = toggle(&mut self.out_data1);
        self.start(DATA_OUT, MAX_PACKET as u32 | pid);
    }

    /// The bytes of the OUT buffer `index` at `offset`, at most `out.len()`.
    fn received(&self, index: usize, offset: u16, out: &mut [u8]) -> usize {
        let len = (self.buffer_control(index) & LEN_MASK) as usize;
        let n = len.min(out.len());
        copy_from_dpram(offset, &mut out[..n]);
        n
    }

    /// Hand a buffer to the controller: the control word first, AVAILABLE
    /// only after 3 USB clocks (datasheet 4.1.2.5, buffer control; 12 system clocks as
    /// rp2040-hal waits).
    fn start(&mut self, index: usize, control: u32) {
        self.set_buffer_control(index, control);
        cortex_m::asm::delay(12);
        self.set_buffer_control(index, control | AVAILABLE);
    }

    fn buffer_control(&self, index: usize) -> u32 {
        self.dpram.ep_buffer_control(index).read().bits()
    }

    fn set_buffer_control(&mut self, index: usize, control: u32) {
        // SAFETY: a whole buffer control word of one of our endpoints.
        self.dpram
            .ep_buffer_control(index)
            .write(|w| unsafe { w.bits(control) });
    }
}

/// The data PID for the next packet (as a buffer control bit), flipped.
fn toggle(data1: &mut bool) -> u32 {
    let pid = if *data1 { DATA1 } else { 0 };
    *data1 = !*data1;
    pid
}

/// Copy `data` (at most one packet) into the DPRAM buffer at `offset`;
/// its length as a buffer control field.
fn copy_to_dpram(offset: u16, data: &[u8]) -> u32 {
    let data = &data[..data.len().min(MAX_PACKET)];
    for (i, &b) in data.iter().enumerate() {
        // SAFETY: inside the endpoint's own 64-byte buffer in DPRAM.
        unsafe { ((DPRAM + usize::from(offset) + i) as *mut u8).write_volatile(b) };
    }
    data.len() as u32
}

fn copy_from_dpram(offset: u16, out: &mut [u8]) {
    for (i, b) in out.iter_mut().enumerate() {
        // SAFETY: inside the endpoint's own 64-byte buffer in DPRAM.
        *b = unsafe { ((DPRAM + usize::from(offset) + i) as *const u8).read_volatile() };
    }
}
