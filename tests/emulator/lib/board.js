// The swimbot board around an emulated RP2040 (rp2040js): loads the firmware
// ELF into flash, boots it (through the real B1 bootrom and boot2 by default),
// drives the IR receiver pin, feeds the battery ADC input from a cell model
// loaded by the motor pin the firmware drives, records the motor pin with
// simulation timestamps, models the watchdog reset, and counts the CPU
// cycles spent in the GPIO (IO_IRQ_BANK0) interrupt. The motor turns the
// tail and the Hall latches (lib/rotor.js, the host's motor model as
// WebAssembly): every millisecond the mean motor voltage (duty x the
// loaded cell) steps the motor against its tail's load, and the latches'
// edges are scheduled at their crossing times, so the rate loop is closed
// through the chip's own PWM, interrupt and controller.
//
// Board facts (pins, divider, reference, timings) come from the image
// itself (lib/facts.js: the firmware's SWIMBOT_BOARD, from shared/src/board.rs).
import { readFileSync } from 'node:fs';
import { BasePeripheral, GPIOPinState, RP2040, USBCDC } from 'rp2040js';
import { FlashChip } from './flash.js';
import { Cell } from './cell.js';
import { Rotor } from './rotor.js';
import { loadFlash, objectBytes, readElf, symbolize } from './elf.js';
import { boardFacts } from './facts.js';

const IO_IRQ_BANK0 = 13;
const EXC_IO_IRQ_BANK0 = 16 + IO_IRQ_BANK0;
const WATCHDOG_BASE = 0x40058000;
const CLOCKS_BASE = 0x40008000;
const TIMER_BASE = 0x40054000;
const IO_BANK0_BASE = 0x40014000;
const XOSC_BASE = 0x40024000;
const SLEEP_EN0 = 0xa8; // CLOCKS
const SLEEP_EN1 = 0xac;
const DORMANT_WAKE_INTE0 = 0x160; // IO_BANK0, four registers
const INTR0 = 0xf0; // IO_BANK0 raw interrupts, four registers
const PROC0_INTS0 = 0x120;
const SCR = 0xd10; // PPB: SLEEPDEEP is bit 2
const DORMANT_MAGIC = 0x636f6d61; // XOSC DORMANT: 'coma'
const FLASH_BASE = 0x10000000;
const VREG_AND_CHIP_RESET_BASE = 0x40064000;

export const MS = 1e6; // nanoseconds
/** The one interrupt the firmware leaves live while the flash is busy (its handler and vector in RAM). */
export const IRQ_LIVE_IN_FLASH_OPS = 1 << IO_IRQ_BANK0;
export const US = 1e3;
const ROTOR_STEP_NS = 1e6;

/** ADC code (12 bit) for a battery voltage through the board's divider and reference. */
export function adcCodeForBattery(facts, volts) {
  const ratio = facts.dividerBottomOhm / (facts.dividerTopOhm + facts.dividerBottomOhm);
  return Math.max(0, Math.min(4095, Math.round(((volts * ratio * 1000) / facts.adcRefMv) * 4096)));
}

class QuietLogger {
  constructor() {
    this.messages = [];
  }
  push(level, c, m) {
    if (this.messages.length < 200) this.messages.push(`${level} ${c}: ${m}`);
  }
  debug() {}
  info() {}
  warn(c, m) {
    this.push('warn', c, m);
  }
  error(c, m) {
    this.push('error', c, m);
  }
}

