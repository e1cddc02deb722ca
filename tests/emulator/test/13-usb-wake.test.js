// Scenario 13: USB plugged into a DORMANT robot. After 10 s idle the chip
// stops its crystal (DORMANT); a lab that plugs a cable in to read the log
// must not have to press a remote key first: VBUS (GPIO24) wakes the chip,
// the port enumerates and the log reads out, the motor stays off while the
// cable is in (safety property 6), and with the cable out the chip goes
// DORMANT again and stays so (no wake-up loop, also after a VBUS blip of
// 100 us). The IR wake still works, with the On latency of an awake robot.
// The board wakes the chip as the IO bank does: any raw GPIO interrupt
// (level or latched edge) whose DORMANT_WAKE_INTE bit is set.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS, US } from '../lib/board.js';
import { ON_LATENCY_NS, RUNNING_DUTY, perf } from '../lib/contract.js';
import { boardWith, manifest } from '../lib/images.js';
import { EVENTS, decodeLog, readOverUsb } from '../lib/runlog.js';
import { ms, pct, sendOff, sendOn } from '../lib/steps.js';

const GAP = 40 * MS;
const route = manifest().route;
const noFlash = route !== 'a' && 'route (b) has no boot ROM: no flash writes, no log to read';

/** The DORMANT stretches that began in [t0, t1). */
const stretchesFrom = (b, t0, t1 = Infinity) => b.dormantStretches.filter((d) => d.from >= t0 && d.from < t1);

/** Run until `ns` after the last activity at `t` plus 500 ms; the stretch that began then, checked. */
function runToDormant(b, t, what) {
  b.runUntil(t + (b.facts.dormantAfterMs + 500) * MS);
  const d = stretchesFrom(b, t)[0];
  assert.ok(d, `not DORMANT ${b.facts.dormantAfterMs + 500} ms after ${what}`);
  assert.ok(b.dormant, `woke from DORMANT by itself after ${what}`);
  return d;
}

