// The motor, its tail and the two Hall latches, driven by the motor pin the
// firmware drives. The loaded motor is static on the sensor's time scale
// (mechanical time constant ~0.2 ms against a ~1 s turn), so its rate
// follows the mean motor voltage over the last millisecond along a line,
// f = (V - V_0) / s (docs/rate-sensing.md). The line here is deliberately
// not the firmware's: V_0 = 0.25 V (the firmware assumes 0.175 V) and
// s = 2.1 V/Hz (inside the 1.9-5.1 V/Hz the paper's observed rates give;
// the firmware starts from 0.7 V/Hz), so the controller has to learn it.
// The latches switch in quadrature (Gray order 00, 01, 11, 10 forwards)
// at `edgesPerTurn` positions a turn, only while their power pin is high;
// unpowered, the open-drain outputs read high through the pull-ups.
export const LINE_V0 = 0.25;
export const LINE_SLOPE_V_PER_HZ = 2.1;
const GRAY = [
  [false, false],
  [false, true],
  [true, true],
  [true, false],
];

export class Rotor {
  constructor(edgesPerTurn) {
    this.edgesPerTurn = edgesPerTurn;
    this.turns = 0;
    this.rateHz = 0;
    /** A seized coupler: the rotor does not turn whatever the drive. */
    this.stalled = false;
    /** The tail's load against the nominal one: the line's slope times this. */
    this.load = 1;
  }

  /** The steady rate at mean motor voltage `v`. */
  static rateAt(v) {
    return Math.max(0, (v - LINE_V0) / LINE_SLOPE_V_PER_HZ);
  }

  /** Turn for `dtNs` at mean voltage `v`: the crossings as [{ dtNs, a, b }] from the step's start. */
  advance(v, dtNs) {
    this.rateHz = this.stalled ? 0 : Rotor.rateAt(v) / this.load;
    const from = this.turns * this.edgesPerTurn;
    this.turns += this.rateHz * dtNs * 1e-9;
    const to = this.turns * this.edgesPerTurn;
    const out = [];
    for (let k = Math.floor(from) + 1; k <= to; k++) {
      const [a, b] = GRAY[k % 4];
      out.push({ dtNs: ((k - from) / (to - from)) * dtNs, a, b });
    }
    return out;
  }
}