export class Board {
  /**
   * @param {object} o
   * @param {string} o.elfPath firmware ELF
   * @param {string} [o.bootromPath] 16 KiB B1 bootrom image; without it, route (b): start at the vector table
   * @param {number|null} [o.paired] the remote's NEC address in the pairing sector, as if paired
   *   earlier (default: the board's NEC address, the tests' remote); null: a blank sector, unpaired
   * @param {object} [o.flashTiming] how long flash operations stall the core (lib/flash.js's
   *   FLASH_TIMING: typical by default, worst, none)
   */
  constructor({ elfPath, bootromPath, paired, flashTiming }) {
    this.elf = readElf(elfPath);
    this.facts = boardFacts(this.elf);
    this.bootrom = bootromPath ? FlashChip.patchBootrom(bootromWords(bootromPath)) : null;
    this.flashChip = new FlashChip(flashTiming);
    this.stallEndNs = 0; // the core waits for the flash chip until then (absolute ns)
    this.stalls = []; // { from, to } absolute ns, one per flash operation
    this.flashChip.onStall = (ns) => {
      this.stallEndNs = this.nowNs + ns;
      this.stalls.push({ from: this.nowNs, to: this.stallEndNs });
    };
    this.flashTop = loadFlash(this.elf, this.flashChip.bytes);
    const address = paired === undefined ? this.facts.necAddress : paired;
    if (address !== null) this.flashChip.storePairing(this.facts.pairingOffset, address);
    this.usb = { connected: false, rx: [], request: null, cdc: null };
    this.timeOffsetNs = 0; // simulated time before the current chip instance (resets)
    this.events = []; // external stimuli: { t, fn }, sorted by t
    this.motorEdges = []; // { t, v } with v = 0/1, absolute ns
    this.resets = []; // { t, reason }
    this.irqEntries = []; // { t, cycles } one per IO_IRQ_BANK0 handler run
    this.irEdgeTimes = [];
    this.asleep = []; // { from, to } absolute ns, one per stretch the core spent in WFI/WFE
    this.dormantStretches = []; // { from, to } absolute ns: crystal stopped, every clock frozen
    this.lockups = []; // { t, address, why }: the core locked up (see `busFault`)
    this.adcReads = []; // { t, pin, phase, v } one per battery conversion
    this.irLevel = true; // TSOP output idles high
    this.cell = new Cell(4.0);
    this.watchdogFired = false;
    this.logger = new QuietLogger();
    this.rotor = new Rotor(4 * this.facts.hallPolePairs);
    this.rateTrace = []; // { t, hz, v } one per rotor step
    this.hallLevels = [true, true];
    this.hallEdgeCount = 0;
    this.hallEdgeTimes = []; // absolute ns of every latch transition
    /** CPU cycles added to every IO_IRQ_BANK0 handler run (a longer handler, for the timing-margin scenarios). */
    this.irqExtraCycles = 0;
    this.powerOn('power-on');
    this.at(ROTOR_STEP_NS, () => this.stepRotor());
  }

  /** One rotor step: the rate from the last millisecond's drive, the Hall edges of the next. */
  stepRotor() {
    const t = this.nowNs;
    // Unpowered, the latches' open-drain outputs let go and the pull-ups
    // lift both lines (within this step): what the firmware's pre-start
    // self-test reads with the motor off.
    if (!this.hallPowered) this.setHall(true, true);
    const v = this.dutyIn(t - ROTOR_STEP_NS, t) * this.cell.loadedV;
    const crossings = this.rotor.advance(v, ROTOR_STEP_NS);
    this.rateTrace.push({ t, hz: this.rotor.rateHz, v });
    for (const c of crossings) this.at(t + c.dtNs, () => this.setHall(c.a, c.b));
    this.at(t + ROTOR_STEP_NS, () => this.stepRotor());
  }

  get hallPowered() {
    return this.mcu.gpio[this.facts.hallPowerGpio].value === GPIOPinState.High;
  }

  setHall(a, b) {
    const f = this.facts;
    const [la, lb] = this.hallPowered ? [a, b] : [true, true];
    for (const [gpio, level, i] of [[f.hallAGpio, la, 0], [f.hallBGpio, lb, 1]]) {
      if (this.hallLevels[i] === level) continue;
      this.hallLevels[i] = level;
      this.hallEdgeCount++;
      this.hallEdgeTimes.push(this.nowNs);
      this.mcu.gpio[gpio].setInputValue(level);
    }
  }

  /** Mean rotor rate (Hz) over [t0, t1). */
  rateIn(t0, t1) {
    const r = this.rateTrace.filter((x) => x.t >= t0 && x.t < t1);
    return r.reduce((s, x) => s + x.hz, 0) / Math.max(1, r.length);
  }

  get nowNs() {
    return this.timeOffsetNs + this.clock.nanos;
  }

