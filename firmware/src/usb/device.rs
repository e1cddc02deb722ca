//! The RP2040's USB controller as the one CDC-ACM device of the readout,
//! on its registers (RP2040 datasheet, 4.1): endpoint 0 answers control
//! requests as `swimbot_shared::usb_cdc::control` decides, with the
//! descriptors of `swimbot_shared::usb_cdc::descriptors`; bulk OUT 1
//! brings the host's bytes, bulk IN 2 takes ours, a packet at a time.
//!
//! Hand-written instead of usb-device + usbd-serial + rp2040-hal's
//! `UsbBus` only for the flash budget (issue 26: 32 KiB). Measured with
//! `cargo fw && cargo xtask size`: that stack made the image 37 136 B, over
//! the budget, and serving the port cost 10.7 kB of it (usb-device and
//! usbd-serial 4 972 B of symbols, the HAL's `UsbBus` 808 B); with this
//! module the image is 28 988 B and serving the port, the log's readout
//! included, 4.9 kB (firmware/README.md, "Flash and RAM").
//!
//! Single-buffered endpoints with the buffers at fixed DPRAM offsets; data
//! toggles kept here (DATA1 for every control stage after SETUP, DATA0 for
//! the bulk endpoints after SET_CONFIGURATION, a bus reset or a cleared
//! halt). The controller raises its interrupt for a SETUP, a bus reset and
//! each finished buffer; `poll` serves all three and clears them, so the
//! interrupt never stays pending.
//!
//! References: RP2040 datasheet 4.1.2 (DPRAM layout, buffer control,
//! "AVAILABLE" set 3 USB clocks after the rest of the register); USB 2.0
//! specification 8.5.3 (control transfers) and 8.6 (data toggles);
//! pico-examples `usb/device/dev_lowlevel` (the same controller driven the
//! same way in C).

use rp2040_hal::pac::{RESETS, USBCTRL_DPRAM, USBCTRL_REGS};
use swimbot_shared::usb_cdc::control::{
    data_stage, decide, Action, Reply, Setup, DEFAULT_LINE_CODING,
};
use swimbot_shared::usb_cdc::descriptors::MAX_PACKET;

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

/// Where endpoint 0 is in a control transfer.
#[derive(Clone, Copy)]
enum Ep0 {
    Idle,
    /// IN data stage: `rest` still to go, then a zero-length packet if
    /// `zlp`, then the host's status.
    Sending {
        rest: &'static [u8],
        zlp: bool,
    },
    /// A zero-length IN status is out; then take this address, if any.
    Status {
        address: Option<u8>,
    },
    /// Waiting for SET_LINE_CODING's 7 bytes.
    LineCoding,
}

