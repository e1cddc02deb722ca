// Scenario 17: what a PC reads from the port before it picks a driver.
// rp2040js's CDC host reads only the configuration; here the test, as the
// host, also asks for the device descriptor and the serial-number string
// once the port is configured, and checks them: the composite class
// 0xEF/0x02/0x01 that Windows 10/11 bind to usbser.sys without an INF (with
// the interface association that the configuration carries), the IDs, and
// a serial number of the maker's domain, a colon and 16 hex digits (the
// flash chip's unique ID). Also: the
// D+ pull-up follows VBUS, and the motor stays off with the cable in.
import assert from 'node:assert/strict';
import { test } from 'node:test';
import { MS } from '../lib/board.js';
import { boardWith } from '../lib/images.js';
import { sendOn } from '../lib/steps.js';

const PULLUP_EN = 1 << 16;

/** A GET_DESCRIPTOR setup packet (type, index, wLength; language 0x0409 for strings). */
function getDescriptor(type, index, length) {
  const lang = type === 3 ? 0x0409 : 0;
  return new Uint8Array([0x80, 6, index, type, lang & 0xff, lang >> 8, length & 0xff, length >> 8]);
}

/** Send `setup` on endpoint 0 and collect what the device answers (IN packets until a short one). */
function controlIn(b, setup) {
  const usbc = b.mcu.usbCtrl;
  const cdcWrite = usbc.onEndpointWrite;
  const got = [];
  let done = false;
  usbc.onEndpointWrite = (ep, buf) => {
    if (ep === 0 && !done) {
      got.push(...buf);
      if (buf.length < 64) done = true;
      return;
    }
    cdcWrite(ep, buf);
  };
  usbc.sendSetupPacket(setup);
  for (let i = 0; i < 50 && !done; i++) b.runFor(1e6);
  usbc.onEndpointWrite = cdcWrite;
  assert.ok(done, 'no answer to the GET_DESCRIPTOR');
  return Buffer.from(got);
}

test('usb: composite CDC descriptor, IAD, serial number from the flash ID; pull-up only with VBUS', () => {
  const b = boardWith('firmware');
  const f = b.facts;
  b.setBattery(4.0);
  b.runUntil(300 * MS);
  const sieCtrl = () => b.mcu.usbCtrl.sieCtrl;
  assert.equal(sieCtrl() & PULLUP_EN, 0, 'D+ pulled up with no VBUS');

  b.connectUsb('INFO\n');
  const until = b.nowNs + 200 * MS;
  while (b.nowNs < until && b.usb.rx.length === 0) b.runFor(1e6);
  assert.ok(b.usb.configuredAt, 'the port was not configured');
  assert.ok(sieCtrl() & PULLUP_EN, 'no D+ pull-up with VBUS present');
  assert.match(Buffer.from(b.usb.rx).toString('ascii'), /^swimbot-log v2 /, 'INFO not answered');

  const cfg = b.usb.cdc.descriptors;
  const iad = cfg.findIndex((_, i) => cfg[i] === 8 && cfg[i + 1] === 0x0b);
  assert.ok(iad > 0, 'no interface association descriptor in the configuration');
  assert.deepEqual(cfg.slice(iad + 2, iad + 7), [0, 2, 0x02, 0x02, 0x00], 'IAD: interfaces 0-1, CDC ACM');

  const dev = controlIn(b, getDescriptor(1, 0, 18));
  assert.equal(dev.length, 18);
  assert.deepEqual([...dev.subarray(4, 7)], [0xef, 0x02, 0x01], 'device class: composite with IAD');
  assert.equal(dev[7], 64, 'bMaxPacketSize0');
  assert.equal(dev.readUInt16LE(8), 0x16c0);
  assert.equal(dev.readUInt16LE(10), 0x27dd);
  assert.ok(dev[16] > 0, 'no serial number string');

  const serial = controlIn(b, getDescriptor(3, dev[16], 255));
  assert.equal(serial[1], 3);
  const text = serial.subarray(2, serial[0]).toString('utf16le');
  // The shared ID pair's rule: the maker's domain (or e-mail), a colon,
  // then the flash chip's unique ID (shared/src/board.rs, USB_VID).
  assert.match(text, /^[a-z0-9.@-]+\.[a-z]+:[0-9A-F]{16}$/, `serial number '${text}'`);

  // The motor stays off with the cable in, On or not.
  const on = sendOn(b, b.nowNs + 40 * MS);
  b.runUntil(on.end + 300 * MS);
  assert.equal(b.motorEdgesIn(on.end, b.nowNs).filter((e) => e.v === 1).length, 0, 'motor started with USB in');

  b.disconnectUsb();
  b.runFor(5 * MS);
  assert.equal(sieCtrl() & PULLUP_EN, 0, 'D+ still pulled up after VBUS went');
});