  /** A fresh chip: power-on, or a watchdog reset (timeout or forced), which keeps the watchdog's reason and scratch registers as the real chip does. */
  powerOn(reason) {
    const previous = this.mcu;
    if (previous) this.timeOffsetNs += this.clock.nanos;
    const mcu = new RP2040(); // with its own SimulationClock (simulated nanoseconds)
    this.lockedUp = null; // a reset ends a lockup
    this.clock = mcu.clock;
    mcu.logger = this.logger;
    mcu.peripherals[(VREG_AND_CHIP_RESET_BASE >>> 14) << 2] = new VregAndChipReset(mcu);
    if (this.bootrom) {
      mcu.loadBootrom(this.bootrom); // resets the core: SP from the bootrom's vector table
    }
    this.flashChip.attach(mcu, () => this.nowNs);
    if (this.bootrom) {
      // Route (a): the real B1 bootrom is mapped at 0 (ROM function table, soft
      // float/memcpy routines the HAL's intrinsics call), and execution starts
      // at boot2 in flash, which sets up the SSI and jumps through the vector
      // table at 0x10000100 as on hardware. The bootrom's own reset handler
      // cannot run here: rp2040js has no SPI flash behind the SSI, so the
      // bootrom could not read boot2 out of flash into SRAM.
      mcu.core.PC = FLASH_BASE;
    } else {
      // Route (b): no bootrom, no boot2. Start at the firmware's vector table.
      const vt = FLASH_BASE + 0x100;
      mcu.core.VTOR = vt;
      mcu.core.SP = mcu.readUint32(vt);
      mcu.core.PC = mcu.readUint32(vt + 4) & ~1;
    }
    if (previous) {
      // The watchdog's reason and scratch registers survive a watchdog reset.
      const oldWd = previous.findPeripheral(WATCHDOG_BASE);
      const newWd = mcu.findPeripheral(WATCHDOG_BASE);
      newWd.scratchData.set(oldWd.scratchData);
      newWd.reason = oldWd.reason;
    }
    const wd = mcu.findPeripheral(WATCHDOG_BASE);
    wd.onWatchdogTrigger = () => {
      // The chip resets here: stop this instance's watchdog at once (its
      // periodic alarm would otherwise fire again and again inside the same
      // clock tick); the run loop swaps in a fresh chip right after the tick.
      wd.timer.enable = false;
      wd.alarm.enable = false;
      this.watchdogFired = true;
    };
    this.mcu = mcu;
    this.modelPowerRegisters(mcu);
    this.resets.push({ t: this.nowNs, reason });
    const f = this.facts;
    // Motor pin: gate pulled down by 100 kohm, so an undriven pin reads low.
    this.recordMotor(mcu.gpio[f.motorGpio].value);
    mcu.gpio[f.motorGpio].addListener((state) => this.recordMotor(state));
    mcu.gpio[f.irGpio].setInputValue(this.irLevel);
    mcu.gpio[f.vbusGpio].setInputValue(this.usb.connected);
    if (this.usb.connected) this.attachUsbHost(mcu);
    if (this.hallLevels) {
      mcu.gpio[f.hallAGpio].setInputValue(this.hallLevels[0]);
      mcu.gpio[f.hallBGpio].setInputValue(this.hallLevels[1]);
    }
    // Writes into the XIP block's space outside its writable windows are
    // bus errors on the chip (XIP_CTRL.ERR_BADWRITE = 1 at reset): the
    // cached alias 0x10xxxxxx (writes go to the cache), XIP_CTRL and
    // XIP_SRAM (0x14/0x15xxxxxx) and the SSI (0x18xxxxxx) take writes;
    // rp2040js ignores the rest. A stack overflow's pushes land at
    // 0x1FFFFFxx. Modelled: such a write aborts the instruction (BusFault
    // below) and the core takes HardFault; if that exception's own stacking
    // faults too, or the core is already in HardFault, the core locks up
    // (ARMv6-M: no handler runs, the core fetches nothing; the peripherals,
    // the PWM and the watchdog run on). `lockups` records each.
    for (const width of ['writeUint32', 'writeUint16', 'writeUint8']) {
      const write = mcu[width].bind(mcu);
      mcu[width] = (address, value) => {
        if (isBadXipWrite(address >>> 0)) throw new BusFault(address >>> 0);
        write(address, value);
      };
    }
    // Sample-and-hold at the start of each conversion: the cell's terminal
    // voltage at that instant, from the motor pin's present level.
    mcu.adc.onADCRead = (channel) => {
      mcu.adc.currentChannel = channel;
      if (channel === f.batteryAdcChannel) {
        const t = this.nowNs;
        const last = this.motorEdges[this.motorEdges.length - 1];
        const pin = last ? last.v : 0;
        const rise = pin ? t - this.lastMotorRise : null;
        const v = this.cell.terminalV(rise);
        const slice = this.pwmSlice0;
        this.adcReads.push({ t, pin, phase: slice.timer.counter / (slice.top + 1), v });
        mcu.adc.channelValues[channel] = adcCodeForBattery(f, v);
      }
      mcu.adc.sampleAlarm.schedule(mcu.adc.sampleTime * 1000);
    };
    this.inIrq = false;
    this.irqCycles = 0;
    this.stallEndNs = 0; // a reset ends the wait (the flash chip's own busy time is not modelled past it)
    this.flashFetchesInStall = this.flashFetchesInStall || 0; // instructions fetched from flash while it was busy
  }

