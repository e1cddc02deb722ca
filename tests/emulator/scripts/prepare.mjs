// Prepares what the emulator tests run: the firmware ELF images, the
// motor model (WebAssembly, lib/rotor.js) and the RP2040 B1 bootrom (fetched from PyPI at test time). Writes
// target/emu/images/manifest.json for the tests.
//
// The images are built in the workspace's own target directory, so they
// share every compiled dependency with `cargo fw` (a separate target
// directory built the whole embedded tree again). The plain image is the
// flashed one, target/thumbv6m-none-eabi/fw/firmware, copied. A variant with
// other features (`fault-test`, route b's `emulator`) is built to the same
// path, so it is moved out of it at once, and `cargo fw` then puts the plain
// image back (cargo re-links a build that is up to date); its bytes are
// checked. The flashed path never keeps a test image.
//
// Environment:
//   SWIMBOT_EMU_ROUTE=a (default) | b   a: bootrom + plain images; b: no bootrom, `emulator` feature
//   SWIMBOT_EMU_NO_BUILD=1             use the images already in target/emu/images
import { execFileSync } from 'node:child_process';
import { copyFileSync, existsSync, mkdirSync, readFileSync, renameSync, writeFileSync } from 'node:fs';
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
  'firmware-fault-test': [...base, 'fault-test'],
};

const flashed = join(root, 'target/thumbv6m-none-eabi/fw/firmware');
function cargoFw(features) {
  const args = ['build', '-p', 'firmware', '--target', 'thumbv6m-none-eabi', '--profile', 'fw'];
  if (features.length) args.push('--features', features.join(','));
  console.log(`emulator: cargo ${args.join(' ')}`);
  execFileSync('cargo', args, { cwd: root, stdio: 'inherit' });
}

mkdirSync(imagesDir, { recursive: true });
const images = {};
let variantBuilt = false;
for (const [name, features] of Object.entries(variants)) {
  const out = join(imagesDir, `${name}.elf`);
  images[name] = out;
  if (process.env.SWIMBOT_EMU_NO_BUILD) {
    if (!existsSync(out)) throw new Error(`${out} missing and SWIMBOT_EMU_NO_BUILD is set`);
    continue;
  }
  cargoFw(features);
  if (features.length) {
    renameSync(flashed, out);
    variantBuilt = true;
  } else {
    copyFileSync(flashed, out);
  }
}
if (variantBuilt) {
  cargoFw([]);
  if (!existsSync(flashed)) throw new Error(`${flashed}: \`cargo fw\` did not put the plain image back`);
  if (route === 'a' && !readFileSync(flashed).equals(readFileSync(images.firmware))) {
    throw new Error(`${flashed} differs from the plain image the emulator ran (${images.firmware})`);
  }
}

// The board's motor (lib/rotor.js): the host's motor model as WebAssembly.
// `cargo xtask test` has built it already (then this is a no-op).
if (!process.env.SWIMBOT_EMU_NO_BUILD) {
  const args = ['build', '-p', 'swimbot-motor-wasm', '--target', 'wasm32-unknown-unknown', '--profile', 'wasm'];
  console.log(`emulator: cargo ${args.join(' ')}`);
  execFileSync('cargo', args, { cwd: root, stdio: 'inherit' });
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
