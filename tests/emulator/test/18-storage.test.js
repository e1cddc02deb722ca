// Scenario 18: a robot stored with a flat cell. Below the cut-off and
// idle, the firmware opens the board's load switch (the power-hold pin,
// driven high from boot, goes low) before it would go DORMANT; a board
// without the switch (this emulated Pico) stays powered, so after its wait
// the chip goes DORMANT as before. Every wake-up reads the cell before
// anything else: the first battery conversion comes within the wake's
// first pass, not on the 20 ms schedule (the timer stood still).
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { ms, sendOn } from '../lib/steps.js';

test('storage: a flat cell opens the load switch before DORMANT; each wake reads the cell first', () => {
  const b = boardWith('firmware');
  const f = b.facts;
  const hold = () => {
    const pin = b.mcu.gpio[f.powerHoldGpio];
    return pin.outputEnable && pin.outputValue;
  };
  b.setBattery(3.9);
  b.runUntil(5 * MS);
  assert.ok(hold(), 'power hold not driven high at boot');
  const lows = [];
  b.mcu.gpio[f.powerHoldGpio].addListener(() => {
    if (!hold()) lows.push(b.nowNs);
  });

  // The cell sags below the cut-off with the motor off: the latch sets.
  b.setBattery((f.cutoffMv - 300) / 1000);
  b.runUntil(b.nowNs + (f.dormantAfterMs + 1500) * MS);
  const d = b.dormantStretches[0];
  assert.ok(d, 'not DORMANT after the cut-off and the idle time');
  assert.equal(lows.length, 1, `power hold released ${lows.length} times`);
  const wait = d.from - lows[0];
  perf('flat cell: power hold released to DORMANT (no switch on this board)', ms(wait), '');
  assert.ok(wait >= 45 * MS && wait <= 60 * MS, `DORMANT ${ms(wait)} after releasing the hold`);

  // A key wakes it: the hold is taken again and the cell is read at once.
  const on = sendOn(b, b.nowNs + 10 * MS);
  b.runUntil(on.end + 50 * MS);
  const wokeAt = d.to;
  assert.ok(wokeAt > d.from && wokeAt < on.end, 'the key did not wake the chip');
  assert.ok(hold(), 'power hold not driven high again after the wake');
  const first = b.adcReads.find((r) => r.t >= wokeAt);
  assert.ok(first, 'no battery conversion after the wake');
  perf('wake to first battery conversion', ms(first.t - wokeAt), '');
  assert.ok(first.t - wokeAt < 2 * MS, `first conversion ${ms(first.t - wokeAt)} after the wake`);
  // Latched and still flat: the motor stays off.
  assert.equal(b.motorEdgesIn(on.end, b.nowNs).filter((e) => e.v === 1).length, 0, 'motor started on a flat cell');
});