  /**
   * rp2040js ignores the sleep clock gates (CLOCKS SLEEP_EN0/1), SCR.SLEEPDEEP
   * and the GPIO dormant-wake enables, and runs on through an XOSC DORMANT
   * write. The board keeps those registers, and models DORMANT: from the
   * write on the chip is frozen (no clock, no timer, no watchdog) while no
   * raw GPIO interrupt (INTR: a pin's levels and its latched edges) has its
   * DORMANT_WAKE_INTE bit set, as the IO bank's dormant-wake line works (a
   * stale latched edge wakes it at once); then the crystal is stable again
   * at once (its ~1 ms start-up is not modelled).
   */
  modelPowerRegisters(mcu) {
    this.dormant = false;
    this.sleepEn = [0xffffffff, 0x7fff]; // reset values: everything runs in sleep
    this.scr = 0;
    this.dormantWake = [0, 0, 0, 0];
    this.irEdgesSeen = 0;
    this.irEdgesLost = 0;
    const wrap = (peripheral, read, write) => {
      const r = peripheral.readUint32.bind(peripheral);
      const w = peripheral.writeUint32.bind(peripheral);
      peripheral.readUint32 = (offset) => read(offset) ?? r(offset);
      peripheral.writeUint32 = (offset, value) => {
        if (!write(offset, value >>> 0)) w(offset, value);
      };
    };
    wrap(
      mcu.findPeripheral(CLOCKS_BASE),
      (o) => (o === SLEEP_EN0 ? this.sleepEn[0] : o === SLEEP_EN1 ? this.sleepEn[1] : undefined),
      (o, v) => {
        if (o !== SLEEP_EN0 && o !== SLEEP_EN1) return false;
        this.sleepEn[(o - SLEEP_EN0) >> 2] = v;
        return true;
      },
    );
    const wakeIndex = (o) => (o >= DORMANT_WAKE_INTE0 && o < DORMANT_WAKE_INTE0 + 16 ? (o - DORMANT_WAKE_INTE0) >> 2 : -1);
    // IR edge latches: an edge the firmware clears (INTR is write-1-to-clear)
    // without any read of INTR or INTS having shown it to the firmware is lost.
    const io = mcu.findPeripheral(IO_BANK0_BASE);
    const irReg = this.facts.irGpio >> 3;
    const irEdges = 0xc << ((this.facts.irGpio & 7) * 4);
    const intrOffset = INTR0 + 4 * irReg;
    const intsOffset = PROC0_INTS0 + 4 * irReg;
    const ioRead = io.readUint32.bind(io);
    this.ioRawRead = ioRead; // INTR without the IR accounting below
    wrap(
      io,
      (o) => {
        if (wakeIndex(o) >= 0) return this.dormantWake[wakeIndex(o)];
        if (o === intrOffset || o === intsOffset) {
          const v = ioRead(o);
          this.irEdgesSeen |= v & irEdges;
          return v;
        }
        return undefined;
      },
      (o, v) => {
        if (o === intrOffset) {
          const cleared = io.rawWriteValue & irEdges & ioRead(intrOffset);
          for (let m = cleared & ~this.irEdgesSeen; m; m &= m - 1) this.irEdgesLost++;
          this.irEdgesSeen &= ~cleared;
          return false;
        }
        if (wakeIndex(o) < 0) return false;
        this.dormantWake[wakeIndex(o)] = v;
        return true;
      },
    );
    wrap(
      mcu.ppb,
      (o) => (o === SCR ? this.scr : undefined),
      (o, v) => {
        if (o !== SCR) return false;
        this.scr = v;
        return true;
      },
    );
    wrap(
      mcu.findPeripheral(XOSC_BASE),
      () => undefined,
      (o, v) => {
        if (o === 0x08 && v === DORMANT_MAGIC) {
          this.dormant = true;
          this.dormantStretches.push({ from: this.nowNs, to: this.nowNs });
        }
        return false;
      },
    );
  }

  /** Is the IO bank's dormant wake asserted (a raw interrupt whose DORMANT_WAKE_INTE bit is set)? */
  dormantWakePending() {
    return this.dormantWake.some((enabled, i) => (this.ioRawRead(INTR0 + 4 * i) & enabled) !== 0);
  }

  wakeFromDormant() {
    this.dormant = false;
    const xosc = this.mcu.findPeripheral(XOSC_BASE);
    xosc.isDormant = false;
    xosc.stable = true;
  }

  recordMotor(state) {
    const v = state === GPIOPinState.High || state === GPIOPinState.InputPullUp ? 1 : 0;
    const last = this.motorEdges[this.motorEdges.length - 1];
    if (last && last.v === v) return;
    this.motorEdges.push({ t: this.nowNs, v });
    if (v) this.lastMotorRise = this.nowNs;
  }

