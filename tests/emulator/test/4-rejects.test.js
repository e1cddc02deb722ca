// Scenario 4: frames the robot must ignore (wrong address, corrupted inverted
// byte, repeat codes alone, truncated frames, random edge noise) change
// nothing, whether the motor is off or running; the decoder still accepts a
// good frame afterwards.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { RUNNING_DUTY, perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { necFrame, necRepeat, noise } from '../lib/nec.js';
import { dutyBins, ms, pct, sendFrame, sendOff, sendOn } from '../lib/steps.js';

const GAP = 30 * MS;

/** The frames to ignore, for command `cmd`. */
function junk(b, cmd) {
  const NEC_ADDRESS = b.facts.necAddress;
  const good = necFrame(NEC_ADDRESS, cmd);
  return [
    ['wrong address 0x01', necFrame(0x01, cmd)],
    ['wrong address 0x80', necFrame(0x80, cmd)],
    ['corrupted inverted command', necFrame(NEC_ADDRESS, cmd, { invCommand: ~cmd & 0xff ^ 0x01 })],
    ['corrupted inverted address', necFrame(NEC_ADDRESS, cmd, { invAddress: 0x7f })],
    ['repeat code alone', necRepeat()],
    ['repeat code alone (2nd)', necRepeat()],
    ['repeat code alone (3rd)', necRepeat()],
    ['truncated frame (first 40 edges)', good.slice(0, 40)],
    ['random edge noise (80 pulses)', noise(0x5eed, 80)],
    ['random edge noise (80 pulses, 2nd seed)', noise(0xbeef, 80)],
  ];
}

function playAll(b, frames) {
  const played = [];
  for (const [name, w] of frames) {
    const f = sendFrame(b, b.nowNs + GAP, w);
    played.push({ name, ...f });
  }
  b.runUntil(b.nowNs + GAP);
  return played;
}

test('ignored frames while the motor is off: it stays off', () => {
  const b = boardWith('firmware');
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  const t0 = b.nowNs;
  const played = playAll(b, junk(b, b.facts.necCmdOn));
  b.runUntil(b.nowNs + 300 * MS);
  for (const p of played) {
    const rises = b.motorEdgesIn(p.start, p.end + GAP).filter((e) => e.v === 1);
    assert.equal(rises.length, 0, `motor pulsed after "${p.name}"`);
  }
  assert.equal(b.motorEdgesIn(t0, b.nowNs).length, 0, 'motor pin changed');
  assert.equal(b.resets.length, 1, 'the chip reset during the junk frames');

  const on = sendOn(b, b.nowNs + GAP);
  b.runUntil(on.end + 50 * MS);
  assert.ok(b.firstRiseAfter(on.start) !== undefined, 'a good On frame after the junk did not start the motor');
});

test('ignored frames while the motor runs: duty unchanged', () => {
  const b = boardWith('firmware');
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  const on = sendOn(b, 20 * MS);
  // Past the rate loop's learning of the line (8-rate), so the duty is the
  // held one, and any change would be the junk's.
  b.runUntil(on.end + 3000 * MS);
  const held = b.dutyIn(on.end + 2900 * MS, on.end + 3000 * MS);
  assert.ok(held > RUNNING_DUTY, `motor not running (duty ${pct(held)})`);
  const t0 = b.nowNs;
  const played = playAll(b, junk(b, b.facts.necCmdOff));
  for (const bin of dutyBins(b, t0, b.nowNs, 2 * MS)) {
    const p = played.find((x) => bin.t >= x.start && bin.t < x.end + GAP);
    assert.ok(Math.abs(bin.duty - held) <= 0.03, `duty ${pct(bin.duty)} (held ${pct(held)}) at ${ms(bin.t - t0)}${p ? ` during/after "${p.name}"` : ''}`);
  }
  assert.equal(b.resets.length, 1, 'the chip reset during the junk frames');

  const off = sendOff(b, b.nowNs + GAP);
  b.runUntil(off.end + 20 * MS);
  assert.equal(b.motorEdgesIn(off.end + 1 * MS, b.nowNs).length, 0, 'a good Off frame after the junk did not stop the motor');
  assert.equal(b.motorAt(b.nowNs), 0);
});

test('IR edges closer than the interrupt: none lost between reading and clearing the latches', () => {
  // Short glitches (a low pulse of 0.2-1.4 us, swept in 4 ns steps) put the
  // second edge at every point of the interrupt handler that serves the
  // first, including between its read of the edge latches and its clear.
  // The board counts an edge lost when the firmware clears a latch that no
  // read had shown it.
  const b = boardWith('firmware');
  b.setBattery(3.9);
  b.runUntil(20 * MS);
  let t = b.nowNs;
  for (let i = 0; i < 300; i++) {
    t += 1 * MS;
    b.playIr(t, [[200 + 4 * i, false]]);
  }
  b.runUntil(t + 20 * MS);
  perf('IR glitch edges lost between latch read and clear (300 pulses, 0.2-1.4 us)', b.irEdgesLost, '');
  assert.equal(b.irEdgesLost, 0, `${b.irEdgesLost} IR edges cleared unseen`);
  assert.equal(b.motorEdgesIn(0, b.nowNs).filter((e) => e.v === 1).length, 0, 'glitches moved the motor');
});
