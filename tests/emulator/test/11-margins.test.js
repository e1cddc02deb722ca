// Scenario 11: timing margins. The rate-key scenario once failed after a
// change that only lengthened the IR handler by a few cycles: the motor
// stopped 2.3 s after a 1.5 -> 0.5 Hz key. It was not the stall fault (the
// Hall edges came every 133 ms, the stall time is 5 s) but a watchdog reset:
// a pass woken by a Hall edge ended on the tick of the 1 ms wake-up alarm,
// the alarm fired after the sleep had masked interrupts and before its WFI,
// and rp2040js then slept through the pending interrupt (a Cortex-M0+ does
// not), so nothing fed the watchdog. lib/board.js now wakes WFI on a pending
// interrupt. This scenario pins the race down on purpose, then repeats the
// step down with longer IR handlers and goes on to the lowest set-point.
// Last, the stall fault's own race: a Hall edge stamped after the pass's
// timer read read as 71 minutes old (rate::control; that did stop the
// motor, in the run-log scenario, once the firmware's timing moved).
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS, US } from '../lib/board.js';
import { perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { necFrame } from '../lib/nec.js';
import { sendFrame, sendOn } from '../lib/steps.js';

const GAP = 40 * MS;
const resetsOf = (b) => b.resets.map((r) => r.reason).join(', ');

test('an IR edge at any moment before the wake-up alarm loses no wake-up', () => {
  const b = boardWith('firmware');
  b.setBattery(3.9);
  b.runUntil(300 * MS);
  // Pass lengths vary with what the edge brings, so sweep the edge over the
  // last 80 us before the alarm in 0.25 us steps: the lost wake-ups were
  // windows of 0.25-0.5 us at 18, 36, 38, 43 and 61 us before it.
  let swept = 0;
  for (let d = 0; d <= 80 * US; d += 0.25 * US) {
    // Asleep, with at least d + 5 us to the alarm.
    while (!(b.mcu.core.waiting && b.wakeAlarmNs - d > b.nowNs + 5 * US)) b.runFor(1 * US);
    const alarm = b.wakeAlarmNs;
    b.at(alarm - d, () => b.setIr(!b.irLevel));
    b.runUntil(alarm + 2 * MS);
    swept++;
  }
  b.runFor(200 * MS); // longer than the watchdog's period
  assert.ok(swept > 300, `only ${swept} edges placed`);
  assert.deepEqual(b.resets.map((r) => r.reason), ['power-on'], `resets: ${resetsOf(b)}`);
});

/** On at preset 5 (1.5 Hz), then key 1 (0.5 Hz) and VOL- six times (0.2 Hz, the lowest set-point). */
function stepDown(extraCycles) {
  const b = boardWith('firmware');
  b.irqExtraCycles = extraCycles;
  const f = b.facts;
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  sendFrame(b, b.nowNs + GAP, necFrame(f.necAddress, f.necCmdPreset5));
  const on = sendOn(b, b.nowNs + GAP);
  b.runUntil(on.end + 3000 * MS);
  sendFrame(b, b.nowNs + GAP, necFrame(f.necAddress, f.necCmdPreset1));
  const tKey = b.nowNs;
  b.runUntil(tKey + 3000 * MS);
  const at05 = b.rateIn(tKey + 2000 * MS, tKey + 3000 * MS);
  for (let i = 0; i < 6; i++) sendFrame(b, b.nowNs + GAP, necFrame(f.necAddress, f.necCmdSlower));
  const tLow = b.nowNs;
  b.runUntil(tLow + 12000 * MS);
  const at02 = b.rateIn(tLow + 10000 * MS, tLow + 12000 * MS);
  // The longest quiet stretch between Hall edges from the key on: what the
  // stall time has to cover.
  const edges = b.hallEdgeTimes.filter((t) => t >= tKey);
  let longestGapNs = 0;
  for (let i = 1; i < edges.length; i++) longestGapNs = Math.max(longestGapNs, edges[i] - edges[i - 1]);
  return { b, at05, at02, longestGapNs, running: b.dutyIn(b.nowNs - 100 * MS, b.nowNs) > 0 };
}

for (const extra of [15]) {
  test(`step down 1.5 -> 0.5 -> 0.2 Hz with the IR handler ${extra} cycles longer`, () => {
    const { b, at05, at02, longestGapNs, running } = stepDown(extra);
    assert.deepEqual(b.resets.map((r) => r.reason), ['power-on'], `resets: ${resetsOf(b)}`);
    assert.ok(running, 'the motor stopped');
    assert.ok(Math.abs(at05 / 0.5 - 1) <= 0.01, `at 0.5 Hz: ${at05.toFixed(4)} Hz`);
    assert.ok(Math.abs(at02 / 0.2 - 1) <= 0.01, `at 0.2 Hz: ${at02.toFixed(4)} Hz`);
    const stallNs = b.facts.stallMs * MS;
    perf(`step down to 0.2 Hz (+${extra} IRQ cycles): longest Hall-edge gap against the ${b.facts.stallMs} ms stall time`, (longestGapNs / MS).toFixed(0), 'ms');
    assert.ok(longestGapNs > 0 && longestGapNs < stallNs / 2, `a ${(longestGapNs / MS).toFixed(0)} ms gap`);
  });
}

test('a Hall edge just after a pass has read the timer is a fresh edge, not a stall', () => {
  const b = boardWith('firmware');
  const f = b.facts;
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  const on = sendOn(b, b.nowNs + GAP);
  // Past the soft start and the stall time: from here a wrapped edge age is a stall.
  b.runUntil(on.end + 250 * MS + f.stallMs * MS + 500 * MS);
  // The rotor's own edges stop; this test places each next quadrature edge
  // itself, 0-40 us after a wake-up alarm (1 us steps, one edge every
  // ~100 ms: 0.6 Hz), where a pass reads the timer and then drains the queue.
  b.rotor.stalled = true;
  const gray = [[false, false], [false, true], [true, true], [true, false]];
  let k = gray.findIndex(([a, c]) => a === b.hallLevels[0] && c === b.hallLevels[1]);
  for (let d = 0; d <= 40 * US; d += 1 * US) {
    b.runFor(100 * MS);
    while (!(b.mcu.core.waiting && b.wakeAlarmNs - b.nowNs > 5 * US)) b.runFor(1 * US);
    k = (k + 1) % 4;
    const [a, c] = gray[k];
    b.at(b.wakeAlarmNs + d, () => b.setHall(a, c));
    b.runUntil(b.wakeAlarmNs + d + 2 * MS);
    assert.ok(b.dutyIn(b.nowNs - 1 * MS, b.nowNs) > 0, `the motor stopped with an edge ${d / US} us after the alarm`);
  }
  assert.deepEqual(b.resets.map((r) => r.reason), ['power-on']);
});