  /** rp2040js's CDC host on the chip's USB controller: sends the pending request once the port is configured. */
  attachUsbHost(mcu) {
    const cdc = new USBCDC(mcu.usbCtrl);
    // rp2040js's CDC host answers an OUT buffer the device arms at once,
    // with what it has: before it has read the descriptors it drops the
    // buffer (the device then waits for ever), and with nothing to send it
    // completes it empty (the device re-arms: an interrupt storm). A real
    // host sends OUT data when it has some; so does this one: an armed OUT
    // buffer waits here until there are bytes for it.
    const usbc = mcu.usbCtrl;
    const cdcRead = usbc.onEndpointRead;
    let waiting = null;
    usbc.onEndpointRead = (ep, size) => {
      if (ep !== 0 && (ep !== cdc.outEndpoint || cdc.txFIFO.itemCount === 0)) {
        waiting = [ep, size];
        return;
      }
      cdcRead(ep, size);
    };
    cdc.onDeviceConnected = () => {
      this.usb.configuredAt = this.nowNs;
      if (this.usb.request) for (const b of this.usb.request) cdc.sendSerialByte(b);
      if (waiting && waiting[0] === cdc.outEndpoint) {
        const [ep, size] = waiting;
        waiting = null;
        cdcRead(ep, size);
      }
    };
    cdc.onSerialData = (buffer) => {
      for (const b of buffer) this.usb.rx.push(b);
      this.usb.lastRxAt = this.nowNs;
    };
    this.usb.cdc = cdc;
    // rp2040js raises BUS_RESET when its 10 ms reset ends but leaves the
    // line state at SE0 and, until the firmware clears BUS_RESET, CONNECTED
    // clear. A B1 chip behind a hub looks the same (RP2040-E5), except that
    // the idle bus after the reset reads J: rp2040-hal's `rp2040-e5`
    // workaround waits for that J, forces it through GPIO15, and sees
    // CONNECTED (rp2040js sets it on the USB_MUXING write). The line state
    // J is set here with the end of the reset, so that path runs.
    if (!usbc.swimbotLineStateJ) {
      usbc.swimbotLineStateJ = true;
      const updated = usbc.sieStatusUpdated.bind(usbc);
      usbc.sieStatusUpdated = () => {
        const BUS_RESET = 1 << 19;
        const LINE_STATE = 3 << 2;
        const J = 1 << 2;
        if (usbc.sieStatus & BUS_RESET && (usbc.sieStatus & LINE_STATE) === 0) usbc.sieStatus |= J;
        updated();
      };
    }
    // The firmware enables its USB controller at boot, before any cable: the
    // host's bus reset, which rp2040js's CDC host sends when the controller
    // is enabled, comes now, as when a cable is plugged in.
    if (mcu.usbCtrl.mainCtrl & 1) mcu.usbCtrl.resetDevice();
  }

  /** Plug USB in (VBUS high, a CDC host enumerates the port) and send `request` (a string) once it is up. */
  connectUsb(request) {
    this.usb = { connected: true, rx: [], request: Buffer.from(request, 'ascii'), cdc: null };
    this.mcu.gpio[this.facts.vbusGpio].setInputValue(true);
    this.attachUsbHost(this.mcu);
  }

  disconnectUsb() {
    this.usb.connected = false;
    this.mcu.gpio[this.facts.vbusGpio].setInputValue(false);
  }

  // ---- stimuli -------------------------------------------------------------

  /** Schedules fn at absolute simulated time t (ns). */
  at(t, fn) {
    let i = this.events.length;
    while (i > 0 && this.events[i - 1].t > t) i--;
    this.events.splice(i, 0, { t, fn });
  }

  setIr(level) {
    if (level === this.irLevel) return;
    this.irLevel = level;
    this.irEdgeTimes.push(this.nowNs);
    this.mcu.gpio[this.facts.irGpio].setInputValue(level);
  }

  /** Schedules a waveform: [[durationNs, level], ...] starting at absolute time t; returns its end time. */
  playIr(t, waveform) {
    for (const [dur, level] of waveform) {
      this.at(t, () => this.setIr(level));
      t += dur;
    }
    this.at(t, () => this.setIr(true));
    return t;
  }

  /** The cell's open-circuit voltage (the ADC sees it at rest, sagging during on-pulses). */
  setBattery(volts) {
    this.cell.ocvV = volts;
  }

  /** Write a 32-bit word of the running firmware's data object `name` (test images' switches). */
  poke(name, value) {
    const { addr } = objectBytes(this.elf, name);
    this.mcu.writeUint32(addr, value);
  }

