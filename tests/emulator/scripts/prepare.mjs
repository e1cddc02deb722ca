// Prepares what the emulator tests run: the firmware ELF images (built into
// target/emu so the flashed target/thumbv6m-none-eabi/fw/firmware is never
// overwritten) and the RP2040 B1 bootrom (fetched from PyPI at test time).
// Writes target/emu/images/manifest.json for the tests.
//
// Environment:
//   SWIMBOT_EMU_ROUTE=a (default) | b   a: bootrom + plain images; b: no bootrom, `emulator` feature
//   SWIMBOT_EMU_NO_BUILD=1             use the images already in target/emu/images
import { execFileSync } from 'node:child_process';
import { copyFileSync, existsSync, mkdirSync, writeFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const root = resolve(here, '../../..');
const emuTarget = join(root, 'target/emu');
const route = process.env.SWIMBOT_EMU_ROUTE || 'a';
const imagesDir = join(emuTarget, route === 'a' ? 'images' : 'images-b');
if (route !== 'a' && route !== 'b') throw new Error(`SWIMBOT_EMU_ROUTE must be a or b, not ${route}`);

const base = route === 'b' ? ['emulator'] : [];
const variants = {
  firmware: base,
  'firmware-hang-test': [...base, 'hang-test'],
};

mkdirSync(imagesDir, { recursive: true });
const images = {};
for (const [name, features] of Object.entries(variants)) {
  const out = join(imagesDir, `${name}.elf`);
  images[name] = out;
  if (process.env.SWIMBOT_EMU_NO_BUILD) {
    if (!existsSync(out)) throw new Error(`${out} missing and SWIMBOT_EMU_NO_BUILD is set`);
    continue;
  }
  const args = ['build', '-p', 'firmware', '--target', 'thumbv6m-none-eabi', '--profile', 'fw', '--target-dir', emuTarget];
  if (features.length) args.push('--features', features.join(','));
  console.log(`emulator: cargo ${args.join(' ')}`);
  execFileSync('cargo', args, { cwd: root, stdio: 'inherit' });
  copyFileSync(join(emuTarget, 'thumbv6m-none-eabi/fw/firmware'), out);
}

let bootrom = null;
if (route === 'a') {
  const python = process.env.PYTHON || 'python3';
  bootrom = execFileSync(python, [join(here, 'fetch_bootrom.py'), join(emuTarget, 'bootrom')], {
    encoding: 'utf8',
    stdio: ['ignore', 'pipe', 'inherit'],
  }).trim();
  console.log(`emulator: bootrom ${bootrom}`);
}

writeFileSync(join(imagesDir, 'manifest.json'), JSON.stringify({ route, bootrom, images }, null, 2));
console.log(`emulator: route (${route}), images in ${imagesDir}`);
