// Scenario 10: the run log, read out over the emulated USB (rp2040js's CDC
// host on the chip's USB controller), and pairing. The ROM's flash
// functions are applied to the board's flash chip (lib/flash.js), so the
// log is programmed into and read back from the flash region the image
// reserves, and survives a power-up; the time a flash operation stalls the
// chip is not emulated.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { perf } from '../lib/contract.js';
import { boardWith, manifest } from '../lib/images.js';
import { necFrame, necRepeat } from '../lib/nec.js';
import { EVENTS, decodeLog, readOverUsb } from '../lib/runlog.js';
import { sendFrame, sendOff, sendOn } from '../lib/steps.js';
import { Board } from '../lib/board.js';

const GAP = 40 * MS;
const route = manifest().route;

function freshBoard(opts = {}) {
  const m = manifest();
  return new Board({ elfPath: m.images.firmware, bootromPath: m.bootrom || undefined, ...opts });
}

test('run log: a run with foreign key spam and a sagging cell, read out over USB', { skip: route !== 'a' && 'route (b) has no boot ROM: no flash writes' }, () => {
  const b = boardWith('firmware');
  const f = b.facts;
  b.setBattery(4.0);
  b.runUntil(300 * MS);
  // Another remote (address 0x42) in the lab: On, Off and a preset while idle.
  let foreign = 0;
  for (const cmd of [f.necCmdOn, f.necCmdOff, f.necCmdPreset5]) {
    sendFrame(b, b.nowNs + GAP, necFrame(0x42, cmd));
    foreign++;
  }
  assert.equal(b.motorEdgesIn(0, b.nowNs).filter((e) => e.v === 1).length, 0, 'a foreign On started the motor');
  const on = sendOn(b, b.nowNs + GAP);
  b.runUntil(on.end + 5000 * MS); // past the first start's learning (2.4 s)
  // While running: more foreign frames, Off among them; then the cell sags.
  for (const cmd of [f.necCmdOff, f.necCmdOff, f.necCmdPreset1]) {
    sendFrame(b, b.nowNs + GAP, necFrame(0x42, cmd));
    foreign++;
  }
  assert.ok(b.dutyIn(b.nowNs - 100 * MS, b.nowNs) > 0.1, 'a foreign Off stopped the motor');
  b.setBattery(3.6);
  const sagAt = b.nowNs;
  b.runUntil(sagAt + 2000 * MS);
  const off = sendOff(b, b.nowNs + GAP);
  b.runUntil(off.end + 300 * MS);

  const bytes = readOverUsb(b, 'LOG\n', { timeoutNs: 5000 * MS });
  const { header, records } = decodeLog(bytes);
  perf('run log: records of a 7.5 s run, read over USB', `${records.length} records, ${bytes.length} B in ${((b.usb.lastRxAt - b.usb.configuredAt) / MS).toFixed(0)} ms`);
  assert.equal(header.periodMs, f.logPeriodMs);
  assert.equal(header.paired, f.necAddress);
  assert.equal(header.foreign, foreign, 'every foreign frame counted');
  assert.equal(header.dropped, 0);
  // 10 Hz from On to Off (the passes come every 1 ms, so a record is at
  // most a pass late), plus the closing record in the pass that stopped.
  const n = records.length;
  for (let i = 1; i < n - 1; i++) {
    const dt = records[i].tMs - records[i - 1].tMs;
    assert.ok(dt >= f.logPeriodMs && dt <= f.logPeriodMs + 2, `records ${i - 1}-${i} ${dt} ms apart`);
  }
  assert.ok(records[n - 1].tMs - records[n - 2].tMs <= f.logPeriodMs);
  assert.ok(Math.abs(records[n - 1].tMs - off.end / MS) <= 2, `the closing record is the Off pass (${records.slice(0, 2).concat(records.slice(-3)).map((r) => r.tMs).join(', ')} ms; Off at ${(off.end / MS).toFixed(1)} ms)`);
  assert.ok(records[0].events & EVENTS.STARTED && records[0].events & EVENTS.ON);
  assert.equal(records[0].foreign, 3, 'the frames while idle are in the first record');
  assert.equal(records.reduce((s, r) => s + r.foreign, 0), foreign);
  const last = records[records.length - 1];
  assert.ok(last.events & EVENTS.STOPPED_COMMAND && last.duty === 0);
  assert.ok(records.every((r) => r.setMhz === f.defaultRateMhz));
  // The log's rate against the rotor's own, and the sag in the cell column.
  const before = records.filter((r) => r.tMs * MS > sagAt - 1000 * MS && r.tMs * MS < sagAt);
  const after = records.filter((r) => r.tMs * MS > sagAt + 1200 * MS && r.tMs * MS < off.start);
  const mean = (xs) => xs.reduce((s, x) => s + x, 0) / xs.length;
  for (const r of [...before, ...after]) {
    // The logged rate is the last whole turn's.
    const turnNs = (1e6 / r.rateMhz) * MS;
    const rotor = b.rateIn(r.tMs * MS - turnNs, r.tMs * MS);
    assert.ok(Math.abs(r.rateMhz / 1000 / rotor - 1) < 0.02, `logged ${r.rateMhz} mHz, rotor ${rotor.toFixed(3)} Hz at ${r.tMs} ms`);
  }
  const cellDrop = mean(before.map((r) => r.cellMv)) - mean(after.map((r) => r.cellMv));
  const dutyRatio = mean(after.map((r) => r.duty)) / mean(before.map((r) => r.duty));
  perf('run log: cell 4.0 -> 3.6 V during control, logged loaded cell drop / duty ratio', `${cellDrop.toFixed(0)} mV / ${dutyRatio.toFixed(3)}`);
  assert.ok(cellDrop > 300 && cellDrop < 500, `logged cell drop ${cellDrop} mV`);
  assert.ok(dutyRatio > 1.05, `the duty did not rise with the sag (${dutyRatio})`);

  // USB connected holds the motor off: On does nothing.
  const t0 = b.nowNs;
  sendOn(b, b.nowNs + GAP);
  b.runUntil(b.nowNs + 500 * MS);
  assert.equal(b.motorEdgesIn(t0, b.nowNs).filter((e) => e.v === 1).length, 0, 'the motor ran with USB connected');
  // The log survives a power-up: the next power-up's readout is the same run.
  b.disconnectUsb();
  b.powerOn('power-on');
  b.runUntil(b.nowNs + 200 * MS);
  const again = decodeLog(readOverUsb(b, 'LOG\n', { timeoutNs: 5000 * MS }));
  assert.deepEqual(again.records, records, 'the log after a power-up');
  assert.equal(again.header.flags & 2, 2, 'flagged as an earlier power-up\'s');
  assert.equal(again.header.foreign, foreign, 'foreign count rebuilt from the records');
  const info = readOverUsb(b, 'INFO\n', { bytes: 60, timeoutNs: 1000 * MS }).toString('ascii');
  assert.match(info, new RegExp(`^swimbot-log v2 records=${records.length} period_ms=100 `));
});