  // ---- running -------------------------------------------------------------

  runFor(ns) {
    this.runUntil(this.nowNs + ns);
  }

  runUntil(t) {
    while (this.nowNs < t) {
      const before = this.nowNs;
      const next = this.events.length && this.events[0].t < t ? this.events[0].t : t;
      this.runChipUntil(next);
      let applied = false;
      while (this.events.length && this.events[0].t <= this.nowNs) {
        this.events.shift().fn();
        applied = true;
      }
      if (this.nowNs === before) {
        // `nowNs` is the clock's nanoseconds plus the offset of the jumps
        // (power-ups, DORMANT): `end` in `runChipUntil` is `next` less that
        // offset, and the sum can fall short of `next` by its rounding. A
        // target within that rounding of now is reached (this loop once
        // never ended there).
        while (this.events.length && this.events[0].t <= next) {
          this.events.shift().fn();
          applied = true;
        }
        if (!applied) break;
      }
    }
  }

  runChipUntil(tAbs) {
    const { clock } = this;
    const mcu = this.mcu;
    const core = mcu.core;
    const end = tAbs - this.timeOffsetNs;
    while (clock.nanos < end) {
      if (this.dormant && this.dormantWakePending()) this.wakeFromDormant();
      if (this.dormant) {
        // Frozen until an event (the runUntil loop applies it) wakes it.
        this.timeOffsetNs += end - clock.nanos;
        this.dormantStretches[this.dormantStretches.length - 1].to = this.nowNs;
        return;
      }
      if (this.watchdogFired) {
        this.watchdogFired = false;
        this.powerOn('watchdog');
        return this.runChipUntil(tAbs);
      }
      if (this.stallEndNs > this.nowNs && core.IPSR === 0 && !takesInterrupt(core)) {
        // The ROM waits for the flash chip: the thread runs no instruction,
        // while the timer, PWM and watchdog run on. An interrupt the
        // firmware left unmasked is taken (below), as on the chip, where the
        // ROM's wait loop is interrupted; masked, an edge stays latched.
        // In the clock's own time base: `stallEndNs - nowNs` mixes the
        // offset (seconds, after a power-up) with the clock's fraction of a
        // nanosecond, and rounded to 0 there while `clock.nanos < end` still
        // held, a loop that never advanced (seen once the passes' timing
        // shifted by a few cycles). At least a picosecond: always progress.
        const stallEnd = this.stallEndNs - this.timeOffsetNs;
        clock.tick(Math.max(Math.min(stallEnd, end) - clock.nanos, 1e-3));
        continue;
      }
      if (this.stallEndNs > this.nowNs && core.IPSR === 0) core.interruptsUpdated = true; // enter it now
      if (this.stallEndNs > this.nowNs && core.PC >= FLASH_BASE && core.PC < FLASH_BASE + 0x1000000) {
        // On the chip this fetch fails: XIP is off while the flash is busy.
        this.flashFetchesInStall++;
      }
      if (core.waiting && wakePending(core)) {
        // rp2040js enters WFI even with an interrupt already pending (it only
        // looks when one is raised); the Cortex-M0+ does not sleep then.
        core.waiting = false;
      }
      if (core.waiting) {
        // Sleeping (WFI/WFE): jump to the next peripheral alarm, or to the end.
        const left = end - clock.nanos;
        const toAlarm = clock.nextAlarm ? clock.nanosToNextAlarm : Infinity;
        const from = this.nowNs;
        // At least a picosecond when time is left: ~28 s into a run the
        // clock's nanoseconds have an ulp of ~4e-6 ns, and a remainder
        // below it added nothing, a loop that never advanced (seen once the
        // idle passes ran on the crystal and shifted the wake-ups).
        const dt = Math.max(0, Math.min(toAlarm, left));
        clock.tick(dt > 0 ? Math.max(dt, 1e-3) : 0);
        const last = this.asleep[this.asleep.length - 1];
        if (last && last.to === from) last.to = this.nowNs;
        else this.asleep.push({ from, to: this.nowNs });
        continue;
      }
      if (this.lockedUp) {
        // Locked up: no instruction runs until a reset (the watchdog's).
        clock.tick(Math.max(Math.min(clock.nanosToNextAlarm, end - clock.nanos), 1e-3));
        continue;
      }
      const before = core.IPSR;
      const pc = core.PC;
      let cycles;
      try {
        cycles = core.executeInstruction();
      } catch (e) {
        if (!(e instanceof BusFault)) throw e;
        cycles = this.busFault(pc, e.address);
      }
      const after = core.IPSR;
      if (before === EXC_IO_IRQ_BANK0 || after === EXC_IO_IRQ_BANK0) {
        if (!this.inIrq) {
          this.inIrq = true;
          this.irqCycles = 0;
          // A longer handler, emulated: its extra cycles pass before the first instruction.
          if (this.irqExtraCycles) clock.tick((this.irqExtraCycles * 1e9) / mcu.clkSys);
        }
        this.irqCycles += cycles;
        if (after !== EXC_IO_IRQ_BANK0) {
          this.inIrq = false;
          this.irqEntries.push({ t: this.nowNs, cycles: this.irqCycles });
        }
      }
      clock.tick((cycles * 1e9) / mcu.clkSys);
    }
    if (this.watchdogFired) {
      this.watchdogFired = false;
      this.powerOn('watchdog');
    }
  }

