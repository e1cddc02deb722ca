// Scenario 2: an NEC On frame starts the motor: PWM at 25 kHz, soft-start ramp
// over 250 ms to the rate controller's first duty (its feed-forward line
// before it has learned the tail), holds it, and once the rate loop has
// learned the line (lib/rotor.js) follows the battery voltage (the rate
// held, the motor's voltage with it). The cell sags during each on-pulse
// (lib/cell.js); the motor sees duty x the loaded voltage. Measures the command-to-PWM latency
// and the CPU cycles the IR interrupt takes per edge.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS, US } from '../lib/board.js';
import {
  MOTOR_TARGET_TOL,
  ON_LATENCY_NS,
  PWM_FREQ_HZ,
  PWM_FREQ_TOL,
  PWM_MIN_COUNTS,
  SOFT_START_NS,
  SOFT_START_TOL,
  perf,
} from '../lib/contract.js';
import { boardWith } from '../lib/images.js';
import { dutyBins, ms, pct, sendOn } from '../lib/steps.js';

test('On frame: 25 kHz PWM, soft-start, hold, voltage compensation under rate control', async (t) => {
  const b = boardWith('firmware');
  b.setBattery(4.0);
  b.runUntil(50 * MS);
  const irStart = 50 * MS;
  const frame = sendOn(b, irStart);
  const t0 = frame.end;
  b.runUntil(t0 + 2 * MS);
  const irq = b.irqCyclesSince(irStart);
  const edges = b.irEdgeTimes.filter((x) => x >= irStart).length;
  b.runUntil(t0 + 600 * MS);

  await t.test('IR interrupt cost per edge', () => {
    const handler = b.irqHandler();
    console.log(`emulator: IO_IRQ_BANK0 handler 0x${handler.addr.toString(16)} ${handler.name}`);
    assert.ok(irq.length > 0, 'no IO_IRQ_BANK0 interrupt ran while the IR frame was played');
    const total = irq.reduce((s, e) => s + e.cycles, 0);
    const max = Math.max(...irq.map((e) => e.cycles));
    perf('IR frame edges', edges, '');
    assert.equal(edges, 68, 'harness: an NEC frame has 68 edges');
    perf('IO_IRQ_BANK0 entries during the frame', irq.length, '');
    perf('IR IRQ cycles per edge (mean, emulated instructions, excl. ~15-cycle exception entry)', (total / edges).toFixed(1), 'cycles');
    perf('IR IRQ cycles, longest single handler run', max, 'cycles');
    perf('IR IRQ CPU time per edge at 125 MHz', ((total / edges / 125e6) * 1e6).toFixed(2), 'us');
  });

  const first = b.firstRiseAfter(irStart);
  await t.test('PWM appears after the frame (latency)', () => {
    assert.ok(first !== undefined, 'no PWM edge on GPIO16 within 600 ms of the On frame');
    assert.ok(first >= t0 - 1 * MS, `PWM started ${ms(t0 - first)} before the frame ended`);
    perf('command-to-PWM latency (end of On frame to first rising edge on GPIO16)', ((first - t0) / US).toFixed(1), 'us');
    assert.ok(first - t0 < ON_LATENCY_NS, `PWM started ${ms(first - t0)} after the frame (> 1 ms)`);
  });

  const holdFrom = t0 + 350 * MS;
  const holdTo = t0 + 550 * MS;
  const held = b.dutyIn(holdFrom, holdTo);

  await t.test('PWM frequency 25 kHz +-1 %, >= 10-bit resolution', () => {
    const f = b.pwmFreqIn(holdFrom, holdTo);
    perf('PWM frequency (mean over 200 ms)', f.hz.toFixed(1), 'Hz');
    assert.ok(f.periods > 100, `only ${f.periods} PWM periods in 200 ms`);
    assert.ok(Math.abs(f.hz / PWM_FREQ_HZ - 1) <= PWM_FREQ_TOL, `PWM at ${f.hz.toFixed(1)} Hz`);
    assert.ok(Math.abs(f.minHz / PWM_FREQ_HZ - 1) <= PWM_FREQ_TOL, `slowest period at ${f.minHz.toFixed(1)} Hz`);
    assert.ok(Math.abs(f.maxHz / PWM_FREQ_HZ - 1) <= PWM_FREQ_TOL, `fastest period at ${f.maxHz.toFixed(1)} Hz`);
    const counts = b.pwmSlice0.top + 1;
    perf('PWM counts per period (slice 0 TOP + 1)', counts, '');
    assert.ok(counts >= PWM_MIN_COUNTS, `slice 0 TOP + 1 = ${counts} < 1024`);
  });

  await t.test('duty holds after the ramp (the unlearned line: no rate window yet)', () => {
    perf('held duty after the ramp at V_bat 4.0 V, before the first rate (3.68 V loaded)', pct(held), '');
    for (const bin of dutyBins(b, holdFrom, holdTo, 10 * MS)) {
      assert.ok(Math.abs(bin.duty - held) <= 0.015, `duty ${pct(bin.duty)} at ${ms(bin.t - t0)} after the frame, average ${pct(held)}`);
    }
  });

  await t.test('soft-start ramp 250 ms +-10 %', () => {
    assert.ok(held > 0.05, `no held duty to ramp to (${pct(held)})`);
    const bins = dutyBins(b, t0, t0 + 350 * MS, 1 * MS);
    const reach = bins.find((x) => x.duty >= 0.98 * held);
    assert.ok(reach, 'duty never reached 98 % of the held value');
    const ramp = reach.t + 1 * MS - t0;
    perf('soft-start: end of frame to 98 % of the held duty', (ramp / MS).toFixed(1), 'ms');
    assert.ok(
      Math.abs(ramp / SOFT_START_NS - 1) <= SOFT_START_TOL,
      `ramp took ${ms(ramp)}, want 250 ms +-10 %`,
    );
    const mid = b.dutyIn(t0 + ramp / 2 - 5 * MS, t0 + ramp / 2 + 5 * MS);
    perf('duty at half the ramp time', pct(mid), '');
    assert.ok(mid >= 0.3 * held && mid <= 0.7 * held, `duty ${pct(mid)} at half the ramp (want 30-70 % of ${pct(held)}): not a ramp`);
    const coarse = dutyBins(b, t0, t0 + ramp, 10 * MS);
    for (let i = 1; i < coarse.length; i++) {
      assert.ok(coarse[i].duty >= coarse[i - 1].duty - 0.02, `duty fell from ${pct(coarse[i - 1].duty)} to ${pct(coarse[i].duty)} during the ramp`);
    }
  });

  await t.test('battery conversions land mid on-pulse (the cell ripples with the PWM)', () => {
    // lib/cell.js sags the cell by ~0.3 V during each on-pulse: a
    // conversion at a random phase would read either level.
    const reads = b.adcReads.filter((r) => r.t >= holdFrom && r.t < holdTo);
    assert.ok(reads.length >= 8, `${reads.length} conversions in 200 ms`);
    const phases = reads.map((r) => r.phase);
    perf('battery conversion phase, motor running (fraction of the PWM period)', `${Math.min(...phases).toFixed(3)}-${Math.max(...phases).toFixed(3)}, on-pulse 0-${held.toFixed(3)}`, '');
    for (const r of reads) {
      assert.equal(r.pin, 1, `conversion at ${ms(r.t - t0)} after the frame during the off-time (phase ${r.phase.toFixed(3)})`);
      assert.ok(Math.abs(r.phase - held / 2) < 0.08, `conversion at phase ${r.phase.toFixed(3)}, want mid on-pulse ${(held / 2).toFixed(3)}`);
    }
    const v = reads.map((x) => x.v);
    perf('battery reading, motor running (cell 4.0 V open circuit)', `${Math.min(...v).toFixed(3)}-${Math.max(...v).toFixed(3)}`, 'V');
    assert.ok(Math.max(...v) - Math.min(...v) < 0.01, 'the readings spread: not at one phase');
  });

  await t.test('rate held: the motor voltage and the duty follow the battery (4.0 V -> 3.6 V -> 4.2 V)', () => {
    // The loop has learned the rotor's line by now (8-rate measures when).
    b.runUntil(t0 + 4000 * MS);
    const tA = b.nowNs;
    const d40 = b.dutyIn(tA - 200 * MS, tA);
    b.setBattery(3.6);
    b.runUntil(tA + 400 * MS);
    const d36 = b.dutyIn(tA + 300 * MS, tA + 400 * MS);
    const r36 = b.rateIn(tA + 300 * MS, tA + 400 * MS);
    b.setBattery(4.2);
    b.runUntil(tA + 800 * MS);
    const d42 = b.dutyIn(tA + 700 * MS, tA + 800 * MS);
    const r42 = b.rateIn(tA + 700 * MS, tA + 800 * MS);
    perf('duty at V_bat 4.0 / 3.6 / 4.2 V, rate held', `${pct(d40)} / ${pct(d36)} / ${pct(d42)}`, '');
    const set = b.facts.defaultRateMhz / 1000;
    const lineV = b.rotor.voltsFor(set);
    for (const [v, d, r] of [[3.6, d36, r36], [4.2, d42, r42]]) {
      const loaded = (v * b.cell.loadedV) / b.cell.ocvV;
      assert.ok(Math.abs((d * loaded) / lineV - 1) <= MOTOR_TARGET_TOL, `average motor voltage ${(d * loaded).toFixed(3)} V at ${v} V (duty ${pct(d)}), the rotor needs ${lineV.toFixed(3)} V`);
      assert.ok(Math.abs(r / set - 1) <= 0.02, `rate ${r.toFixed(3)} Hz at ${v} V`);
      const ratio = d / d40;
      assert.ok(Math.abs(ratio / (4.0 / v) - 1) <= 0.03, `duty ratio ${ratio.toFixed(3)} vs ${(4.0 / v).toFixed(3)} expected at ${v} V`);
    }
  });
});
