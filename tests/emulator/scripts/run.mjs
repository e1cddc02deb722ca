// `npm test`: prepare the images and the bootrom, run every scenario under
// node:test (one file per core: each runs in simulated time, so running them
// side by side changes no measured number), then print the
// measured numbers together, the wall time and a plain closing line.
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, readFileSync, rmSync } from 'node:fs';
import { availableParallelism } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const pkg = resolve(here, '..');
const perfLog = resolve(pkg, '../../target/emu/perf.log');
const started = Date.now();

const prep = spawnSync(process.execPath, [join(here, 'prepare.mjs')], { stdio: 'inherit' });
if (prep.status !== 0) process.exit(prep.status ?? 1);

mkdirSync(dirname(perfLog), { recursive: true });
rmSync(perfLog, { force: true });
const args = ['--test', '--test-reporter=tap', `--test-concurrency=${availableParallelism()}`, ...process.argv.slice(2)];
if (process.argv.length <= 2) args.push('test/');
const child = spawn(process.execPath, args, {
  cwd: pkg,
  stdio: ['ignore', 'pipe', 'inherit'],
  env: { ...process.env, SWIMBOT_EMU_PERF_LOG: perfLog },
});
let out = '';
child.stdout.on('data', (chunk) => {
  process.stdout.write(chunk);
  out += chunk;
});
child.on('close', (code) => {
  const count = (key) => Number((out.match(new RegExp(`^# ${key} (\\d+)$`, 'm')) || [])[1] ?? 0);
  console.log('\n# emulator measurements (simulated time; CPU cycles as rp2040js counts them)');
  if (existsSync(perfLog)) {
    for (const line of readFileSync(perfLog, 'utf8').trim().split('\n')) console.log(`#   ${line}`);
  }
  console.log(`# emulator tests wall time: ${((Date.now() - started) / 1000).toFixed(1)} s (images + bootrom + scenarios)`);
  const skipped = count('skipped') + count('todo');
  console.log(`emulator: ${count('pass')} passed, ${count('fail') + count('cancelled')} failed${skipped ? `, ${skipped} skipped` : ''}`);
  process.exit(code ?? 1);
});
