// Scenario 3: an Off frame stops the motor: duty 0 within 1 ms of the end of
// the frame, and it stays 0. A following On starts from zero (soft-start again).
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS, US } from '../lib/board.js';
import { OFF_DEADLINE_NS, RUNNING_DUTY, perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { ms, pct, sendOff, sendOn } from '../lib/steps.js';

test('Off frame: duty 0 within 1 ms of the end of the frame', () => {
  const b = boardWith('firmware');
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  const on = sendOn(b, 20 * MS);
  b.runUntil(on.end + 350 * MS);
  const running = b.dutyIn(on.end + 300 * MS, on.end + 350 * MS);
  assert.ok(running > RUNNING_DUTY, `motor not running before the Off frame (duty ${pct(running)})`);

  const off = sendOff(b, b.nowNs);
  // Still running while the Off frame is being received.
  assert.ok(b.dutyIn(off.end - 10 * MS, off.end - 1 * MS) > RUNNING_DUTY, 'motor stopped before the Off frame ended');
  b.runUntil(off.end + 300 * MS);

  const lastRise = b.lastRiseBefore(off.end + 300 * MS);
  const lastFall = b.motorEdgesIn(off.end - 1 * MS, off.end + 300 * MS).filter((e) => e.v === 0).pop();
  const stopAt = Math.max(lastRise ?? 0, lastFall ? lastFall.t : 0);
  perf('Off: end of frame to motor pin low for good', ((stopAt - off.end) / US).toFixed(1), 'us');
  assert.equal(b.motorAt(off.end + OFF_DEADLINE_NS), 0, 'motor pin high 1 ms after the Off frame');
  const late = b.motorEdgesIn(off.end + OFF_DEADLINE_NS, off.end + 300 * MS);
  assert.equal(late.length, 0, `${late.length} motor pin edges later than 1 ms after the Off frame, first at ${late.length ? ms(late[0].t - off.end) : ''}`);
  assert.equal(b.dutyIn(off.end + OFF_DEADLINE_NS, off.end + 300 * MS), 0);

  // On again: soft-start from zero, not a jump back to the old duty.
  const on2 = sendOn(b, b.nowNs);
  b.runUntil(on2.end + 300 * MS);
  const early = b.dutyIn(on2.end, on2.end + 20 * MS);
  const late2 = b.dutyIn(on2.end + 280 * MS, on2.end + 300 * MS);
  perf('duty in the first 20 ms after a second On', pct(early), '');
  assert.ok(late2 > RUNNING_DUTY, `second On did not restart the motor (duty ${pct(late2)})`);
  // The rate reference ramps from zero; the duty from the line's intercept
  // (the voltage at which the motor just does not turn yet).
  const d0 = b.facts.lineInterceptMv / 1000 / b.cell.loadedV;
  assert.ok(early - d0 < 0.2 * (late2 - d0), `second On jumped to ${pct(early)} in its first 20 ms (held ${pct(late2)}, intercept ${pct(d0)}): no soft-start`);
});
