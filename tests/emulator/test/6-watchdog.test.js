// Scenario 6: the watchdog. The normal image enables it and never trips it;
// the `hang-test` image stops feeding it ~1 s after boot, the chip resets
// after the 500 ms period, and the motor pin is low after the reset.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MOTOR_GPIO, MS } from '../lib/board.js';
import { WATCHDOG_NS, perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { ms, pct, sendOn } from '../lib/steps.js';

test('normal image: watchdog enabled, fed, never trips (2 s with the motor on)', () => {
  const b = boardWith('firmware');
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  assert.ok(b.watchdogEnabled, 'watchdog not enabled 20 ms after boot');
  const on = sendOn(b, 20 * MS);
  b.runUntil(2000 * MS);
  assert.ok(b.dutyIn(on.end + 300 * MS, 2000 * MS) > 0.5, 'motor not running');
  assert.deepEqual(b.resets.map((r) => r.reason), ['power-on'], 'the normal image was reset');
  // Between passes the core sleeps (WFI) until an IR edge or the 1 kHz
  // wake-up alarm: a pass is a few microseconds, so it is asleep almost
  // always, and the watchdog above was still fed by every pass.
  const asleep = b.asleepIn(on.end + 300 * MS, 2000 * MS);
  perf('core asleep between passes, motor running', pct(asleep), '');
  assert.ok(asleep > 0.9, `core asleep only ${pct(asleep)} of the time: the main loop is not sleeping between passes`);
});

test('hang-test image: watchdog resets the chip, motor pin low after the reset', () => {
  const b = boardWith('firmware-hang-test');
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  const on = sendOn(b, 20 * MS);
  b.runUntil(950 * MS);
  const before = b.dutyIn(on.end + 300 * MS, 950 * MS);
  assert.ok(before > 0.5, `motor not running before the hang (duty ${pct(before)})`);
  let wd;
  while (!wd && b.nowNs < 3000 * MS) {
    b.runUntil(b.nowNs + 5 * MS);
    wd = b.resets.find((r) => r.reason === 'watchdog');
  }
  assert.ok(wd, 'no watchdog reset within 3 s of boot');
  perf('hang-test: boot to watchdog reset (hang at ~1 s + 500 ms period)', (wd.t / MS).toFixed(1), 'ms');
  assert.ok(wd.t >= 1000 * MS + 0.8 * WATCHDOG_NS && wd.t <= 1100 * MS + 1.2 * WATCHDOG_NS, `watchdog reset at ${ms(wd.t)}, want ~1.5 s`);
  const motorDuringHang = b.dutyIn(1050 * MS, wd.t);
  console.log(`emulator: motor duty between the hang and the watchdog reset: ${pct(motorDuringHang)}`);

  // After the reset: low at once (pin undriven, 100k pull-down), driven low by
  // the rebooted firmware within 1 ms, and no PWM without a new command.
  assert.equal(b.motorAt(wd.t), 0, 'motor pin high at the reset');
  b.runUntil(wd.t + 1 * MS);
  const pin = b.mcu.gpio[MOTOR_GPIO];
  assert.ok(pin.outputEnable && !pin.outputValue, 'GPIO16 not driven low 1 ms after the watchdog reset');
  b.runUntil(wd.t + 900 * MS);
  assert.equal(b.resets.length, 2, `resets: ${b.resets.map((r) => `${r.reason}@${ms(r.t)}`).join(', ')}`);
  // (A falling edge exactly at the reset is the PWM output being released.)
  const edges = b.motorEdgesIn(wd.t, b.nowNs).filter((e) => e.t > wd.t || e.v === 1);
  assert.equal(edges.length, 0, `motor pin moved ${edges.length} times after the watchdog reset without a command`);
});
