// Minimal ELF32 little-endian reader: the loadable segments (for the flash
// image) and the symbol table (to name the interrupt handlers).
import { readFileSync } from 'node:fs';

export function readElf(path) {
  const buf = readFileSync(path);
  const dv = new DataView(buf.buffer, buf.byteOffset, buf.byteLength);
  if (buf.readUInt32BE(0) !== 0x7f454c46) throw new Error(`${path}: not an ELF file`);
  if (buf[4] !== 1 || buf[5] !== 1) throw new Error(`${path}: not ELF32 little-endian`);
  const u16 = (o) => dv.getUint16(o, true);
  const u32 = (o) => dv.getUint32(o, true);
  const entry = u32(0x18);
  const phoff = u32(0x1c);
  const shoff = u32(0x20);
  const phentsize = u16(0x2a);
  const phnum = u16(0x2c);
  const shentsize = u16(0x2e);
  const shnum = u16(0x30);

  const segments = [];
  for (let i = 0; i < phnum; i++) {
    const o = phoff + i * phentsize;
    const type = u32(o);
    if (type !== 1 /* PT_LOAD */) continue;
    const offset = u32(o + 4);
    const vaddr = u32(o + 8);
    const paddr = u32(o + 12);
    const filesz = u32(o + 16);
    const memsz = u32(o + 20);
    segments.push({ offset, vaddr, paddr, filesz, memsz, data: buf.subarray(offset, offset + filesz) });
  }

  const sections = [];
  for (let i = 0; i < shnum; i++) {
    const o = shoff + i * shentsize;
    sections.push({
      name: u32(o),
      type: u32(o + 4),
      addr: u32(o + 12),
      offset: u32(o + 16),
      size: u32(o + 20),
      link: u32(o + 24),
      entsize: u32(o + 36),
    });
  }
  const symbols = [];
  const objects = [];
  for (const s of sections) {
    if (s.type !== 2 /* SHT_SYMTAB */) continue;
    const strtab = sections[s.link];
    for (let o = s.offset; o + 16 <= s.offset + s.size; o += 16) {
      const nameOff = u32(o);
      const value = u32(o + 4);
      const size = u32(o + 8);
      const info = buf[o + 12];
      const type = info & 0xf;
      if (type !== 2 /* STT_FUNC */ && type !== 1 /* STT_OBJECT */) continue;
      let end = strtab.offset + nameOff;
      while (buf[end] !== 0) end++;
      const name = buf.toString('latin1', strtab.offset + nameOff, end);
      if (type === 2) symbols.push({ name, addr: value & ~1, size });
      else objects.push({ name, addr: value, size });
    }
  }
  return { path, entry, segments, symbols, objects };
}

/** The bytes of the data object `name` as the image loads them (from its segment by load address). */
export function objectBytes(elf, name) {
  const sym = elf.objects.find((s) => s.name === name);
  if (!sym) throw new Error(`${elf.path}: no symbol ${name}`);
  for (const seg of elf.segments) {
    if (sym.addr >= seg.vaddr && sym.addr + sym.size <= seg.vaddr + seg.filesz) {
      const off = sym.addr - seg.vaddr;
      return { addr: sym.addr, bytes: seg.data.subarray(off, off + sym.size) };
    }
  }
  // Not in a loaded segment (e.g. .bss): only its address is known.
  return { addr: sym.addr, bytes: null };
}

/** Copies the ELF's loadable segments that live in flash (by load address) into `flash` (offset 0 = 0x10000000). */
export function loadFlash(elf, flash) {
  const FLASH = 0x10000000;
  let top = 0;
  for (const seg of elf.segments) {
    if (seg.filesz === 0) continue;
    if (seg.paddr < FLASH || seg.paddr >= FLASH + flash.length) {
      throw new Error(`segment at LMA 0x${seg.paddr.toString(16)} is outside flash`);
    }
    flash.set(seg.data, seg.paddr - FLASH);
    top = Math.max(top, seg.paddr - FLASH + seg.filesz);
  }
  if (top === 0) throw new Error(`${elf.path}: no loadable flash segment`);
  return top;
}

/** The function symbol containing `addr`, or undefined. */
export function symbolize(elf, addr) {
  addr &= ~1;
  return elf.symbols.find((s) => addr >= s.addr && addr < s.addr + Math.max(s.size, 2));
}
