// Scenario 16: the motor supervisor on the chip (shared/src/supervisor.rs),
// independent of the rate controller. A tail whose load grows (weed, a
// bent helix) until the rated voltage turns it at only 0.08 Hz crawls with
// the controller saturated: the supervisor stops it within 2 s. The mean
// motor voltage never passes the motor's rating, even from a full cell
// with the controller asking more. The loads are the factors on the tail's
// torque (tau_0 + c w) at which the calibrated motor (lib/rotor.js) needs
// those voltages: most of its drag is its own seal's, so a tail twenty
// times heavier still turns at 0.4 Hz.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { ms, sendOn } from '../lib/steps.js';

test('a crawling tail is stopped by the supervisor; the mean voltage stays under the rating', async (t) => {
  const b = boardWith('firmware');
  b.setBattery(4.2);
  b.runUntil(50 * MS);
  const on = sendOn(b, 50 * MS);
  b.runUntil(on.end + 3000 * MS);
  const rated = b.facts.motorRatedMv / 1000;

  const set = b.facts.defaultRateMhz / 1000;
  await t.test('a heavy load: the controller asks more than the rating, the drive holds at it', () => {
    // Holding the set-point would need 1.3 times the rating.
    b.rotor.load = b.rotor.loadFor(1.3 * rated, set);
    perf('heavy load: tail load factor needing 1.3 x the rating at ' + set + ' Hz', b.rotor.load.toFixed(1), '');
    const from = b.nowNs;
    b.runUntil(from + 3000 * MS);
    const meanV = b.dutyIn(from + 2000 * MS, b.nowNs) * b.cell.loadedV;
    perf('heavy load from a 4.2 V cell: mean motor voltage (rating ' + rated + ' V)', meanV.toFixed(3), 'V');
    assert.ok(meanV <= rated + 0.02, `mean motor voltage ${meanV.toFixed(3)} V`);
    assert.ok(meanV >= rated - 0.15, `not at the ceiling: ${meanV.toFixed(3)} V`);
  });

  await t.test('a load that holds the rated voltage to 0.08 Hz: crawling, stopped within 2 s', () => {
    b.rotor.load = b.rotor.loadFor(rated, 0.08);
    perf('crawl: tail load factor turning it at 0.08 Hz at the rating', b.rotor.load.toFixed(0), '');
    const from = b.nowNs;
    b.runUntil(from + 4000 * MS);
    const off = b.lastRiseBefore(b.nowNs);
    assert.ok(off !== undefined && off > from, 'the motor was not driven after the load grew');
    const after = off - from;
    const crawl = b.rateIn(from + 500 * MS, off);
    perf('tail crawling at ' + crawl.toFixed(3) + ' Hz: load step to motor off', ms(after), '');
    assert.ok(crawl < 0.1 && crawl > 0, `rate ${crawl.toFixed(3)} Hz`);
    assert.ok(after <= 2050 * MS, `stopped ${ms(after)} after the load step`);
    assert.equal(b.dutyIn(off + 1 * MS, b.nowNs), 0);
    assert.equal(b.hallPowered, false);
    assert.deepEqual(b.resets.map((r) => r.reason), ['power-on']);
  });
});
