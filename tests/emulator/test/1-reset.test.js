// Scenario 1: reset. The motor pin is low from the first millisecond and no
// PWM appears while no command has been received.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS, US } from '../lib/board.js';
import { CUTOFF_DEBOUNCE_NS, CUTOFF_V, DEFAULT_RATE_HZ, HALL_EDGES_PER_TURN, PWM_FREQ_HZ, SOFT_START_NS, WATCHDOG_MAX_NS, WATCHDOG_MIN_NS, perf } from '../lib/contract.js';
import { boardWith, manifest } from '../lib/images.js';

test('reset: motor pin low within the first ms, no PWM', () => {
  const m = manifest();
  console.log(`emulator: route (${m.route}), ${m.bootrom ? 'B1 bootrom + boot2' : 'no bootrom'}`);
  const b = boardWith('firmware');
  const f = b.facts;
  // The image's board facts (shared/src/board.rs) meet the contract.
  assert.deepEqual(
    [f.motorGpio, f.irGpio, f.hallAGpio, f.hallBGpio, f.hallPowerGpio, 4 * f.hallPolePairs, f.pwmFreqHz, f.defaultRateMhz, f.rampUs * 1e3, f.cutoffMv, f.cutoffDebounceUs * 1e3],
    [16, 15, 13, 14, 12, HALL_EDGES_PER_TURN, PWM_FREQ_HZ, DEFAULT_RATE_HZ * 1e3, SOFT_START_NS, CUTOFF_V * 1e3, CUTOFF_DEBOUNCE_NS],
  );
  assert.ok(f.watchdogMs * MS >= WATCHDOG_MIN_NS && f.watchdogMs * MS <= WATCHDOG_MAX_NS, `watchdog ${f.watchdogMs} ms`);
  const pin = b.mcu.gpio[f.motorGpio];
  while (!pin.outputEnable && b.nowNs < 1 * MS) b.runFor(1 * US);
  perf('reset to GPIO16 driven low (emulated clocks start at once: no XOSC start-up)', (b.nowNs / US).toFixed(0), 'us');
  b.runUntil(1 * MS);
  assert.equal(b.motorEdgesIn(0, 1 * MS).filter((e) => e.v === 1).length, 0, 'motor pin went high in the first ms');
  assert.equal(b.motorAt(1 * MS), 0, 'motor pin not low at 1 ms');
  assert.ok(pin.outputEnable, 'GPIO16 is not driven by 1 ms (left floating on the 100k pull-down)');
  assert.equal(pin.outputValue, false, 'GPIO16 drives high at 1 ms');
  // The gate pad: 12 mA drive (PADS DRIVE = 3) and fast slew, not the
  // reset's 4 mA / slow, which stretch the MOSFET's switching edges.
  const pad = pin.padValue;
  assert.equal((pad >> 4) & 3, 3, `GPIO16 pad drive ${[2, 4, 8, 12][(pad >> 4) & 3]} mA, want 12 mA`);
  assert.equal(pad & 1, 1, 'GPIO16 pad slew slow, want fast');

  b.runUntil(300 * MS);
  const rises = b.motorEdgesIn(0, 300 * MS).filter((e) => e.v === 1);
  assert.equal(rises.length, 0, `motor pin pulsed ${rises.length} times in 300 ms without a command`);
  assert.equal(b.motorAt(300 * MS), 0);
  assert.equal(b.resets.length, 1, 'unexpected reset during boot');
  assert.ok(b.mcu.core.cycles > 0, 'the core did not run');
});
