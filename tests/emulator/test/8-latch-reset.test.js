// Scenario 8: the cut-off survives a reset. After a cut-off the cell
// recovers to 3.6 V at rest; a watchdog reset (which keeps the watchdog's
// scratch registers) must not make that read as a usable cell: On stays
// refused. A power-on (scratch cleared, e.g. the cell unplugged to be
// recharged) forgets it.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { boardWith } from '../lib/images.js';
import { pct, sendOn } from '../lib/steps.js';

const RECOVERED_V = 3.6;

test('cut-off latched across a watchdog reset', () => {
  const b = boardWith('firmware');
  b.setBattery(3.8);
  b.runUntil(20 * MS);
  const on = sendOn(b, 20 * MS);
  b.runUntil(on.end + 400 * MS);
  assert.ok(b.dutyIn(on.end + 300 * MS, on.end + 400 * MS) > 0.5, 'motor not running');
  b.setBattery(3.1);
  b.runUntil(b.nowNs + 2000 * MS);
  assert.equal(b.dutyIn(b.nowNs - 300 * MS, b.nowNs), 0, 'no cut-off at 3.1 V');
  b.setBattery(RECOVERED_V);
  b.runUntil(b.nowNs + 300 * MS);
  const tReset = b.nowNs;
  b.watchdog.writeUint32(0, 1 << 31); // CTRL.TRIGGER: a watchdog reset
  b.runUntil(tReset + 300 * MS);
  assert.deepEqual(b.resets.map((r) => r.reason), ['power-on', 'watchdog']);
  const on2 = sendOn(b, b.nowNs);
  b.runUntil(on2.end + 500 * MS);
  const edges = b.motorEdgesIn(tReset, b.nowNs).filter((e) => e.v === 1);
  assert.equal(edges.length, 0, `motor started after the reset at ${RECOVERED_V} V: the cut-off was forgotten`);
});

test('a power-on forgets it: the same cell starts', () => {
  const b = boardWith('firmware');
  b.setBattery(RECOVERED_V);
  b.runUntil(300 * MS);
  const on = sendOn(b, b.nowNs);
  b.runUntil(on.end + 400 * MS);
  const d = b.dutyIn(on.end + 300 * MS, on.end + 400 * MS);
  assert.ok(d > 0.5, `motor not running at ${RECOVERED_V} V after a power-on (duty ${pct(d)})`);
});
