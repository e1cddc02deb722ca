// NEC IR frames as the IR receiver (TSOP-style, active low) outputs them:
// a carrier burst ("mark") pulls the pin LOW, a space leaves it HIGH.
// Waveforms are [[durationNs, level], ...]; the pin returns high at the end.
import { US } from './board.js';

export const T = 562.5 * US; // NEC time unit
export const LEADER_MARK = 16 * T; // 9 ms
export const LEADER_SPACE = 8 * T; // 4.5 ms
export const REPEAT_SPACE = 4 * T; // 2.25 ms

/** A full NEC frame: address, ~address, command, ~command, each LSB first; inverted bytes can be overridden to corrupt the frame. */
export function necFrame(address, command, { invAddress = ~address & 0xff, invCommand = ~command & 0xff } = {}) {
  const w = [
    [LEADER_MARK, false],
    [LEADER_SPACE, true],
  ];
  for (const byte of [address, invAddress, command, invCommand]) {
    for (let bit = 0; bit < 8; bit++) {
      w.push([T, false]);
      w.push([(byte >> bit) & 1 ? 3 * T : T, true]);
    }
  }
  w.push([T, false]); // stop mark; the frame ends on its rising edge
  return w;
}

/** An NEC repeat code (sent by a remote while a key is held). */
export function necRepeat() {
  return [
    [LEADER_MARK, false],
    [REPEAT_SPACE, true],
    [T, false],
  ];
}

export function duration(waveform) {
  return waveform.reduce((s, [d]) => s + d, 0);
}

/** Deterministic PRNG (mulberry32) so noise tests are reproducible. */
export function rng(seed) {
  let a = seed >>> 0;
  return () => {
    a = (a + 0x6d2b79f5) >>> 0;
    let t = a;
    t = Math.imul(t ^ (t >>> 15), t | 1);
    t ^= t + Math.imul(t ^ (t >>> 7), t | 61);
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
}

/** Random glitches: `count` low pulses of 5 us..3 ms separated by 50 us..5 ms high gaps. */
export function noise(seed, count) {
  const r = rng(seed);
  const w = [];
  for (let i = 0; i < count; i++) {
    w.push([(5 + r() * 2995) * US, false]);
    w.push([(50 + r() * 4950) * US, true]);
  }
  return w;
}
