// Scenario 19: the board's motor is the host's. The WebAssembly rotor
// (lib/rotor.js, the `swimbot-motor` crate) stepped at 1 ms as the board
// steps it reaches the steady rates and currents the host computes for the
// calibrated robot file's motor and tail 1 (lib/motor.json, written and
// checked by host/tests/emulator_motor.rs); its edges come in Gray order,
// 16 a turn; a seized coupler holds it and a heavier tail slows it.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { perf } from '../lib/contract.js';
import { MOTOR, Rotor } from '../lib/rotor.js';

const STEP_NS = 1_000_000;

function run(rotor, v, seconds) {
  const edges = [];
  for (let i = 0; i < seconds * 1000; i++) edges.push(...rotor.advance(v, STEP_NS));
  return edges;
}

test('the WebAssembly rotor is the host motor', async (t) => {
  await t.test('steady rate and current equal the host model at each operating point', () => {
    let worst = 0;
    for (const p of MOTOR.steady) {
      const r = new Rotor(16);
      run(r, p.volts, 2);
      const err = Math.max(Math.abs(r.rateHz / p.rate_hz - 1), Math.abs(r.currentA / p.current_a - 1));
      worst = Math.max(worst, err);
      assert.ok(err < 1e-6, `${p.volts} V: ${r.rateHz} Hz ${r.currentA} A, host ${p.rate_hz} Hz ${p.current_a} A`);
      assert.ok(Math.abs(r.voltsFor(p.rate_hz) / p.volts - 1) < 1e-9, 'the steady line inverts the host point');
    }
    perf('WebAssembly rotor vs host steady motor (4 points): largest relative difference', worst.toExponential(1), '');
  });

  await t.test('edges: Gray order forwards, 16 a turn', () => {
    const r = new Rotor(16);
    const edges = run(r, 3.0, 5);
    const gray = ['00', '01', '11', '10'];
    let state = 0;
    for (const e of edges) {
      state = (state + 1) % 4;
      assert.equal(`${+e.a}${+e.b}`, gray[state]);
      assert.ok(e.dtNs >= 0 && e.dtNs <= STEP_NS);
    }
    const turns = r.wasm.rotor_turns();
    assert.equal(edges.length, Math.floor(turns * 16));
  });

  await t.test('a seized coupler holds at full drive; a heavier tail turns slower', () => {
    const seized = new Rotor(16);
    seized.stalled = true;
    assert.equal(run(seized, 3.7, 5).length, 0);
    const free = new Rotor(16);
    run(free, 3.0, 1);
    const heavy = new Rotor(16);
    heavy.load = 20;
    run(heavy, 3.0, 1);
    assert.ok(heavy.rateHz < 0.5 * free.rateHz, `${heavy.rateHz} vs ${free.rateHz} Hz`);
  });
});
