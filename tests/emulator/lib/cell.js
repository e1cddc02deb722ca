// The robot's cell as the battery ADC sees it, driven by the motor pin the
// firmware actually drives: at rest the open-circuit voltage; during an
// on-pulse the current rises from zero (discontinuous conduction: the
// motor's L/R is a tenth of the 40 us period) towards V_oc / (R_motor +
// R_cell), and the terminal sags by R_cell times it. Parameters: the host
// models' 70 mAh cell (0.6 ohm) and 6 mm coreless motor (7 ohm, 25 uH),
// host/src/robot/battery.rs and motor/src/dc_motor.rs. Back-EMF is neglected (a few mV at
// the tail's ~1 Hz, direct drive), and so is the charge drawn (a test's
// seconds take under 1 % of 70 mAh).
export const CELL_OHM = 0.6;
export const MOTOR_OHM = 7.0;
export const MOTOR_H = 25e-6;

export class Cell {
  constructor(ocvV) {
    this.ocvV = ocvV;
  }

  /** Terminal voltage `sinceRiseNs` into an on-pulse (pin high), or at rest (null). */
  terminalV(sinceRiseNs) {
    if (sinceRiseNs === null) return this.ocvV;
    const r = MOTOR_OHM + CELL_OHM;
    const tauNs = (MOTOR_H / r) * 1e9;
    const current = (this.ocvV / r) * (1 - Math.exp(-sinceRiseNs / tauNs));
    return this.ocvV - CELL_OHM * current;
  }

  /** Terminal voltage with the on-current settled (late in a long on-pulse). */
  get loadedV() {
    return (this.ocvV * MOTOR_OHM) / (MOTOR_OHM + CELL_OHM);
  }
}
