// Steps shared by the scenarios.
import { MS } from './board.js';
import { necFrame } from './nec.js';

/** Plays an NEC frame starting at absolute time t, runs until it has ended; returns { start, end }. */
export function sendFrame(board, t, waveform) {
  const end = board.playIr(t, waveform);
  board.runUntil(end);
  return { start: t, end };
}

export const sendOn = (b, t) => sendFrame(b, t, necFrame(b.facts.necAddress, b.facts.necCmdOn));
export const sendOff = (b, t) => sendFrame(b, t, necFrame(b.facts.necAddress, b.facts.necCmdOff));

/** Duty in consecutive bins of `binNs` over [t0, t1). */
export function dutyBins(b, t0, t1, binNs = 1 * MS) {
  const out = [];
  for (let t = t0; t + binNs <= t1; t += binNs) out.push({ t, duty: b.dutyIn(t, t + binNs) });
  return out;
}

export const pct = (x) => `${(100 * x).toFixed(2)} %`;
export const ms = (ns) => `${(ns / 1e6).toFixed(3)} ms`;