  /** A bus error at the instruction at `pc`: HardFault, or lockup if that cannot be entered. */
  busFault(pc, address) {
    const core = this.mcu.core;
    const lockup = (why) => {
      this.lockedUp = { t: this.nowNs, address, why };
      this.lockups.push(this.lockedUp);
      return 1;
    };
    if (core.IPSR === 3) return lockup('bus error in the HardFault handler');
    core.PC = pc; // the stacked return address: the faulting instruction
    try {
      core.exceptionEntry(3);
    } catch (e) {
      if (!(e instanceof BusFault)) throw e;
      return lockup('bus error stacking the HardFault frame');
    }
    return 1;
  }

  // ---- observation ---------------------------------------------------------

  /** Fraction of [t0, t1] the chip spent DORMANT. */
  dormantIn(t0, t1) {
    let ns = 0;
    for (const { from, to } of this.dormantStretches) ns += Math.max(0, Math.min(to, t1) - Math.max(from, t0));
    return ns / (t1 - t0);
  }

  /** Fraction of [t0, t1] the core spent asleep (WFI/WFE). */
  asleepIn(t0, t1) {
    let ns = 0;
    for (const { from, to } of this.asleep) ns += Math.max(0, Math.min(to, t1) - Math.max(from, t0));
    return ns / (t1 - t0);
  }

  /** Index of the first recorded motor edge later than t (binary search). */
  edgeIndexAfter(t) {
    const e = this.motorEdges;
    let lo = 0;
    let hi = e.length;
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (e[mid].t <= t) lo = mid + 1;
      else hi = mid;
    }
    return lo;
  }

  /** Motor pin level (0/1) at absolute time t. */
  motorAt(t) {
    const i = this.edgeIndexAfter(t);
    return i > 0 ? this.motorEdges[i - 1].v : 0;
  }

  motorEdgesIn(t0, t1) {
    return this.motorEdges.filter((e) => e.t >= t0 && e.t < t1);
  }

  /** Fraction of [t0, t1) during which the motor pin is high. */
  dutyIn(t0, t1) {
    const e = this.motorEdges;
    let high = 0;
    let v = this.motorAt(t0);
    let t = t0;
    for (let i = this.edgeIndexAfter(t0); i < e.length && e[i].t < t1; i++) {
      if (v) high += e[i].t - t;
      t = e[i].t;
      v = e[i].v;
    }
    if (v) high += t1 - t;
    return high / (t1 - t0);
  }

  /** PWM carrier frequency from the rising edges in [t0, t1): { hz, minHz, maxHz, periods }. */
  pwmFreqIn(t0, t1) {
    const rises = this.motorEdges.filter((e) => e.v === 1 && e.t >= t0 && e.t < t1).map((e) => e.t);
    if (rises.length < 3) return { hz: 0, minHz: 0, maxHz: 0, periods: Math.max(0, rises.length - 1) };
    const periods = [];
    for (let i = 1; i < rises.length; i++) periods.push(rises[i] - rises[i - 1]);
    const mean = (rises[rises.length - 1] - rises[0]) / periods.length;
    return {
      hz: 1e9 / mean,
      minHz: 1e9 / Math.max(...periods),
      maxHz: 1e9 / Math.min(...periods),
      periods: periods.length,
    };
  }

  firstRiseAfter(t) {
    const e = this.motorEdges.find((x) => x.v === 1 && x.t >= t);
    return e ? e.t : undefined;
  }

  lastRiseBefore(t) {
    let r;
    for (const e of this.motorEdges) {
      if (e.t >= t) break;
      if (e.v === 1) r = e.t;
    }
    return r;
  }

  /** The PWM slice driving GPIO16 (slice 0), straight from the emulator's registers. */
  get pwmSlice0() {
    return this.mcu.pwm.channels[0];
  }

  /**
   * What in the flash operations so far would fetch from the busy flash on
   * the chip: an operation with an interrupt other than IO_IRQ_BANK0 live,
   * or an instruction fetched from flash during a stall. Empty when safe.
   */
  flashStallViolations() {
    const bad = this.flashChip.ops
      .filter((o) => o.liveIrqs & ~IRQ_LIVE_IN_FLASH_OPS)
      .map((o) => `${o.op} at ${(o.t / MS).toFixed(1)} ms with IRQs 0x${o.liveIrqs.toString(16)} live`);
    if (this.flashFetchesInStall) bad.push(`${this.flashFetchesInStall} instructions fetched from flash during a stall`);
    return bad;
  }

  /** Absolute time (ns) the TIMER's alarm 0 (the sleep's wake-up) is armed for, or null. */
  get wakeAlarmNs() {
    const alarm = this.mcu.findPeripheral(TIMER_BASE).alarms[0];
    return alarm.armed ? this.timeOffsetNs + alarm.targetMicros * US : null;
  }

  get watchdog() {
    return this.mcu.findPeripheral(WATCHDOG_BASE);
  }

  get watchdogEnabled() {
    return this.watchdog.enable;
  }

  /** The handler installed for IO_IRQ_BANK0, read from the vector table the firmware runs with. */
  irqHandler() {
    const vtor = this.mcu.core.VTOR;
    const addr = this.mcu.readUint32(vtor + 4 * EXC_IO_IRQ_BANK0) & ~1;
    const sym = symbolize(this.elf, addr);
    return { addr, name: sym ? sym.name : '?' };
  }

  irqCyclesSince(t) {
    return this.irqEntries.filter((e) => e.t >= t);
  }
}