pub struct CdcDevice {
    regs: USBCTRL_REGS,
    dpram: USBCTRL_DPRAM,
    ep0: Ep0,
    ep0_data1: bool,
    out_data1: bool,
    in_data1: bool,
    configured: bool,
    line_coding: [u8; 7],
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
            regs,
            dpram,
            ep0: Ep0::Idle,
            ep0_data1: true,
            out_data1: false,
            in_data1: false,
            configured: false,
            line_coding: DEFAULT_LINE_CODING,
        }
    }

    /// Serve what the controller reports: finished buffers on endpoint 0
    /// first (they belong to the transfer a new SETUP would replace), then
    /// a SETUP, then a bus reset.
    pub fn poll(&mut self) {
        let ints = self.regs.ints().read();
        if ints.buff_status().bit_is_set() {
            let done = self.regs.buff_status().read().bits();
            // SAFETY: write-1-to-clear of the bits just read.
            self.regs.buff_status().write(|w| unsafe { w.bits(done) });
            if done & EP0_IN_DONE != 0 {
                self.ep0_in_done();
            }
            if done & EP0_OUT_DONE != 0 {
                self.ep0_out_done();
            }
        }
        if ints.setup_req().bit_is_set() {
            self.regs
                .sie_status()
                .write(|w| w.setup_rec().clear_bit_by_one());
            self.setup();
        }
        if ints.bus_reset().bit_is_set() {
            self.regs
                .sie_status()
                .write(|w| w.bus_reset().clear_bit_by_one());
            self.regs.addr_endp().write(|w| unsafe { w.bits(0) });
            self.configure(false);
            self.ep0 = Ep0::Idle;
        }
    }

    /// One packet from the host into `buf`, if one has come (0 otherwise).
    pub fn read(&mut self, buf: &mut [u8; MAX_PACKET]) -> usize {
        let control = self.buffer_control(DATA_OUT);
        if !self.configured || control & (FULL | AVAILABLE) != FULL {
            return 0;
        }
        let n = ((control & LEN_MASK) as usize).min(MAX_PACKET);
        copy_from_dpram(OUT_BUF, &mut buf[..n]);
        self.arm_out();
        n
    }

    /// Send `data` (at most 64 bytes; empty = a zero-length packet) if the
    /// IN endpoint is free; false while the host has not taken the last one.
    pub fn write(&mut self, data: &[u8]) -> bool {
        if !self.configured || self.buffer_control(DATA_IN) & AVAILABLE != 0 {
            return false;
        }
        let len = copy_to_dpram(IN_BUF, data);
        let pid = toggle(&mut self.in_data1);
        self.start(DATA_IN, len | FULL | pid);
        true
    }

    fn setup(&mut self) {
        let low = self.dpram.setup_packet_low().read().bits().to_le_bytes();
        let high = self.dpram.setup_packet_high().read().bits().to_le_bytes();
        let setup = Setup::parse([
            low[0], low[1], low[2], low[3], high[0], high[1], high[2], high[3],
        ]);
        // Every stage after SETUP starts on DATA1; a STALL left from the
        // last request goes (the controller disarmed it for this SETUP).
        self.ep0_data1 = true;
        self.set_buffer_control(EP0_OUT, 0);
        self.ep0 = Ep0::Idle;
        let data: &'static [u8] = match decide(&setup, self.configured) {
            Action::Send(Reply::Static(data)) => data,
            Action::Send(Reply::LineCoding) => {
                let (len, _) = data_stage(self.line_coding.len(), setup.length);
                let coding = self.line_coding;
                self.send_ep0(&coding[..len]);
                self.ep0 = Ep0::Sending {
                    rest: &[],
                    zlp: false,
                };
                return;
            }
            Action::SetAddress(address) => return self.status_in(Some(address)),
            Action::SetConfiguration(on) => {
                self.configure(on);
                return self.status_in(None);
            }
            Action::ClearHalt(endpoint) => {
                self.clear_halt(endpoint);
                return self.status_in(None);
            }
            Action::Ack => return self.status_in(None),
            Action::ReceiveLineCoding => {
                self.ep0 = Ep0::LineCoding;
                return self.start(EP0_OUT, MAX_PACKET as u32 | DATA1);
            }
            Action::Stall => return self.stall_ep0(),
        };
        // The first packet goes even if empty (a request for 0 bytes gets
        // its zero-length packet).
        let (len, zlp) = data_stage(data.len(), setup.length);
        self.send_chunk(&data[..len], zlp);
    }

    /// Send up to a packet of `rest`; the remainder (and a zero-length
    /// packet if `zlp`) after the host takes it.
    fn send_chunk(&mut self, rest: &'static [u8], zlp: bool) {
        let (now, later) = rest.split_at(rest.len().min(MAX_PACKET));
        self.send_ep0(now);
        self.ep0 = Ep0::Sending { rest: later, zlp };
    }

    /// The last IN packet on endpoint 0 was taken: the next one, the
    /// status OUT, or the address.
    fn ep0_in_done(&mut self) {
        match self.ep0 {
            Ep0::Sending { rest, zlp } if !rest.is_empty() => self.send_chunk(rest, zlp),
            Ep0::Sending { zlp: true, .. } => self.send_chunk(&[], false),
            Ep0::Sending { .. } => {
                // The host's zero-length status (DATA1).
                self.start(EP0_OUT, DATA1);
                self.ep0 = Ep0::Idle;
            }
            Ep0::Status {
                address: Some(address),
            } => {
                // SAFETY: a 7-bit address from the decoder.
                self.regs
                    .addr_endp()
                    .write(|w| unsafe { w.address().bits(address) });
                self.ep0 = Ep0::Idle;
            }
            _ => self.ep0 = Ep0::Idle,
        }
    }

    /// An OUT packet on endpoint 0: SET_LINE_CODING's data (then the
    /// status), or the status of an IN transfer (nothing to do).
    fn ep0_out_done(&mut self) {
        if let Ep0::LineCoding = self.ep0 {
            let len = (self.buffer_control(EP0_OUT) & LEN_MASK) as usize;
            let n = len.min(self.line_coding.len());
            copy_from_dpram(EP0_BUF, &mut self.line_coding[..n]);
            self.status_in(None);
        }
    }

    fn status_in(&mut self, address: Option<u8>) {
        self.send_ep0(&[]);
        self.ep0 = Ep0::Status { address };
    }

    fn send_ep0(&mut self, data: &[u8]) {
        let len = copy_to_dpram(EP0_BUF, data);
        let pid = toggle(&mut self.ep0_data1);
        self.start(EP0_IN, len | FULL | pid);
    }

    /// Both directions of endpoint 0 answer STALL until the next SETUP
    /// (the controller clears EP_STALL_ARM when one comes).
    fn stall_ep0(&mut self) {
        self.regs
            .ep_stall_arm()
            .write(|w| w.ep0_in().set_bit().ep0_out().set_bit());
        self.set_buffer_control(EP0_IN, STALL);
        self.set_buffer_control(EP0_OUT, STALL);
    }

    /// Configured: the bulk endpoints from DATA0, OUT armed. Not
    /// configured (SET_CONFIGURATION 0, bus reset): both idle.
    fn configure(&mut self, on: bool) {
        self.configured = on;
        self.in_data1 = false;
        self.out_data1 = false;
        self.set_buffer_control(DATA_IN, 0);
        self.set_buffer_control(DATA_OUT, 0);
        if on {
            self.arm_out();
        }
    }

    fn clear_halt(&mut self, endpoint: u8) {
        if endpoint & 0x80 != 0 {
            self.in_data1 = false;
        } else if self.configured {
            self.out_data1 = false;
            self.arm_out();
        }
    }

    fn arm_out(&mut self) {
        let pid = toggle(&mut self.out_data1);
        self.start(DATA_OUT, MAX_PACKET as u32 | pid);
    }

    /// Hand a buffer to the controller: the control word first, AVAILABLE
    /// only after 3 USB clocks (datasheet 4.1.2.5.1; 12 system clocks as
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
