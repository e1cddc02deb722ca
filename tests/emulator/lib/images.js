// The images and bootrom that scripts/prepare.mjs made.
import { readFileSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { Board } from './board.js';

const root = resolve(dirname(fileURLToPath(import.meta.url)), '../../..');
const route = process.env.SWIMBOT_EMU_ROUTE || 'a';
const manifestPath =
  process.env.SWIMBOT_EMU_MANIFEST ||
  join(root, route === 'a' ? 'target/emu/images/manifest.json' : 'target/emu/images-b/manifest.json');

export function manifest() {
  try {
    return JSON.parse(readFileSync(manifestPath, 'utf8'));
  } catch (e) {
    throw new Error(`${manifestPath}: ${e.message} (run \`npm test\`, which runs scripts/prepare.mjs first)`);
  }
}

/** A board booting the named image (`firmware` or `firmware-fault-test`); `opts` as Board's (paired, flashTiming). */
export function boardWith(image = 'firmware', opts = {}) {
  const m = manifest();
  return new Board({ elfPath: m.images[image], bootromPath: m.bootrom || undefined, ...opts });
}