test('pairing: unpaired obeys nobody; a 1 s hold of Off in the window pairs, kept in flash', { skip: route !== 'a' && 'route (b) has no boot ROM: no flash writes' }, () => {
  const b = freshBoard({ paired: null });
  const f = b.facts;
  b.setBattery(4.0);
  b.runUntil(300 * MS);
  sendOn(b, b.nowNs + GAP);
  b.runUntil(b.nowNs + 300 * MS);
  assert.equal(b.motorEdgesIn(0, b.nowNs).filter((e) => e.v === 1).length, 0, 'an unpaired robot started');
  // Hold Off on remote 0x5a: one frame, then a repeat every 108 ms for 1.2 s.
  const remote = 0x5a;
  let t = b.nowNs + GAP;
  sendFrame(b, t, necFrame(remote, f.necCmdOff));
  for (let i = 0; i < 11; i++) {
    t += 108 * MS;
    sendFrame(b, t, necRepeat());
  }
  b.runUntil(b.nowNs + 50 * MS);
  const programs = b.flashChip.ops.filter((o) => o.op === 'program' && o.offset >= f.pairingOffset);
  assert.equal(programs.length, 1, 'one page program stores the pairing');
  // The 8-byte entry (shared/src/pairing/sector.rs): R, the address's two
  // bytes, On, Off, their XOR, it inverted, !R.
  const lo = remote, hi = ~remote & 0xff, x = lo ^ hi ^ f.necCmdOn ^ f.necCmdOff;
  assert.deepEqual([...b.flashChip.bytes.subarray(f.pairingOffset, f.pairingOffset + 8)], [0x52, lo, hi, f.necCmdOn, f.necCmdOff, x, ~x & 0xff, 0xad]);
  assert.ok(b.nowNs < f.pairingWindowMs * MS + 1500 * MS);
  const on = sendFrame(b, b.nowNs + GAP, necFrame(remote, f.necCmdOn));
  b.runUntil(on.end + 300 * MS);
  assert.ok(b.dutyIn(b.nowNs - 50 * MS, b.nowNs) > 0, 'the paired remote\'s On did not start');
  sendFrame(b, b.nowNs + GAP, necFrame(remote, f.necCmdOff));
  // After a power-up the pairing holds, and the old address is foreign.
  b.powerOn('power-on');
  b.runUntil(b.nowNs + 6000 * MS); // past the window
  const t0 = b.nowNs;
  sendOn(b, b.nowNs + GAP);
  b.runUntil(b.nowNs + 300 * MS);
  assert.equal(b.motorEdgesIn(t0, b.nowNs).filter((e) => e.v === 1).length, 0, 'address 0x00 started a robot paired with 0x5a');
  const on2 = sendFrame(b, b.nowNs + GAP, necFrame(remote, f.necCmdOn));
  b.runUntil(on2.end + 300 * MS);
  assert.ok(b.dutyIn(b.nowNs - 50 * MS, b.nowNs) > 0, 'the pairing was lost at the power-up');
});

