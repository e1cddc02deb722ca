// Scenario 12: the run log's page programs at their worst-case stall (3 ms
// each, every 1.6 s while running; lib/flash.js's FLASH_TIMING.worst) with
// interrupts held off as on the chip. The rate loop holds, the watchdog is
// not tripped, keys sent clear of a stall are obeyed, a key whose frame a
// stall cuts is rejected (never a wrong command) and obeyed when sent again,
// and an Off at a stall stops the motor. Then a key pressed during a block
// erase (150 ms typical, interrupts masked): lost, as firmware/README.md
// says; the erases wait for the IR to be quiet, and the key pressed again
// is obeyed.
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
    for (const o of p) {
      assert.ok(o.masked, 'a page program with interrupts enabled');
      assert.equal(o.stallNs, 3 * MS);
    }
    const hz = b.rateIn(on.end + 5000 * MS, on.end + 6000 * MS);
    perf('worst-case stalls: rate over the 6th second at 1 Hz', hz.toFixed(4), 'Hz');
    assert.ok(Math.abs(hz - 1) <= 0.01, `rate ${hz.toFixed(4)} Hz`);
    const asleep = b.asleepIn(on.end + 4000 * MS, on.end + 6000 * MS);
    perf('worst-case stalls: core asleep with the motor running', `${(100 * asleep).toFixed(1)} %`, '');
    assert.ok(asleep >= 0.95);
    assert.deepEqual(b.resets.map((r) => r.reason), ['power-on']);
  });

  await t.test('a key clear of a stall is obeyed; one a stall cuts is rejected, then obeyed', () => {
    // Key 5 (1.5 Hz), its 68 ms frame clear of any stall.
    const k5 = sendClear(b.nowNs, necFrame(f.necAddress, f.necCmdPreset5));
    b.runUntil(k5.end + 3000 * MS);
    const hz5 = b.rateIn(b.nowNs - 500 * MS, b.nowNs);
    assert.ok(Math.abs(hz5 / 1.5 - 1) <= 0.01, `key 5 not obeyed: ${hz5.toFixed(3)} Hz`);
    // Key 1 with the next page program in the middle of its frame.
    const start = nextProgram() - 30 * MS;
    const k1 = sendFrame(b, start, necFrame(f.necAddress, f.necCmdPreset1));
    const cut = b.flashChip.ops.filter((o) => o.op === 'program' && o.t >= k1.start && o.t <= k1.end);
    assert.equal(cut.length, 1, 'the predicted page program did not fall in the frame');
    perf('worst-case stalls: key frame with a 3 ms stall in it, stall at', ms(cut[0].t - k1.start), 'into the frame');
    b.runUntil(k1.end + 1500 * MS);
    const after = b.rateIn(b.nowNs - 300 * MS, b.nowNs);
    assert.ok(Math.abs(after / 1.5 - 1) <= 0.01, `the cut frame changed the rate: ${after.toFixed(3)} Hz`);
    assert.ok(b.dutyIn(b.nowNs - 50 * MS, b.nowNs) > 0, 'the motor stopped');
    // Pressed again, clear of a stall: obeyed.
    const again = sendClear(b.nowNs + GAP, necFrame(f.necAddress, f.necCmdPreset1));
    b.runUntil(again.end + 3000 * MS);
    const hz1 = b.rateIn(b.nowNs - 500 * MS, b.nowNs);
    assert.ok(Math.abs(hz1 / 0.5 - 1) <= 0.01, `key 1 pressed again not obeyed: ${hz1.toFixed(3)} Hz`);
    assert.deepEqual(b.resets.map((r) => r.reason), ['power-on']);
  });

  await t.test('Off at a stall: the pin low within the stall + 1 ms, or the frame rejected and Off pressed again obeyed', () => {
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
    const where = `stall from ${ms(stall.from - off.end)} to ${ms(stall.to - off.end)} around the frame's end`;
    if (b.dutyIn(off.end + 10 * MS, b.nowNs) === 0) {
      const lastRise = b.lastRiseBefore(b.nowNs);
      const low = b.motorEdges.find((e) => e.v === 0 && e.t >= lastRise).t;
      perf(`worst-case stalls: Off frame, ${where}: end of frame to pin low`, ms(low - off.end), '');
      assert.ok(low - off.end <= Math.max(0, stall.to - off.end) + 1 * MS, `pin low ${ms(low - off.end)} after the frame`);
    } else {
      perf(`worst-case stalls: Off frame, ${where}`, 'rejected (pressed again)', '');
      const again = sendClear(b.nowNs + GAP, frame);
      b.runUntil(again.end + 5 * MS);
      assert.equal(b.dutyIn(again.end + 1 * MS, b.nowNs), 0, 'Off pressed again did not stop the motor');
    }
    assert.deepEqual(b.resets.map((r) => r.reason), ['power-on']);
  });
});

test('a key pressed during a block erase is lost; pressed again after it, obeyed', { skip: (process.env.SWIMBOT_EMU_ROUTE || 'a') !== 'a' && 'route (b) has no boot ROM: no flash writes' }, () => {
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
  const first = b.stalls.at(-1);
  perf('block erase (typical): the chip stalled for', ms(first.to - first.from), '');
  // On, its frame starting 20 ms into the erase's stall.
  const lost = sendFrame(b, first.from + 20 * MS, necFrame(f.necAddress, f.necCmdOn));
  b.runUntil(lost.end + 200 * MS);
  assert.equal(b.motorEdgesIn(lost.start, b.nowNs).length, 0, 'the On sent during the erase started the motor');
  // The erases pause while the IR is busy (250 ms quiet before the next).
  const next = erases().find((e) => e.t > first.to);
  assert.ok(!next || next.t >= lost.end + 250 * MS, 'an erase within 250 ms of the lost frame');
  // Pressed again, after the stall: obeyed (and no erase while it runs).
  const again = sendOn(b, Math.max(b.nowNs, b.stallEndNs) + GAP);
  b.runUntil(again.end + 300 * MS);
  assert.ok(b.dutyIn(b.nowNs - 50 * MS, b.nowNs) > 0, 'On pressed again did not start the motor');
  assert.deepEqual(b.resets.filter((r) => r.t > boot).length, 0);
});
