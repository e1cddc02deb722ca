// Scenario 15: a run the robot could not log is said to be lost, not read
// out as if it were the last one. Three power-ups with a short run each use
// the three blank log slots; the fourth has none (its slot is erased only
// after the 5 s pairing window), so a run in its first second is dropped.
// Read over USB, LOG then holds the third power-up's records (the newest
// earlier log) and, in its header, the fourth power-up's dropped count;
// INFO says `log=earlier this_run=dropped`. A header whose count stays 0
// under an earlier power-up's records would say `dropped=0`, and a lab
// would take the third run's trace for the fourth's. A fifth
// power-up without a run says `log=earlier this_run=none`.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { perf } from '../lib/contract.js';
import { boardWith, manifest } from '../lib/images.js';
import { decodeLog, readOverUsb } from '../lib/runlog.js';
import { sendOff, sendOn } from '../lib/steps.js';

const GAP = 40 * MS;
const noFlash = manifest().route !== 'a' && 'route (b) has no boot ROM: no flash writes';

/** A short run from an idle robot: On, 500 ms, Off. */
function shortRun(b) {
  b.runUntil(b.nowNs + 300 * MS);
  const on = sendOn(b, b.nowNs + GAP);
  b.runUntil(on.end + 500 * MS);
  sendOff(b, b.nowNs + GAP);
  b.runUntil(b.nowNs + 100 * MS);
}

/** The INFO line (plugs USB in if it is not). */
function info(b) {
  b.connectUsb('INFO\n');
  const until = b.nowNs + 1000 * MS;
  while (b.nowNs < until && !b.usb.rx.includes(0x0a)) b.runFor(1e6);
  const line = Buffer.from(b.usb.rx).toString('ascii');
  assert.ok(line.endsWith('\n'), `no INFO line: ${JSON.stringify(line)}`);
  return line.trimEnd();
}

/** The `key=value` fields of an INFO line. */
function fields(line) {
  return Object.fromEntries(line.split(' ').slice(2).map((kv) => kv.split('=')));
}

test('a power-up with no erased slot runs: LOG and INFO say its run was dropped', { skip: noFlash }, () => {
  const b = boardWith('firmware');
  b.setBattery(4.0);
  for (let i = 0; i < 3; i++) {
    if (i > 0) b.powerOn('power-on');
    shortRun(b);
  }
  // The third power-up's own run: kept, and said so.
  const third = decodeLog(readOverUsb(b, 'LOG\n', { timeoutNs: 1000 * MS }));
  assert.equal(third.header.flags & 2, 0, 'the third power-up\'s run was not kept');
  const own = fields(info(b));
  assert.deepEqual([own.log, own.this_run, own.dropped], ['this', 'kept', '0']);
  b.disconnectUsb();

  // The fourth: no blank slot, the same run in its pairing window.
  b.powerOn('power-on');
  const boot = b.nowNs;
  shortRun(b);
  assert.equal(b.flashChip.ops.filter((o) => o.op === 'erase' && o.t >= boot).length, 0, 'an erase in the pairing window');
  const lost = decodeLog(readOverUsb(b, 'LOG\n', { timeoutNs: 1000 * MS }));
  assert.deepEqual(lost.records, third.records, 'the readout is not the newest earlier log');
  assert.equal(lost.header.flags & 2, 2, 'an earlier power-up\'s records not flagged as such');
  // The same script took as many records as the third power-up kept (the
  // pass timing may shift one across the Off).
  const n = third.records.length;
  assert.ok(Math.abs(lost.header.dropped - n) <= 1, `the fourth power-up dropped ${lost.header.dropped} records; the same run kept ${n}`);
  const said = info(b);
  const f = fields(said);
  assert.deepEqual([f.log, f.this_run], ['earlier', 'dropped'], said);
  assert.equal(Number(f.dropped), lost.header.dropped, said);
  assert.equal(Number(f.records), n, said);
  perf('lost run: fourth power-up, no erased slot, 0.5 s run: records dropped / earlier records read out', `${lost.header.dropped} / ${n}`);
  b.disconnectUsb();

  // A fifth power-up without a run: the earlier log, nothing dropped.
  b.powerOn('power-on');
  b.runUntil(b.nowNs + 200 * MS);
  const idle = fields(info(b));
  assert.deepEqual([idle.log, idle.this_run, idle.dropped], ['earlier', 'none', '0']);
});
