// Scenario 18: the serial port's text requests beside the binary log.
// `INFO` carries the robot's state after the log's fields (firmware version
// and commit, battery, rate, faults, pairing); `BOOTSEL` answers `OK
// BOOTSEL` and the chip leaves for the boot ROM's USB bootloader (the
// RPI-RP2 drive) with the motor pin low. The refusal's state and duty
// terms cannot be reached through the port: VBUS holds the motor off from
// the pass before the port is served (`MainLoop::set_usb_connected`; the
// first test below: the motor runs up to the moment the cable goes in, and
// the request that follows finds it stopped), so those two are host-tested
// (`shared/src/run_log/status.rs`). The gate term is reached on the chip:
// the pad's output forced high through GPIO16_CTRL.OUTOVER (what a stray
// write or a wrong pin function would do; `Motor::gate_high` reads
// GPIO16_STATUS.OUTTOPAD), BOOTSEL is answered `ERR motor on` and the chip
// stays in the firmware; released, the same request is honoured.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { boardWith, manifest } from '../lib/images.js';
import { sendOn } from '../lib/steps.js';

const GAP = 40 * MS;
const route = manifest().route;

/** The answer line to `request`, on a fresh plug of the cable. */
function ask(b, request) {
  b.connectUsb(request);
  const until = b.nowNs + 1000 * MS;
  while (b.nowNs < until && !b.usb.rx.includes(0x0a)) b.runFor(1e6);
  const line = Buffer.from(b.usb.rx).toString('ascii');
  assert.ok(line.endsWith('\n'), `no answer to ${JSON.stringify(request)}: ${JSON.stringify(line)}`);
  return line.trimEnd();
}

function fields(line) {
  return Object.fromEntries(line.split(' ').slice(2).map((kv) => kv.split('=')));
}

test('INFO: version, commit, battery, rate, faults and pairing after the log fields', () => {
  const b = boardWith('firmware');
  b.setBattery(4.0);
  b.runUntil(300 * MS);
  const f = fields(ask(b, 'INFO\n'));
  assert.equal(f.fw, '0.1.0');
  assert.match(f.commit, /^([0-9a-f]{7,12}|unknown)$/);
  assert.ok(Math.abs(Number(f.battery_mv) - 4000) < 100, `battery_mv=${f.battery_mv} at a 4.0 V cell`);
  assert.equal(f.battery, 'ok');
  assert.deepEqual([f.rate_mhz, f.set_mhz, f.fault, f.trips, f.lockout], ['none', '1000', 'none', '0', 'no']);
  assert.equal(f.pairing, 'window', 'inside the 5 s pairing window');
  assert.equal(f.paired, `0x${b.facts.necAddress.toString(16).padStart(2, '0')}`);
});

test('BOOTSEL: answered, then the boot ROM runs and the motor pin stays low', { skip: route !== 'a' && 'route (b) has no boot ROM' }, () => {
  const b = boardWith('firmware');
  b.setBattery(4.0);
  b.runUntil(300 * MS);
  const on = sendOn(b, b.nowNs + GAP);
  b.runUntil(on.end + 1000 * MS);
  assert.ok(b.dutyIn(b.nowNs - 100 * MS, b.nowNs) > 0, 'the motor did not start');
  const answer = ask(b, 'BOOTSEL\n');
  assert.equal(answer, 'OK BOOTSEL', 'the cable stopped the motor, so BOOTSEL is honoured');
  const answered = b.nowNs;
  b.runUntil(answered + 200 * MS);
  assert.ok(b.mcu.core.PC < 0x4000, `the core runs at ${b.mcu.core.PC.toString(16)}, not in the boot ROM`);
  const rising = b.motorEdgesIn(answered, b.nowNs).filter((e) => e.v === 1);
  assert.equal(rising.length, 0, 'a gate pulse after BOOTSEL');
});

/** GPIO16_CTRL (IO_BANK0 + 8 * 16 + 4): OUTOVER, bits 9:8 (0 normal, 3 drive high). */
function gateOverride(b, high) {
  const pin = b.mcu.gpio[b.facts.motorGpio];
  pin.ctrl = (pin.ctrl & ~(3 << 8)) | ((high ? 3 : 0) << 8);
  pin.checkForUpdates?.();
}

test('BOOTSEL: refused while the gate pin drives high, honoured once it is low', { skip: route !== 'a' && 'route (b) has no boot ROM' }, () => {
  const b = boardWith('firmware');
  b.setBattery(4.0);
  b.runUntil(300 * MS);
  gateOverride(b, true);
  b.runFor(5 * MS);
  assert.equal(b.mcu.gpio[b.facts.motorGpio].value, 1, 'the override did not drive the pad high');
  assert.equal(ask(b, 'BOOTSEL\n'), 'ERR motor on', 'BOOTSEL with the gate high');
  b.runFor(200 * MS);
  assert.ok(b.mcu.core.PC >= 0x10000000, `the core left the firmware: PC ${b.mcu.core.PC.toString(16)}`);
  b.disconnectUsb();
  gateOverride(b, false);
  b.runFor(50 * MS);
  assert.equal(b.mcu.gpio[b.facts.motorGpio].value, 0, 'the pad stayed high');
  assert.equal(ask(b, 'BOOTSEL\n'), 'OK BOOTSEL', 'BOOTSEL with the motor off and the gate low');
  b.runFor(200 * MS);
  assert.ok(b.mcu.core.PC < 0x4000, `the core runs at ${b.mcu.core.PC.toString(16)}, not in the boot ROM`);
});