test('run log: the oldest slot is erased only with the motor off, after the pairing window', { skip: route !== 'a' && 'route (b) has no boot ROM: no flash writes' }, () => {
  const b = boardWith('firmware');
  const f = b.facts;
  b.setBattery(4.0);
  // Three power-ups with a short run each fill the three slots' headers.
  for (let i = 0; i < 3; i++) {
    if (i > 0) b.powerOn('power-on');
    b.runUntil(b.nowNs + 300 * MS);
    const on = sendOn(b, b.nowNs + GAP);
    b.runUntil(on.end + 500 * MS);
    sendOff(b, b.nowNs + GAP);
    b.runUntil(b.nowNs + 100 * MS);
  }
  assert.equal(b.flashChip.ops.filter((o) => o.op === 'erase').length, 0, 'blank slots need no erase');
  // The fourth power-up has no blank slot: it erases the oldest, block by
  // block, once the window has closed and the IR has been quiet; an On in
  // the window runs, with its records dropped until the slot is erased.
  b.powerOn('power-on');
  const boot = b.nowNs;
  const on = sendOn(b, boot + 1000 * MS);
  b.runUntil(on.end + 1000 * MS);
  sendOff(b, b.nowNs + GAP);
  const blocks = f.logSlotBytes / 65536;
  // Each block erase stalls the chip (lib/flash.js: 150 ms typical).
  b.runUntil(boot + (f.pairingWindowMs + 1000) * MS + 2 * blocks * b.flashChip.timing.blockEraseNs);
  // Its own slot first (the oldest log), then the next oldest, to be the
  // next power-up's blank slot; the newest log is kept for the readout.
  const erases = b.flashChip.ops.filter((o) => o.op === 'erase');
  assert.equal(erases.length, 2 * blocks, 'one erase per 64 KiB block of two slots');
  const slotOf = (e) => Math.floor((e.offset - f.logOffset) / f.logSlotBytes);
  const slots = [slotOf(erases[0]), slotOf(erases[blocks])];
  assert.notEqual(slots[0], slots[1]);
  assert.deepEqual(erases.map((e) => ((e.offset - f.logOffset) % f.logSlotBytes) / 65536), [3, 2, 1, 0, 3, 2, 1, 0], 'last block first');
  const slot = slots.join(' then ');
  for (const e of erases) {
    assert.ok(e.t >= boot + f.pairingWindowMs * MS, `an erase in the pairing window at ${(e.t - boot) / MS} ms`);
    assert.equal(b.motorAt(e.t), 0, 'an erase with the motor pin high');
    assert.ok(b.dutyIn(e.t - 10 * MS, e.t) === 0, 'an erase within 10 ms of a PWM pulse');
  }
  assert.deepEqual(b.flashStallViolations(), [], 'flash fetched while busy');
  // The watchdog, lengthened for each erase, did not reset the chip in its stall.
  assert.equal(b.resets.filter((r) => r.t > boot).length, 0, `resets: ${b.resets.map((r) => r.reason).join(', ')}`);
  perf('run log: fourth power-up, two oldest slots erased (4 blocks each), first erase after boot', `${((erases[0].t - boot) / MS).toFixed(0)} ms, slot ${slot}`);
  // The run in the window was counted as dropped; the readout is then the
  // newest earlier log, and the next power-up writes into the erased slot.
  const log = decodeLog(readOverUsb(b, 'LOG\n', { timeoutNs: 3000 * MS }));
  assert.equal(log.header.flags & 2, 2, 'an earlier power-up\'s log');
  assert.ok(log.records.length > 0);
});
