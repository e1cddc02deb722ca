// Scenario 5: low-battery cut-off. A short dip below 3.3 V does not stop the
// motor (debounce); a reading below the cut-off for longer than the ~1 s
// debounce stops it, and it stays stopped (latched) when the reading then
// recovers a little, even if On is pressed again, and across a watchdog
// reset (the latch lives in the watchdog's scratch registers). A power-on
// (scratch cleared: the cell unplugged to be recharged) forgets it.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { CUTOFF_DEBOUNCE_NS, RUNNING_DUTY, perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { dutyBins, ms, pct, sendOn } from '../lib/steps.js';

const LOW_V = 3.1; // below the 3.3 V cut-off, above any "implausible reading" floor
const OK_V = 3.8;
const RECOVERED_V = 3.6; // a depleted cell at rest: above the cut-off, below a recharged cell (3.9 V)

test('low battery: debounced cut-off, latched', async (t) => {
  const b = boardWith('firmware');
  b.setBattery(OK_V);
  b.runUntil(20 * MS);
  const on = sendOn(b, 20 * MS);
  b.runUntil(on.end + 400 * MS);
  assert.ok(b.dutyIn(on.end + 350 * MS, on.end + 400 * MS) > RUNNING_DUTY, 'motor not running at 3.8 V');

  await t.test('a 300 ms dip below the cut-off does not stop the motor', () => {
    const tDip = b.nowNs;
    b.setBattery(LOW_V);
    b.runUntil(tDip + 300 * MS);
    b.setBattery(OK_V);
    b.runUntil(tDip + 1500 * MS);
    for (const bin of dutyBins(b, tDip, b.nowNs, 10 * MS)) {
      assert.ok(bin.duty > RUNNING_DUTY, `duty ${pct(bin.duty)} ${ms(bin.t - tDip)} after a 300 ms dip`);
    }
  });

  const tLow = b.nowNs;
  b.setBattery(LOW_V);
  b.runUntil(tLow + 2000 * MS);

  await t.test('below the cut-off for longer than the debounce: motor stops', () => {
    const stillOn = b.dutyIn(tLow + 400 * MS, tLow + 500 * MS);
    assert.ok(stillOn > RUNNING_DUTY, `motor stopped within 0.5 s of the low reading (duty ${pct(stillOn)}): no debounce`);
    const last = b.motorEdgesIn(tLow, tLow + 2000 * MS).pop();
    assert.ok(last, 'no motor edges at all after the drop');
    perf('low-battery cut-off: reading below 3.3 V to motor stopped', ((last.t - tLow) / MS).toFixed(1), 'ms');
    assert.equal(b.motorAt(tLow + 2000 * MS), 0, 'motor pin high 2 s after the battery fell below the cut-off');
    assert.ok(last.t - tLow >= 0.7 * CUTOFF_DEBOUNCE_NS, `stopped after ${ms(last.t - tLow)}: debounce shorter than ~1 s`);
    assert.ok(last.t - tLow <= 1.6 * CUTOFF_DEBOUNCE_NS, `stopped only after ${ms(last.t - tLow)}`);
  });

  await t.test('stays stopped after a small recovery, On ignored (latched)', () => {
    const tRec = b.nowNs;
    b.setBattery(RECOVERED_V);
    b.runUntil(tRec + 300 * MS);
    const on2 = sendOn(b, b.nowNs);
    b.runUntil(on2.end + 700 * MS);
    const edges = b.motorEdgesIn(tRec, b.nowNs);
    assert.equal(edges.length, 0, `motor pin moved ${edges.length} times after recovering to ${RECOVERED_V} V (first ${edges.length ? ms(edges[0].t - tRec) : ''} after)`);
    assert.equal(b.motorAt(b.nowNs), 0);
  });

  assert.equal(b.resets.length, 1, `unexpected reset (${b.resets.map((r) => r.reason).join(', ')})`);

  await t.test('still latched after a watchdog reset', () => {
    const tReset = b.nowNs;
    b.watchdog.writeUint32(0, 1 << 31); // CTRL.TRIGGER: a watchdog reset, scratch kept
    b.runUntil(tReset + 300 * MS);
    assert.deepEqual(b.resets.map((r) => r.reason), ['power-on', 'watchdog']);
    const on3 = sendOn(b, b.nowNs);
    b.runUntil(on3.end + 500 * MS);
    const rises = b.motorEdgesIn(tReset, b.nowNs).filter((e) => e.v === 1);
    assert.equal(rises.length, 0, `motor started after the reset at ${RECOVERED_V} V: the cut-off was forgotten`);
  });
});

test('a power-on forgets the cut-off: the same cell starts', () => {
  const b = boardWith('firmware');
  b.setBattery(RECOVERED_V);
  b.runUntil(300 * MS);
  const on = sendOn(b, b.nowNs);
  b.runUntil(on.end + 400 * MS);
  const d = b.dutyIn(on.end + 300 * MS, on.end + 400 * MS);
  assert.ok(d > RUNNING_DUTY, `motor not running at ${RECOVERED_V} V after a power-on (duty ${pct(d)})`);
});