/**
 * rp2040js leaves VREG_AND_CHIP_RESET unimplemented (reads 0xffffffff). The
 * bootrom's reset handler reads CHIP_RESET and, seeing HAD_PSM_RESTART (bit 24,
 * "restarted by the debugger"), parks the core waiting for a debugger. Model
 * the registers as after a power-on reset: VREG 1.10 V enabled, BOD enabled,
 * CHIP_RESET.HAD_POR set.
 */
class VregAndChipReset extends BasePeripheral {
  constructor(rp2040) {
    super(rp2040, 'VREG_AND_CHIP_RESET');
    this.regs = [0x000000b1, 0x00000091, 0x00000100];
  }
  readUint32(offset) {
    if (offset < 12) return this.regs[offset >> 2];
    return super.readUint32(offset);
  }
  writeUint32(offset, value) {
    if (offset === 0 || offset === 4) this.regs[offset >> 2] = value;
    // CHIP_RESET: only PSM_RESTART_FLAG (bit 24) is writable (write 1 to clear)
    else if (offset === 8) this.regs[2] &= ~(value & (1 << 24));
    else super.writeUint32(offset, value);
  }
}

/**
 * Would a pending interrupt wake WFI? On the Cortex-M0+ (ARMv6-M ARM, B1.5.19)
 * any enabled interrupt that would preempt the current priority if PRIMASK
 * were clear wakes it, also one that was already pending when WFI ran: so
 * an alarm that fires between the sleep's arming (PRIMASK set) and its WFI
 * does not put the core to sleep for ever. rp2040js checks only when an
 * interrupt is raised, so without this check a pass that ends on its alarm's
 * tick sleeps until the watchdog resets the chip.
 */
function wakePending(core) {
  const set = core.pendingInterrupts & core.enabledInterrupts;
  if (!set) return false;
  const running = core.exceptionPriority(core.IPSR);
  for (let p = 0; p < running; p++) if (set & core.interruptPriorities[p]) return true;
  return false;
}

/** Would the core take an interrupt now (enabled, pending, PRIMASK clear, above the running priority)? */
function takesInterrupt(core) {
  return !core.PM && wakePending(core);
}

function bootromWords(path) {
  const bytes = readFileSync(path);
  if (bytes.length !== 16384) throw new Error(`${path}: expected a 16 KiB bootrom, got ${bytes.length} B`);
  const words = new Uint32Array(4096);
  for (let i = 0; i < 4096; i++) words[i] = bytes.readUInt32LE(i * 4);
  return words;
}

class BusFault extends Error {
  constructor(address) {
    super(`bus error: write to 0x${address.toString(16)}`);
    this.address = address;
  }
}

/** A write the XIP block answers with a bus error (see the guard in `boot`). */
function isBadXipWrite(a) {
  if (a < 0x10000000 || a >= 0x20000000) return false;
  const top = a >>> 24;
  return !(top === 0x10 || top === 0x14 || top === 0x15 || top === 0x18);
}
