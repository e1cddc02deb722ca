// Scenario 9: the remote's rate keys (firmware/README.md's key map) on the
// chip, with the rotor of lib/rotor.js closing the rate loop. Key spam
// with the motor off starts nothing; a preset key while running is a
// set-point step the loop follows; a held step key (one frame, then repeat
// frames) steps once.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { perf } from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { necFrame, necRepeat } from '../lib/nec.js';
import { ms, sendFrame, sendOn } from '../lib/steps.js';

const GAP = 40 * MS;

/** One key press of `cmd` held for `repeats` repeat frames. */
function press(b, cmd, repeats = 0) {
  sendFrame(b, b.nowNs + GAP, necFrame(b.facts.necAddress, cmd));
  for (let i = 0; i < repeats; i++) sendFrame(b, b.nowNs + GAP, necRepeat());
}

/** Settling time into 2 % of `setHz` for good, and the overshoot of the step from `fromHz`. */
function stepResponse(b, t0, fromHz, setHz) {
  const trace = b.rateTrace.filter((x) => x.t >= t0);
  let settled = null;
  for (let i = trace.length - 1; i >= 0; i--) {
    if (Math.abs(trace[i].hz / setHz - 1) > 0.02) break;
    settled = trace[i].t;
  }
  const peak = Math.max(...trace.map((x) => x.hz));
  return { settleNs: settled === null ? null : settled - t0, overshoot: Math.max(0, (peak - setHz) / (setHz - fromHz)) };
}

test('rate keys: no start from keys, a preset step, a held step key steps once', async (t) => {
  const b = boardWith('firmware');
  const f = b.facts;
  b.setBattery(3.9);
  b.runUntil(20 * MS);

  await t.test('key spam with the motor off starts nothing', () => {
    const t0 = b.nowNs;
    for (const cmd of [f.necCmdPreset1, f.necCmdPreset5, f.necCmdFaster, f.necCmdSlower, f.necCmdPreset5]) press(b, cmd, 3);
    b.runUntil(b.nowNs + 300 * MS);
    assert.equal(b.motorEdgesIn(t0, b.nowNs).length, 0, 'a rate key moved the motor');
    assert.equal(b.hallPowered, false);
  });

  // The spam left preset 5 (1.5 Hz) selected: On runs there.
  const on = sendOn(b, b.nowNs + GAP);
  b.runUntil(on.end + 4000 * MS);
  const hz5 = b.rateIn(on.end + 3000 * MS, on.end + 4000 * MS);

  await t.test('the key chosen while off is the set-point at On', () => {
    perf('rate after On with preset 5 chosen while off', hz5.toFixed(3), 'Hz');
    assert.ok(Math.abs(hz5 / 1.5 - 1) <= 0.01, `rate ${hz5.toFixed(3)} Hz, preset 5 is 1.5 Hz`);
  });

  await t.test('a preset key while running: the loop follows the step', () => {
    press(b, f.necCmdPreset1);
    const tKey = b.nowNs;
    b.runUntil(tKey + 4000 * MS);
    const r = stepResponse(b, tKey, 1.5, 0.5);
    assert.ok(r.settleNs !== null, 'never settled at 0.5 Hz');
    perf('set-point step 1.5 -> 0.5 Hz (key 1): end of frame to within 2 % for good', ms(r.settleNs), '');
    perf('set-point step 1.5 -> 0.5 Hz: overshoot (of the step)', `${(100 * r.overshoot).toFixed(2)} %`, '');
    const steady = b.rateIn(tKey + 3000 * MS, tKey + 4000 * MS);
    assert.ok(Math.abs(steady / 0.5 - 1) <= 0.01, `steady ${steady.toFixed(4)} Hz`);
    assert.ok(r.overshoot <= 0.1, `overshoot ${(100 * r.overshoot).toFixed(2)} % of the step`);
  });

  await t.test('a held step key (1 frame + 10 repeats) steps once: 0.5 -> 0.55 Hz', () => {
    press(b, f.necCmdFaster, 10);
    const tKey = b.nowNs;
    b.runUntil(tKey + 3000 * MS);
    const steady = b.rateIn(tKey + 2000 * MS, tKey + 3000 * MS);
    perf('held VOL+ (1 frame + 10 repeats) from 0.5 Hz: rate after 3 s', steady.toFixed(4), 'Hz');
    assert.ok(Math.abs(steady / 0.55 - 1) <= 0.01, `rate ${steady.toFixed(4)} Hz, want 0.55 Hz (one step)`);
  });
});
