// Scenario 6: the fail-safes. The normal image enables the watchdog (not
// paused for a debugger) and never trips it; the `fault-test` image, told
// through its SWIMBOT_FAULT_TEST switch, hangs its main loop (the watchdog
// resets the chip within its period) or panics (the handler forces the gate
// low at once and resets). The motor pin is low after each, and stays low.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS, US } from '../lib/board.js';
import { ASLEEP_RUNNING_MIN, FAILSAFE_DEADLINE_NS, RUNNING_DUTY, perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { ms, pct, sendOn } from '../lib/steps.js';

const PAUSE_BITS = (1 << 24) | (1 << 25) | (1 << 26); // PAUSE_JTAG, PAUSE_DBG0, PAUSE_DBG1

test('normal image: watchdog enabled, not paused by a debugger, fed, never trips (2 s with the motor on)', () => {
  const b = boardWith('firmware');
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  assert.ok(b.watchdogEnabled, 'watchdog not enabled 20 ms after boot');
  const ctrl = b.watchdog.readUint32(0);
  assert.equal(ctrl & PAUSE_BITS, 0, `watchdog CTRL 0x${ctrl.toString(16)}: paused while a debugger halts the core`);
  const on = sendOn(b, 20 * MS);
  b.runUntil(2000 * MS);
  assert.ok(b.dutyIn(on.end + 300 * MS, 2000 * MS) > RUNNING_DUTY, 'motor not running');
  assert.deepEqual(b.resets.map((r) => r.reason), ['power-on'], 'the normal image was reset');
  // Between passes the core sleeps (WFI) until an IR edge or the 1 kHz
  // wake-up alarm: a pass is a few microseconds, so it is asleep almost
  // always, and the watchdog above was still fed by every pass.
  const asleep = b.asleepIn(on.end + 300 * MS, 2000 * MS);
  perf('core asleep between passes, motor running', pct(asleep), '');
  assert.ok(asleep >= ASLEEP_RUNNING_MIN, `core asleep only ${pct(asleep)} of the time: the main loop is not sleeping between passes`);
});

/** Boots the fault-test image, runs the motor, throws `mode` at `tFault`; returns the board and the reset. */
function faultAt(mode, tFault) {
  const b = boardWith('firmware-fault-test');
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  const on = sendOn(b, 20 * MS);
  b.runUntil(tFault);
  const before = b.dutyIn(on.end + 300 * MS, tFault);
  assert.ok(before > RUNNING_DUTY, `motor not running before the fault (duty ${pct(before)})`);
  b.poke('SWIMBOT_FAULT_TEST', mode);
  let reset;
  while (!reset && b.nowNs < tFault + 1000 * MS) {
    b.runUntil(b.nowNs + 100 * US);
    reset = b.resets.find((r) => r.reason === 'watchdog');
  }
  assert.ok(reset, 'no reset within 1 s of the fault');
  return { b, reset };
}

/** After a reset at `t`: gate low and driven low, no PWM without a command. */
function staysOff(b, t) {
  assert.equal(b.motorAt(t), 0, 'motor pin high at the reset');
  b.runUntil(t + 1 * MS);
  const pin = b.mcu.gpio[b.facts.motorGpio];
  assert.ok(pin.outputEnable && !pin.outputValue, 'GPIO16 not driven low 1 ms after the reset');
  b.runUntil(t + 500 * MS);
  assert.equal(b.resets.length, 2, `resets: ${b.resets.map((r) => `${r.reason}@${ms(r.t)}`).join(', ')}`);
  const edges = b.motorEdgesIn(t, b.nowNs).filter((e) => e.t > t || e.v === 1);
  assert.equal(edges.length, 0, `motor pin moved ${edges.length} times after the reset without a command`);
}

test('forced hang: the watchdog resets the chip within its period, motor pin low after it', () => {
  const tHang = 700 * MS;
  const { b, reset } = faultAt(1, tHang);
  const wdNs = b.facts.watchdogMs * MS;
  perf(`hang: main loop stops to watchdog reset (period ${b.facts.watchdogMs} ms)`, ((reset.t - tHang) / MS).toFixed(1), 'ms');
  assert.ok(reset.t - tHang <= wdNs + 2 * MS, `watchdog reset ${ms(reset.t - tHang)} after the hang, period ${ms(wdNs)}`);
  assert.ok(reset.t - tHang >= 0.8 * wdNs, `reset only ${ms(reset.t - tHang)} after the hang: not the watchdog`);
  const lastHigh = b.lastRiseBefore(reset.t);
  console.log(`emulator: motor ran on for ${ms(reset.t - tHang)} of hang (last pulse ${ms(reset.t - lastHigh)} before the reset)`);
  staysOff(b, reset.t);
});

test('forced panic: gate low at once, then a reset', () => {
  const tPanic = 700 * MS;
  const { b, reset } = faultAt(2, tPanic);
  const lastHigh = b.lastRiseBefore(reset.t);
  const fall = b.motorEdges.find((e) => e.t >= tPanic && e.v === 0 && !b.motorEdgesIn(e.t + 1, reset.t).some((x) => x.v === 1));
  assert.ok(fall, 'the motor pin never went low for good after the panic');
  perf('panic: switch set to motor pin low for good (includes up to one 1 ms pass)', ((fall.t - tPanic) / US).toFixed(1), 'us');
  assert.ok(fall.t - tPanic <= FAILSAFE_DEADLINE_NS + 1 * MS, `gate low ${ms(fall.t - tPanic)} after the panic`);
  assert.ok(reset.t - tPanic < 5 * MS, `reset ${ms(reset.t - tPanic)} after the panic (not forced by the handler?)`);
  assert.equal(b.watchdog.reason, 2, `watchdog REASON ${b.watchdog.reason}: want FORCE (the handler's trigger)`);
  console.log(`emulator: last motor pulse ${ms(reset.t - lastHigh)} before the reset`);
  staysOff(b, reset.t);
});

// A stack overflow on the Cortex-M0+ (the board models the XIP block's bus
// error for a write below RAM and the ARMv6-M lockup when the HardFault
// frame cannot be stacked: lib/board.js, `busFault`). Expected: the core
// locks up, no handler runs (the gate is not forced low), the PWM keeps its
// last duty until the watchdog resets the chip within its period, then the
// pin is low and stays low; the reset reads as the watchdog's, not FORCE.
test('stack overflow: lockup, the motor runs on until the watchdog resets the chip', () => {
  const tFault = 700 * MS;
  const { b, reset } = faultAt(3, tFault);
  assert.equal(b.lockups.length, 1, `lockups: ${JSON.stringify(b.lockups)}`);
  const lock = b.lockups[0];
  perf('stack overflow: switch set to lockup', ((lock.t - tFault) / US).toFixed(0), 'us');
  console.log(`emulator: lockup at 0x${lock.address.toString(16)} (${lock.why})`);
  assert.ok(lock.address >= 0x1f000000 && lock.address < 0x20000000, 'the fault was not a push below RAM');
  // The PWM ran on through the lockup: the duty before the reset is the run's.
  assert.ok(b.dutyIn(lock.t, reset.t) > RUNNING_DUTY, 'the motor stopped before the watchdog: a handler ran?');
  const wdNs = b.facts.watchdogMs * MS;
  perf(`stack overflow: lockup to watchdog reset (period ${b.facts.watchdogMs} ms)`, ((reset.t - lock.t) / MS).toFixed(1), 'ms');
  assert.ok(reset.t - lock.t <= wdNs + 2 * MS, `reset ${ms(reset.t - lock.t)} after the lockup`);
  assert.equal(b.watchdog.reason, 1, `watchdog REASON ${b.watchdog.reason}: want TIMER (no handler's FORCE)`);
  staysOff(b, reset.t);
});