test('USB plugged into a DORMANT robot wakes it: the log reads out, the motor stays off, unplugged it sleeps again', { skip: noFlash }, () => {
  const b = boardWith('firmware');
  const f = b.facts;
  b.setBattery(4.0);
  b.runUntil(300 * MS);
  // A short run to read back.
  sendOn(b, b.nowNs + GAP);
  b.runUntil(b.nowNs + 1000 * MS);
  const off = sendOff(b, b.nowNs + GAP);
  const d = runToDormant(b, off.end, 'Off');
  perf('Off frame to DORMANT', ms(d.from - off.end), '');
  assert.ok(d.from - off.end >= f.dormantAfterMs * MS && d.from - off.end <= (f.dormantAfterMs + 50) * MS, `DORMANT ${ms(d.from - off.end)} after Off`);

  // The cable goes in while the crystal is stopped.
  const plug = b.nowNs;
  const bytes = readOverUsb(b, 'LOG\n', { timeoutNs: 3000 * MS });
  assert.ok(!b.dormant, 'VBUS did not wake the DORMANT chip');
  assert.ok(d.to - plug < 1 * US, `woken ${ms(d.to - plug)} after VBUS rose`);
  assert.ok(b.usb.configuredAt !== undefined, 'the port did not enumerate after the VBUS wake');
  const { header, records } = decodeLog(bytes);
  perf('USB plugged into a DORMANT robot: VBUS to port configured / log read', `${ms(b.usb.configuredAt - plug)} / ${ms(b.usb.lastRxAt - plug)} (${records.length} records)`);
  assert.equal(header.dropped, 0);
  assert.ok(records.length >= 10, `${records.length} records of a 1 s run`);
  assert.ok(records[0].events & EVENTS.ON && records[0].events & EVENTS.STARTED, 'the first record is not the On');
  const last = records[records.length - 1];
  assert.ok(last.events & EVENTS.STOPPED_COMMAND && last.duty === 0, 'the closing record is not the Off');
  assert.ok(Math.abs(last.tMs - off.end / MS) <= 2, `closing record at ${last.tMs} ms, Off ended at ${ms(off.end)}`);

  // Cable in: On starts nothing, and the chip stays awake to serve the port.
  const t0 = b.nowNs;
  sendOn(b, b.nowNs + GAP);
  b.runUntil(t0 + (f.dormantAfterMs + 1000) * MS);
  assert.equal(b.motorEdgesIn(t0, b.nowNs).filter((e) => e.v === 1).length, 0, 'the motor ran with USB connected after a VBUS wake');
  assert.equal(stretchesFrom(b, t0).length, 0, 'DORMANT with USB connected');

  // Cable out: the idle is long over, so DORMANT at once, and it stays.
  b.disconnectUsb();
  const unplug = b.nowNs;
  b.runUntil(unplug + 2000 * MS);
  const after = stretchesFrom(b, unplug);
  assert.equal(after.length, 1, `${after.length} DORMANT entries in 2 s after the unplug (a wake-up loop)`);
  perf('USB unplugged (idle > 10 s) to DORMANT', ms(after[0].from - unplug), '');
  assert.ok(after[0].from - unplug < 5 * MS, `DORMANT ${ms(after[0].from - unplug)} after the unplug`);
  const res = b.dormantIn(after[0].from, b.nowNs);
  assert.ok(res > 0.999, `DORMANT only ${pct(res)} after the unplug`);

  // A 100 us VBUS blip (a cable brushed in and out) while DORMANT: one wake,
  // DORMANT again within a few passes, and no further wake.
  const blip = b.nowNs;
  b.at(blip, () => b.mcu.gpio[f.vbusGpio].setInputValue(true));
  b.at(blip + 100 * US, () => b.mcu.gpio[f.vbusGpio].setInputValue(false));
  b.runUntil(blip + 2000 * MS);
  const blipped = stretchesFrom(b, blip);
  assert.ok(after[0].to - blip < 1 * US, 'the VBUS blip did not wake the chip');
  assert.equal(blipped.length, 1, `${blipped.length} DORMANT entries in 2 s after a VBUS blip`);
  perf('VBUS blip of 100 us while DORMANT: wake to DORMANT again', ms(blipped[0].from - blip), '');
  assert.ok(blipped[0].from - blip < 5 * MS, `DORMANT again only ${ms(blipped[0].from - blip)} after the blip`);

  // Plugged in again: woken again, enumerated again, answered.
  const replug = b.nowNs;
  const info = readOverUsb(b, 'INFO\n', { bytes: 30, timeoutNs: 1000 * MS }).toString('ascii');
  assert.ok(blipped[0].to - replug < 1 * US, 'the second plug did not wake the chip');
  assert.match(info, new RegExp(`^swimbot-log v2 records=${records.length} `), 'no answer after the second plug');
  b.disconnectUsb();
  const unplug2 = b.nowNs;
  b.runUntil(unplug2 + 1000 * MS);
  assert.equal(stretchesFrom(b, unplug2).length, 1, 'not DORMANT once after the second unplug');
  assert.equal(b.motorEdgesIn(plug, b.nowNs).filter((e) => e.v === 1).length, 0, 'the motor ran');

  // The IR pin still wakes it: On starts the motor as from an awake robot.
  const on = sendOn(b, b.nowNs + GAP);
  b.runUntil(on.end + 400 * MS);
  assert.ok(b.dutyIn(on.end + 300 * MS, on.end + 400 * MS) > RUNNING_DUTY, 'On after the USB wakes did not start the motor');
  assert.deepEqual(b.resets.map((r) => r.reason), ['power-on'], 'a reset on the way');
});

test('IR wakes a DORMANT robot with the On latency of an awake one', () => {
  const b = boardWith('firmware');
  b.setBattery(4.0);
  b.runUntil(300 * MS);
  const awake = sendOn(b, b.nowNs + GAP);
  b.runUntil(awake.end + 500 * MS);
  const awakeNs = b.firstRiseAfter(awake.start) - awake.end;
  const off = sendOff(b, b.nowNs + GAP);
  const d = runToDormant(b, off.end, 'Off');
  const on = sendOn(b, b.nowNs);
  assert.ok(d.to <= on.start + 1 * US, 'the On frame\'s first edge did not wake the chip');
  b.runUntil(on.end + 5 * MS);
  const first = b.firstRiseAfter(on.start);
  assert.ok(first !== undefined, 'On after DORMANT did not start the motor');
  const wokenNs = first - on.end;
  perf('On frame end to first PWM edge, awake / after DORMANT', `${ms(awakeNs)} / ${ms(wokenNs)}`);
  assert.ok(wokenNs < ON_LATENCY_NS, `PWM ${ms(wokenNs)} after the frame that woke the chip`);
});
