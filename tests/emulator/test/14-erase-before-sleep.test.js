// Scenario 14: a pending log erase is finished before DORMANT. A power-up
// with no blank log slot has two slots to erase (8 blocks of 64 KiB); with
// a USB cable in from the start none is erased (the host would time out in
// a 150 ms stall). Unplugged after the 10 s idle time, the idle clock has
// long run out, yet the chip erases every block, one per pass while the
// motor is off, the gate low and the IR quiet, and only then goes DORMANT.
// The next power-up (the cell disconnected in between) then finds a blank
// slot and logs its first run from the start. An image that erased one
// block and went DORMANT would leave 7 for a later wake-up; with those
// checks taken out, its fifth power-up keeps nothing of its run (the
// readout is an earlier power-up's log).
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { perf } from '../lib/contract.js';
import { boardWith, manifest } from '../lib/images.js';
import { decodeLog, readOverUsb } from '../lib/runlog.js';
import { ms, sendOff, sendOn } from '../lib/steps.js';

const GAP = 40 * MS;
const noFlash = manifest().route !== 'a' && 'route (b) has no boot ROM: no flash writes';

/** A short run from an idle robot: On, 300 ms, Off. */
function shortRun(b) {
  b.runUntil(b.nowNs + 300 * MS);
  const on = sendOn(b, b.nowNs + GAP);
  b.runUntil(on.end + 300 * MS);
  sendOff(b, b.nowNs + GAP);
  b.runUntil(b.nowNs + 100 * MS);
}

test('an erase pending while USB was in is finished after the unplug, before DORMANT', { skip: noFlash }, () => {
  const b = boardWith('firmware');
  const f = b.facts;
  b.setBattery(4.0);
  // Three power-ups with a short run each use the three blank slots.
  for (let i = 0; i < 3; i++) {
    if (i > 0) b.powerOn('power-on');
    shortRun(b);
  }
  // The fourth powers up with the cable already in: its own slot and the
  // next one are to be erased, and nothing may be while USB is connected.
  b.connectUsb('INFO\n');
  b.powerOn('power-on');
  const boot = b.nowNs;
  const erases = () => b.flashChip.ops.filter((o) => o.op === 'erase' && o.t >= boot);
  b.runUntil(boot + (f.dormantAfterMs + 2000) * MS);
  assert.match(Buffer.from(b.usb.rx).toString('ascii'), /^swimbot-log v2 /, 'the port did not answer');
  assert.equal(erases().length, 0, 'an erase with USB connected');
  assert.equal(b.dormantStretches.filter((d) => d.from >= boot).length, 0, 'DORMANT with USB connected');

  b.disconnectUsb();
  const unplug = b.nowNs;
  const blocks = (2 * f.logSlotBytes) / 65536;
  b.runUntil(unplug + blocks * b.flashChip.timing.blockEraseNs + 1000 * MS);
  const done = erases();
  assert.equal(done.length, blocks, `${done.length} of ${blocks} blocks erased before the chip slept`);
  const lastEnd = b.stalls.filter((s) => s.from >= done.at(-1).t).at(0).to;
  const sleeps = b.dormantStretches.filter((d) => d.from >= unplug);
  assert.ok(sleeps.length > 0, 'not DORMANT after the erases');
  assert.ok(sleeps[0].from >= lastEnd, `DORMANT ${ms(lastEnd - sleeps[0].from)} before the last block was done`);
  assert.ok(sleeps[0].from - lastEnd < 5 * MS, `DORMANT only ${ms(sleeps[0].from - lastEnd)} after the last block`);
  assert.equal(sleeps.length, 1, `${sleeps.length} DORMANT entries after the unplug`);
  for (const e of done) {
    assert.equal(b.motorAt(e.t), 0, 'an erase with the motor pin high');
    assert.ok(b.dutyIn(e.t - 10 * MS, e.t) === 0, 'an erase within 10 ms of a PWM pulse');
  }
  assert.deepEqual(b.flashStallViolations(), [], 'flash fetched while busy');
  assert.deepEqual(b.resets.filter((r) => r.t > boot), [], 'a reset during the erases');
  perf('USB unplugged (idle > 10 s) with 8 blocks to erase: unplug to last block done / to DORMANT', `${ms(lastEnd - unplug)} / ${ms(sleeps[0].from - unplug)}`);

  // The cell disconnected and connected again: the fifth power-up writes
  // into the slot erased for it, so its first run (in the pairing window,
  // before any erase could run) is kept whole.
  b.powerOn('power-on');
  const boot5 = b.nowNs;
  shortRun(b);
  const { header, records } = decodeLog(readOverUsb(b, 'LOG\n', { timeoutNs: 1000 * MS }));
  assert.equal(header.flags & 2, 0, 'the readout is an earlier power-up\'s log: this one\'s run was not kept');
  assert.equal(header.dropped, 0, `the fifth power-up dropped ${header.dropped} records (its slot was not erased)`);
  assert.ok(records.length >= 3, `${records.length} records of a 300 ms run`);
  assert.equal(b.flashChip.ops.filter((o) => o.op === 'erase' && o.t >= boot5).length, 0, 'the fifth power-up had to erase');
});
