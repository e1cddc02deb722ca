// Scenario 12: the run log's page programs at their worst-case stall (3 ms
// each, every 1.6 s while running; lib/flash.js's FLASH_TIMING.worst) with
// every interrupt but the IR/Hall one held off (its handler and vector are
// in RAM; the board counts any fetch from the busy flash). The rate loop
// holds, the watchdog is not tripped, a key is obeyed whether or not a
// stall falls in its frame, and an Off at a stall stops the motor. Then a
// key pressed during a block erase (150 ms typical): queued, and obeyed
// when the block is done.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { perf } from '../lib/contract.js';
import { FLASH_TIMING } from '../lib/flash.js';
import { boardWith } from '../lib/images.js';
import { necFrame } from '../lib/nec.js';
import { ms, sendFrame, sendOff, sendOn } from '../lib/steps.js';

const GAP = 40 * MS;
const PAGE_EVERY_NS = 1600 * MS; // 16 records of 100 ms a page

test('worst-case page-program stalls (3 ms): rate loop, watchdog, IR keys', { skip: (process.env.SWIMBOT_EMU_ROUTE || 'a') !== 'a' && 'route (b) has no boot ROM: no flash writes' }, async (t) => {
  const b = boardWith('firmware', { flashTiming: FLASH_TIMING.worst });
  const f = b.facts;
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  const on = sendOn(b, b.nowNs + GAP);
  b.runUntil(on.end + 6000 * MS);
  const programs = () => b.flashChip.ops.filter((o) => o.op === 'program' && o.t > on.end);
  /** The next page program, predicted from the last one (records every 100 ms, a page every 16). */
  const nextProgram = () => programs().at(-1).t + PAGE_EVERY_NS;
  /** Sends `frame` at the first moment from `t` on whose frame no page program can meet. */
  const sendClear = (t, frame) => {
    const len = frame.reduce((s, [d]) => s + d, 0);
    b.runUntil(t);
    if (nextProgram() - b.nowNs < len + 10 * MS) b.runUntil(nextProgram() + 10 * MS);
    const sent = sendFrame(b, b.nowNs + 1 * MS, frame);
    assert.equal(b.flashChip.ops.filter((o) => o.t >= sent.start && o.t <= sent.end).length, 0, 'a stall in a frame meant to be clear');
    return sent;
  };

  await t.test('the rate loop holds through the stalls; no reset', () => {
    const p = programs();
    assert.ok(p.length >= 3, `${p.length} page programs in 6 s`);
    for (const o of p) assert.equal(o.stallNs, 3 * MS);
    assert.deepEqual(b.flashStallViolations(), [], 'flash fetched while busy');
    const hz = b.rateIn(on.end + 5000 * MS, on.end + 6000 * MS);
    perf('worst-case stalls: rate over the 6th second at 1 Hz', hz.toFixed(4), 'Hz');
    assert.ok(Math.abs(hz - 1) <= 0.01, `rate ${hz.toFixed(4)} Hz`);
    const asleep = b.asleepIn(on.end + 4000 * MS, on.end + 6000 * MS);
    perf('worst-case stalls: core asleep with the motor running', `${(100 * asleep).toFixed(1)} %`, '');
    assert.ok(asleep >= 0.95);
    assert.deepEqual(b.resets.map((r) => r.reason), ['power-on']);
  });

  await t.test('a key clear of a stall is obeyed, and so is one with a stall in its frame', () => {
    // Key 5 (1.5 Hz), its 68 ms frame clear of any stall.
    const k5 = sendClear(b.nowNs, necFrame(f.necAddress, f.necCmdPreset5));
    b.runUntil(k5.end + 3000 * MS);
    const hz5 = b.rateIn(b.nowNs - 500 * MS, b.nowNs);
    assert.ok(Math.abs(hz5 / 1.5 - 1) <= 0.01, `key 5 not obeyed: ${hz5.toFixed(3)} Hz`);
    // Key 1 with the next page program in the middle of its frame: the
    // IR interrupt, in RAM, still timestamps every edge.
    const k1 = sendFrame(b, nextProgram() - 30 * MS, necFrame(f.necAddress, f.necCmdPreset1));
    const cut = b.flashChip.ops.filter((o) => o.op === 'program' && o.t >= k1.start && o.t <= k1.end);
    assert.equal(cut.length, 1, 'the predicted page program did not fall in the frame');
    perf('worst-case stalls: key frame with a 3 ms page program in it, stall at', ms(cut[0].t - k1.start), 'into the frame: obeyed');
    b.runUntil(k1.end + 3000 * MS);
    const hz1 = b.rateIn(b.nowNs - 500 * MS, b.nowNs);
    assert.ok(Math.abs(hz1 / 0.5 - 1) <= 0.01, `key 1 with a stall in its frame not obeyed: ${hz1.toFixed(3)} Hz`);
    assert.deepEqual(b.resets.map((r) => r.reason), ['power-on']);
    assert.deepEqual(b.flashStallViolations(), []);
  });

  await t.test('Off at a stall: the pin low within 1 ms of the frame or of the stall, whichever ends later', () => {
    // Aimed to end 1.5 ms into the next page program's 3 ms stall (the
    // program comes with the first pass after a record's 100 ms tick, so
    // the aim is good to about 1 ms).
    const frame = necFrame(f.necAddress, f.necCmdOff);
    const len = frame.reduce((s, [d]) => s + d, 0);
    if (nextProgram() - len < b.nowNs + 5 * MS) b.runUntil(nextProgram() + 10 * MS);
    const off = sendFrame(b, nextProgram() - len + 1.5 * MS, frame);
    b.runUntil(off.end + 50 * MS);
    const stall = b.stalls.find((x) => x.to >= off.start && x.from <= off.end + 1 * MS);
    assert.ok(stall, 'no stall met the frame');
    assert.equal(b.dutyIn(off.end + 10 * MS, b.nowNs), 0, 'Off at a stall did not stop the motor');
    const lastRise = b.lastRiseBefore(b.nowNs);
    const low = b.motorEdges.find((e) => e.v === 0 && e.t >= lastRise).t;
    perf(`worst-case stalls: Off frame, stall from ${ms(stall.from - off.end)} to ${ms(stall.to - off.end)} around the frame's end: end of frame to pin low`, ms(low - off.end), '');
    assert.ok(low - off.end <= Math.max(0, stall.to - off.end) + 1 * MS, `pin low ${ms(low - off.end)} after the frame`);
    assert.deepEqual(b.resets.map((r) => r.reason), ['power-on']);
    assert.deepEqual(b.flashStallViolations(), []);
  });
});

