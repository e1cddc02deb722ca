// The motor, its tail and the two Hall latches, driven by the motor pin the
// firmware drives: the host's motor model (the `swimbot-motor` crate:
// winding R and L, back-EMF, rotor + tail inertia, viscous and Coulomb
// friction, the tail's load tau_0 + c w from the swimmer model, the ring's
// quadrature edge pattern), compiled to WebAssembly (motor/wasm) and loaded
// with Node's built-in WebAssembly API, one instance per rotor. Every step
// the mean motor voltage of the last millisecond goes in, held over the
// step as the host's simulation holds a PWM period's average.
//
// The motor is the robot file's calibrated one with tail 1's load
// (lib/motor.json, generated from host/data/robot.toml by the host's tests,
// which fail when it is stale), not the firmware's assumed line (175 mV
// intercept, 0.7 V/Hz): the controller has to learn it. The latches switch
// in Gray order (00, 01, 11, 10 forwards) at `edgesPerTurn` positions a
// turn, only while their power pin is high; unpowered, the open-drain
// outputs read high through the pull-ups (board.js).
import { existsSync, readFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
export const MOTOR = JSON.parse(readFileSync(join(here, 'motor.json'), 'utf8'));
export const WASM_PATH = resolve(here, '../../../target/wasm32-unknown-unknown/wasm/swimbot_motor_wasm.wasm');

let module = null;
function wasmModule() {
  if (!module) {
    if (!existsSync(WASM_PATH)) {
      throw new Error(`${WASM_PATH} missing: build it with \`cargo build -p swimbot-motor-wasm --target wasm32-unknown-unknown --profile wasm\` (scripts/prepare.mjs does)`);
    }
    module = new WebAssembly.Module(readFileSync(WASM_PATH));
  }
  return module;
}

/** A seized coupler's holding torque: ten times the motor's stall torque at 5 V. */
const SEIZED_FACTOR = 10;

export class Rotor {
  constructor(edgesPerTurn, motor = MOTOR) {
    this.edgesPerTurn = edgesPerTurn;
    this.motor = motor;
    this.wasm = new WebAssembly.Instance(wasmModule(), {}).exports;
    const m = motor;
    this.wasm.rotor_init(
      m.resistance_ohm,
      m.inductance_h,
      m.torque_constant_n_m_per_a,
      m.rotor_inertia_kg_m2,
      m.viscous_friction_n_m_s,
      m.coulomb_friction_n_m,
      m.load_inertia_kg_m2,
      m.load_tau0_n_m,
      m.load_damping_n_m_s,
      edgesPerTurn,
    );
    this.rateHz = 0;
    this._stalled = false;
    this._load = 1;
  }

  /** A seized coupler: a holding torque far beyond stall, so the rotor sticks whatever the drive. */
  get stalled() {
    return this._stalled;
  }
  set stalled(on) {
    this._stalled = on;
    const m = this.motor;
    const stall = (m.torque_constant_n_m_per_a * 5.0) / m.resistance_ohm;
    this.wasm.rotor_set_brake_n_m(on ? SEIZED_FACTOR * stall : 0);
  }

  /** The tail's load (tau_0 and c) against the nominal one. */
  get load() {
    return this._load;
  }
  set load(factor) {
    this._load = factor;
    this.wasm.rotor_set_load_scale(factor);
  }

  /** Mean motor voltage (V) that holds `hz` steadily against the present load. */
  voltsFor(hz) {
    return this.wasm.rotor_volts_for_rate(hz);
  }

  /** The load factor at which `volts` turns the tail at `hz` (NaN if none). */
  loadFor(volts, hz) {
    return this.wasm.rotor_load_scale_for(volts, hz);
  }

  get currentA() {
    return this.wasm.rotor_current_a();
  }

  /** Fixed position error of edge `i` in pitches (the ring's pole pattern). */
  setEdgeOffset(i, pitches) {
    this.wasm.rotor_set_edge_offset(i, pitches);
  }

  /** Turn for `dtNs` at mean voltage `v`: the crossings as [{ dtNs, a, b }] from the step's start. */
  advance(v, dtNs) {
    const n = this.wasm.rotor_step(v, dtNs * 1e-9);
    this.rateHz = this.wasm.rotor_rate_hz();
    const out = [];
    for (let i = 0; i < n; i++) {
      const levels = this.wasm.rotor_crossing_levels(i);
      out.push({ dtNs: this.wasm.rotor_crossing_after_s(i) * 1e9, a: (levels & 1) !== 0, b: (levels & 2) !== 0 });
    }
    return out;
  }
}
