// The firmware's behaviour contract: the required
// behaviour and the tolerances the emulator scenarios accept. Board facts
// (pins, divider, reference, NEC codes, the watchdog period the image uses)
// are not repeated here: each Board reads them from its image
// (`board.facts`, lib/facts.js); 1-reset checks the image's facts meet
// these requirements.
import { appendFileSync } from 'node:fs';
import { MS } from './board.js';

export const PWM_FREQ_HZ = 25_000;
export const PWM_FREQ_TOL = 0.01; // +-1 %
export const PWM_MIN_COUNTS = 1024; // >= 10-bit duty resolution: TOP + 1 >= 1024

export const DEFAULT_RATE_HZ = 1.0; // the set-point after power-up
export const HALL_EDGES_PER_TURN = 16; // two latches in quadrature, 8-pole ring
// Under rate control the motor's voltage is what holds the set-point: the
// rotor's steady voltage (lib/rotor.js) at the set-point, +-5 % once learned.
export const MOTOR_TARGET_TOL = 0.05; // +-5 % on the average motor voltage
// "The motor runs": a duty clearly above zero. The rate controller's first
// duty after the soft start, on the lightest load's line before it has
// measured a rate, is about 23 % at 4.0 V (2-on); learned, about 64 %.
export const RUNNING_DUTY = 0.1;
export const SOFT_START_NS = 250 * MS;
export const SOFT_START_TOL = 0.1; // +-10 %

export const ON_LATENCY_NS = 1 * MS; // end of the On frame to the first PWM edge
export const ASLEEP_RUNNING_MIN = 0.95; // the core >= 95 % asleep with the motor running
export const OFF_DEADLINE_NS = 1 * MS; // duty 0 within 1 ms of the end of the Off frame

export const CUTOFF_V = 3.3; // low-battery cut-off, under load
export const CUTOFF_DEBOUNCE_NS = 1000 * MS; // ~1 s
export const WATCHDOG_MIN_NS = 50 * MS; // what the 1 ms pass allows
export const WATCHDOG_MAX_NS = 100 * MS;
export const FAILSAFE_DEADLINE_NS = 1 * MS; // a panic: gate low within 1 ms

/** Prints one measured number; also collected for the summary at the end of `npm test` (scripts/run.mjs). */
export function perf(name, value, unit) {
  const line = `${name} = ${value}${unit ? ` ${unit}` : ''}`;
  console.log(`emulator perf: ${line}`);
  if (process.env.SWIMBOT_EMU_PERF_LOG) appendFileSync(process.env.SWIMBOT_EMU_PERF_LOG, `${line}\n`);
}