test('a key pressed during a block erase is obeyed when the block is done', { skip: (process.env.SWIMBOT_EMU_ROUTE || 'a') !== 'a' && 'route (b) has no boot ROM: no flash writes' }, () => {
  const b = boardWith('firmware', { flashTiming: FLASH_TIMING.typical });
  const f = b.facts;
  b.setBattery(4.0);
  // Three power-ups with a short run each use the three blank slots; the
  // fourth has none left and erases once the pairing window has closed.
  for (let i = 0; i < 3; i++) {
    if (i > 0) b.powerOn('power-on');
    b.runUntil(b.nowNs + 300 * MS);
    const on = sendOn(b, b.nowNs + GAP);
    b.runUntil(on.end + 300 * MS);
    sendOff(b, b.nowNs + GAP);
    b.runUntil(b.nowNs + 100 * MS);
  }
  b.powerOn('power-on');
  const boot = b.nowNs;
  const erases = () => b.flashChip.ops.filter((o) => o.op === 'erase' && o.t >= boot);
  b.runUntil(boot + f.pairingWindowMs * MS);
  while (erases().length === 0) b.runFor(1 * MS);
  const stall = b.stalls.at(-1);
  perf('block erase (typical): the chip stalled for', ms(stall.to - stall.from), '');
  // On, its frame starting 20 ms into the erase's stall: queued by the IR
  // interrupt (in RAM) and decoded by the first pass after the block.
  const on = sendFrame(b, stall.from + 20 * MS, necFrame(f.necAddress, f.necCmdOn));
  b.runUntil(stall.to + 300 * MS);
  const first = b.firstRiseAfter(on.start);
  assert.ok(first !== undefined, 'the On sent during the erase was lost');
  assert.ok(first >= stall.to, 'PWM during the erase');
  perf('On sent 20 ms into a block erase: end of the erase to the first PWM pulse', ms(first - stall.to), '');
  assert.ok(first - stall.to < 1 * MS);
  assert.equal(erases().filter((e) => e.t > stall.to).length, 0, 'an erase with the motor started');
  assert.deepEqual(b.resets.filter((r) => r.t > boot), []);
  assert.deepEqual(b.flashStallViolations(), [], 'flash fetched while busy');
});
