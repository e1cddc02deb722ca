// The run log image read out over USB (format: shared/src/run_log.rs's
// module doc): a 32-byte header and 16-byte records, little-endian, with a
// CRC-32 (zlib's) over header bytes 0-27 and the records. Read here by the
// test's own code, not the firmware's, so the format is checked from
// outside.
import { crc32 } from 'node:zlib';

export const EVENTS = {
  ON: 1 << 0,
  OFF: 1 << 1,
  STARTED: 1 << 2,
  RAMP_DONE: 1 << 3,
  STOPPED_COMMAND: 1 << 4,
  SET_POINT_CHANGED: 1 << 9,
  LOW_BATTERY: 1 << 11,
  PAIRED: 1 << 13,
  USB_CONNECTED: 1 << 15,
};

/** { header, records } from the bytes, or throws saying what is wrong. */
export function decodeLog(bytes) {
  const b = Buffer.from(bytes);
  if (b.length < 32) throw new Error(`log: ${b.length} B, shorter than a header`);
  if (b.toString('ascii', 0, 4) !== 'SWLG') throw new Error('log: no SWLG magic');
  const header = {
    version: b.readUInt16LE(4),
    headerLen: b.readUInt16LE(6),
    recordLen: b.readUInt16LE(8),
    periodMs: b.readUInt16LE(10),
    count: b.readUInt32LE(12),
    dropped: b.readUInt32LE(16),
    foreign: b.readUInt32LE(20),
    paired: b.readUInt16LE(24) === 0xffff ? null : b.readUInt16LE(24),
    flags: b.readUInt16LE(26),
    crc: b.readUInt32LE(28),
  };
  if (b.length !== 32 + 16 * header.count) throw new Error(`log: ${b.length} B for ${header.count} records`);
  const crc = crc32(Buffer.concat([b.subarray(0, 28), b.subarray(32)]));
  if (crc !== header.crc) throw new Error(`log: CRC ${crc.toString(16)} != stored ${header.crc.toString(16)}`);
  const records = [];
  for (let o = 32; o < b.length; o += 16) {
    const rate = b.readUInt16LE(o + 6);
    records.push({
      tMs: b.readUInt32LE(o),
      setMhz: b.readUInt16LE(o + 4),
      rateMhz: rate === 0xffff ? null : rate,
      duty: b.readUInt16LE(o + 8) / 10_000,
      cellMv: b.readUInt16LE(o + 10),
      events: b.readUInt16LE(o + 12),
      fault: b[o + 14],
      foreign: b[o + 15],
    });
  }
  return { header, records };
}

/** Plug USB in, send `request`, run until `bytes` have come (or `timeoutNs`); the bytes. */
export function readOverUsb(board, request, { bytes = null, timeoutNs }) {
  board.connectUsb(request);
  const until = board.nowNs + timeoutNs;
  const want = () => {
    const rx = board.usb.rx;
    if (bytes !== null) return bytes;
    return rx.length >= 32 ? 32 + 16 * Buffer.from(rx.slice(12, 16)).readUInt32LE(0) : Infinity;
  };
  while (board.nowNs < until && board.usb.rx.length < want()) board.runFor(1e6);
  return Buffer.from(board.usb.rx);
}
