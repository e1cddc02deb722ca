// Scenario 9: power. Between passes the core sleeps with SLEEPDEEP set and
// the unneeded clocks gated (CLOCKS SLEEP_EN0/1); after a long idle with the
// motor off the chip goes DORMANT (crystal stopped: no pass, no timer) until
// the IR receiver's first falling edge, and then works as before.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { RUNNING_DUTY, perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { ms, pct, sendOff, sendOn } from '../lib/steps.js';

// CLOCKS SLEEP_EN0/1 bit numbers (RP2040 datasheet, CLOCKS: SLEEP_EN0/1).
const KEEP = { sys_io: 8, sys_pads: 11, sys_pwm: 17, sys_sram0: 28, sys_timer: 32 + 5, sys_watchdog: 32 + 12 };
const GATE = { adc_adc: 1, sys_adc: 2, sys_dma: 5, sys_pio0: 12, sys_rom: 19, sys_spi0: 25, peri_uart0: 32 + 6, usb_usbctrl: 32 + 11, sys_xip: 32 + 13 };
const bit = (sleepEn, n) => (sleepEn[n >> 5] >>> (n & 31)) & 1;

/** PLL PWR.PD (RP2040 datasheet 2.18.4): the PLL is powered down. */
const pllOff = (pll) => (pll.pwr & 1) === 1;

/** clk_sys and both PLLs at every 1 ms step of [t, t + ms): the distinct states seen. */
function clockStates(b, ms) {
  const seen = new Set();
  for (let i = 0; i < ms; i++) {
    b.runFor(1 * MS);
    seen.add(`clk_sys ${b.mcu.clkSys / 1e6} MHz, PLL_SYS ${pllOff(b.mcu.pllSys) ? 'off' : 'on'}, PLL_USB ${pllOff(b.mcu.pllUsb) ? 'off' : 'on'}`);
  }
  return [...seen];
}

test('clk_sys on the crystal with PLL_SYS off between idle passes; PLL_USB only with VBUS', () => {
  const b = boardWith('firmware');
  b.setBattery(3.9);
  b.runUntil(200 * MS);
  assert.deepEqual(clockStates(b, 800), ['clk_sys 12 MHz, PLL_SYS off, PLL_USB off'], 'idle, no IR, no VBUS');
  const on = sendOn(b, b.nowNs + 40 * MS);
  b.runUntil(on.end + 100 * MS);
  assert.deepEqual(clockStates(b, 500), ['clk_sys 125 MHz, PLL_SYS on, PLL_USB off'], 'the motor running, no VBUS');
  sendOff(b, b.nowNs + 40 * MS);
  b.runUntil(b.nowNs + 300 * MS);
  assert.deepEqual(clockStates(b, 100), ['clk_sys 12 MHz, PLL_SYS off, PLL_USB off'], 'idle again after Off');
  b.connectUsb('INFO\n');
  b.runFor(200 * MS);
  assert.ok(b.usb.rx.length > 0, 'INFO not answered');
  assert.deepEqual(clockStates(b, 100), ['clk_sys 125 MHz, PLL_SYS on, PLL_USB on'], 'USB connected');
  b.disconnectUsb();
  b.runFor(5 * MS);
  assert.deepEqual(clockStates(b, 100), ['clk_sys 12 MHz, PLL_SYS off, PLL_USB off'], 'unplugged');
});

test('sleep gates the unneeded clocks; DORMANT after a long idle, woken by IR', () => {
  const b = boardWith('firmware');
  b.setBattery(3.9);
  b.runUntil(1000 * MS);
  assert.equal(b.scr & 4, 4, 'SCR.SLEEPDEEP not set: the sleep clock gates never apply');
  for (const [name, n] of Object.entries(KEEP)) assert.equal(bit(b.sleepEn, n), 1, `clk_${name} gated in sleep`);
  for (const [name, n] of Object.entries(GATE)) assert.equal(bit(b.sleepEn, n), 0, `clk_${name} runs in sleep`);
  const idleAsleep = b.asleepIn(200 * MS, 1000 * MS);
  perf('core asleep between passes, motor off (clk_sys on the 12 MHz crystal)', pct(idleAsleep), '');
  perf('awake cycles per idle pass', (((1 - idleAsleep) * 12e6) / 1000).toFixed(0), '');
  // On the crystal a pass takes 125/12 times as long as at 125 MHz (the
  // same cycles); it must still leave most of its 1 ms period asleep, for
  // the IR interrupt and a late alarm.
  assert.ok(idleAsleep > 0.5, `asleep only ${pct(idleAsleep)} idle`);

  const quietMs = b.facts.dormantAfterMs;
  b.runUntil((quietMs + 2000) * MS);
  const d = b.dormantStretches[0];
  assert.ok(d, `not DORMANT ${quietMs + 2000} ms after boot`);
  perf('boot (motor off, no IR) to DORMANT', (d.from / MS).toFixed(1), 'ms');
  assert.ok(d.from >= quietMs * MS && d.from <= (quietMs + 50) * MS, `DORMANT at ${ms(d.from)}, want ${quietMs} ms after the last activity`);
  const res = b.dormantIn(d.from, b.nowNs);
  perf('DORMANT residency until the IR frame', pct(res), '');
  assert.ok(res > 0.999, `DORMANT only ${pct(res)} of the idle time`);
  assert.deepEqual(b.resets.map((r) => r.reason), ['power-on'], 'reset while DORMANT');
  assert.equal(b.motorAt(b.nowNs), 0);

  // The On frame's first edge wakes it; a second press is the fallback.
  let on = sendOn(b, b.nowNs);
  assert.ok(!b.dormant, 'the IR frame did not wake the chip');
  b.runUntil(on.end + 400 * MS);
  let frames = 1;
  if (b.dutyIn(on.end + 300 * MS, on.end + 400 * MS) < RUNNING_DUTY) {
    on = sendOn(b, b.nowNs);
    b.runUntil(on.end + 400 * MS);
    frames = 2;
  }
  perf('On frames needed after DORMANT', frames, '');
  const duty = b.dutyIn(on.end + 300 * MS, on.end + 400 * MS);
  assert.ok(duty > RUNNING_DUTY, `motor not running after waking from DORMANT (duty ${pct(duty)})`);
  const f = b.pwmFreqIn(on.end + 300 * MS, on.end + 400 * MS);
  assert.ok(Math.abs(f.hz / b.facts.pwmFreqHz - 1) < 0.01, `PWM at ${f.hz.toFixed(0)} Hz after the wake: clock tree not restored`);
});
