// The board's 2 MiB flash chip, kept across chip resets (as the real chip's
// flash keeps the run log and the pairing), and the boot ROM's flash
// functions applied to it. rp2040js has no SPI flash behind the SSI, so a
// program or an erase through the ROM would do nothing; the board patches
// the entries of the ROM's flash functions with BKPT instructions and does
// here what the ROM would do on the chip: erase fills 0xFF, program ANDs
// the data in (bits only go 1 -> 0). Each operation then stalls the core
// for as long as the flash chip is busy (`FLASH_TIMING`; the board holds
// the thread for that long, takes the interrupts the firmware left
// unmasked, and runs the timer, PWM and watchdog on), and returns to its
// caller. Not emulated: the XIP
// cache (rp2040js reads flash directly).
//
// W25Q16JV datasheet (Winbond, rev. H), AC characteristics: page program
// tPP 0.4 ms typical, 3 ms max; sector erase (4 KiB) tSE 45 / 400 ms; block
// erase (64 KiB) tBE2 150 / 2000 ms.
export const FLASH_TIMING = {
  typical: { pageProgramNs: 0.4e6, sectorEraseNs: 45e6, blockEraseNs: 150e6 },
  worst: { pageProgramNs: 3e6, sectorEraseNs: 400e6, blockEraseNs: 2000e6 },
  /** The stall not emulated at all (before the stall model; for comparisons). */
  none: { pageProgramNs: 0, sectorEraseNs: 0, blockEraseNs: 0 },
};
const PAGE = 256;
const SECTOR = 4096;
const BLOCK = 65536;
const FLASH_BYTES = 2 * 1024 * 1024;
// ROM header: 16-bit pointers to the function table (0x14) and its lookup (0x18).
const ROM_FUNC_TABLE = 0x14;
const FUNCTIONS = ['IF', 'EX', 'RE', 'RP', 'FC', 'CX'];
const BKPT_BASE = 0xa0;

const code = (s) => s.charCodeAt(0) | (s.charCodeAt(1) << 8);

export class FlashChip {
  /** @param {object} [timing] one of FLASH_TIMING (default: typical), or { pageProgramNs, sectorEraseNs, blockEraseNs } */
  constructor(timing = FLASH_TIMING.typical) {
    this.bytes = new Uint8Array(FLASH_BYTES).fill(0xff); // a blank chip
    this.timing = timing;
    this.ops = []; // { t, op: 'erase'|'program', offset, len, stallNs, liveIrqs }
    /** Called with the stall (ns) of each operation; the board holds the core that long. */
    this.onStall = () => {};
  }

  /**
   * How long the chip is busy: the ROM's flash_range_erase erases 64 KiB
   * blocks where the range allows and 4 KiB sectors elsewhere (the firmware
   * passes block size 65536 and command 0xd8); flash_range_program writes
   * page by page.
   */
  stallNs(op, offset, len) {
    const t = this.timing;
    if (op === 'program') return Math.ceil(len / PAGE) * t.pageProgramNs;
    let ns = 0;
    for (let a = offset; a < offset + len; ) {
      const block = a % BLOCK === 0 && a + BLOCK <= offset + len;
      ns += block ? t.blockEraseNs : t.sectorEraseNs;
      a += block ? BLOCK : SECTOR;
    }
    return ns;
  }

  /** The address of each ROM flash function in `bootrom` (Uint32Array words). */
  static romFunctions(bootrom) {
    const bytes = new Uint8Array(bootrom.buffer, bootrom.byteOffset, bootrom.byteLength);
    const u16 = (a) => bytes[a] | (bytes[a + 1] << 8);
    const found = {};
    for (let p = u16(ROM_FUNC_TABLE); u16(p) !== 0; p += 4) {
      const name = FUNCTIONS.find((f) => code(f) === u16(p));
      if (name) found[name] = u16(p + 2) & ~1;
    }
    for (const f of FUNCTIONS) if (!(f in found)) throw new Error(`bootrom has no flash function '${f}'`);
    return found;
  }

  /** A bootrom copy whose flash functions start with BKPT #0xa0+i. */
  static patchBootrom(bootrom) {
    const patched = new Uint32Array(bootrom);
    const view = new DataView(patched.buffer);
    const fns = FlashChip.romFunctions(bootrom);
    FUNCTIONS.forEach((f, i) => view.setUint16(fns[f], 0xbe00 | (BKPT_BASE + i), true));
    return patched;
  }

  /** Load into a fresh chip's flash window, and serve its ROM flash calls. */
  attach(mcu, nowNs) {
    mcu.flash.set(this.bytes);
    this.mcu = mcu;
    mcu.onBreak = (imm) => {
      const f = FUNCTIONS[imm - BKPT_BASE];
      if (!f) return;
      const r = mcu.core.registers;
      if (f === 'RE') this.erase(nowNs(), r[0], r[1]);
      if (f === 'RP') this.program(nowNs(), r[0], r[1], r[2]);
      if (f === 'RE' || f === 'RP') {
        const op = this.ops[this.ops.length - 1];
        // The interrupts that can be taken while the flash is busy (a
        // bitmask of NVIC lines; 0 with PRIMASK set). On the chip each must
        // have its vector and handler in RAM: the board counts every
        // instruction fetched from flash during a stall (flashFetchesInStall).
        op.liveIrqs = mcu.core.PM ? 0 : mcu.core.enabledInterrupts >>> 0;
        op.stallNs = this.stallNs(op.op, op.offset, op.len);
        if (op.stallNs > 0) this.onStall(op.stallNs);
      }
      mcu.core.PC = mcu.core.LR & ~1; // return to the caller
    };
  }

  erase(t, offset, len) {
    this.ops.push({ t, op: 'erase', offset, len });
    this.bytes.fill(0xff, offset, offset + len);
    this.mcu.flash.fill(0xff, offset, offset + len);
  }

  program(t, offset, src, len) {
    this.ops.push({ t, op: 'program', offset, len });
    for (let i = 0; i < len; i++) {
      const b = this.bytes[offset + i] & this.mcu.readUint8(src + i);
      this.bytes[offset + i] = b;
      this.mcu.flash[offset + i] = b;
    }
  }

  /** A pairing entry ('P', address, ~address, ~'P') at `offset`, as if paired earlier. */
  storePairing(offset, address) {
    this.bytes.set([0x50, address, ~address & 0xff, ~0x50 & 0xff], offset);
  }
}
