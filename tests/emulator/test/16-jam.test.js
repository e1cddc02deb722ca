// Scenario 16: the motor supervisor on the chip (shared/src/supervisor.rs),
// independent of the rate controller. A tail whose load grows twentyfold
// while running crawls at under 0.1 Hz with the controller saturated: the
// supervisor stops it within 2 s. The mean motor voltage never passes the
// motor's rating, even from a full cell with the controller asking more.
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

  await t.test('a heavy load: the controller asks more than the rating, the drive holds at it', () => {
    b.rotor.load = 2;
    const from = b.nowNs;
    b.runUntil(from + 3000 * MS);
    const meanV = b.dutyIn(from + 2000 * MS, b.nowNs) * b.cell.loadedV;
    perf('twice the load from a 4.2 V cell: mean motor voltage (rating ' + rated + ' V)', meanV.toFixed(3), 'V');
    assert.ok(meanV <= rated + 0.02, `mean motor voltage ${meanV.toFixed(3)} V`);
    assert.ok(meanV >= rated - 0.15, `not at the ceiling: ${meanV.toFixed(3)} V`);
  });

  await t.test('a twentyfold load: crawling under 0.1 Hz, stopped within 2 s', () => {
    b.rotor.load = 20;
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
