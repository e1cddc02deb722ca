// Scenario 7: the battery input ripples. The cell model (lib/cell.js) sags
// during every on-pulse the firmware drives, by ~0.3 V at 4 V. The firmware
// must convert at a fixed phase, the middle of the on-pulse, so that it
// reads the loaded voltage every time; a free-running conversion lands at
// any phase and reads the on or the off level at random.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { sendOn } from '../lib/steps.js';

test('battery conversions land mid on-pulse while the motor runs', () => {
  const b = boardWith('firmware');
  b.setBattery(4.0);
  b.runUntil(20 * MS);
  const on = sendOn(b, 20 * MS);
  b.runUntil(on.end + 1300 * MS);
  const from = on.end + 300 * MS;
  const reads = b.adcReads.filter((r) => r.t >= from);
  const duty = b.dutyIn(from, b.nowNs);
  assert.ok(duty > 0.5 && reads.length >= 40, `motor duty ${duty}, ${reads.length} conversions`);
  const phases = reads.map((r) => r.phase);
  const lo = Math.min(...phases);
  const hi = Math.max(...phases);
  perf('battery conversion phase with the motor running (fraction of the PWM period)', `${lo.toFixed(3)}-${hi.toFixed(3)}, on-pulse 0-${duty.toFixed(3)}`, '');
  for (const r of reads) {
    assert.equal(r.pin, 1, `conversion at ${(r.t / MS).toFixed(3)} ms during the off-time (phase ${r.phase.toFixed(3)})`);
    assert.ok(Math.abs(r.phase - duty / 2) < 0.08, `conversion at phase ${r.phase.toFixed(3)}, want mid on-pulse ${(duty / 2).toFixed(3)}`);
  }
  const v = reads.map((x) => x.v);
  perf('battery reading with the motor running (cell 4.0 V open circuit)', `${Math.min(...v).toFixed(3)}-${Math.max(...v).toFixed(3)}`, 'V');
  assert.ok(Math.max(...v) - Math.min(...v) < 0.01, 'the readings spread: not at one phase');
});
