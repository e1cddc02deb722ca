// The board's constants, read from the firmware image itself: the firmware
// exports shared/src/board.rs's `EXPORT` as the symbol SWIMBOT_BOARD, a
// header ('SWBD', pair count) and (four-character tag, value) pairs. One
// source for the chip, the host tests and this board model.
import { objectBytes } from './elf.js';

const NAMES = {
  MOTR: 'motorGpio',
  IRIN: 'irGpio',
  ADCC: 'batteryAdcChannel',
  'LED ': 'ledGpio',
  PWMF: 'pwmFreqHz',
  DVTP: 'dividerTopOhm',
  DVBT: 'dividerBottomOhm',
  VREF: 'adcRefMv',
  NADR: 'necAddress',
  'NON ': 'necCmdOn',
  NOFF: 'necCmdOff',
  WDMS: 'watchdogMs',
  WAKE: 'wakePeriodUs',
  SMPL: 'samplePeriodUs',
  CUTM: 'cutoffMv',
  CUTD: 'cutoffDebounceUs',
  RCHM: 'rechargedMv',
  MOTM: 'targetMotorMv',
  RAMP: 'rampUs',
  DORM: 'dormantAfterMs',
  HALA: 'hallAGpio',
  HALB: 'hallBGpio',
  HALP: 'hallPowerGpio',
  POLE: 'hallPolePairs',
  RATE: 'defaultRateMhz',
  STAL: 'stallMs',
  LNV0: 'lineInterceptMv',
  LNSL: 'lineSlopeMvPerHz',
  'KP1 ': 'necCmdPreset1',
  'KP5 ': 'necCmdPreset5',
  'KUP ': 'necCmdFaster',
  'KDN ': 'necCmdSlower',
  LOGA: 'logOffset',
  LOGS: 'logSlotBytes',
  LOGN: 'logSlots',
  LOGP: 'logPeriodMs',
  PAIR: 'pairingOffset',
  PWIN: 'pairingWindowMs',
  PHLD: 'pairingHoldMs',
  VBUS: 'vbusGpio',
  VMAX: 'motorRatedMv',
  JAMW: 'jamWindowMs',
  PHGP: 'powerHoldGpio',
};

const tagText = (w) => String.fromCharCode((w >>> 24) & 0xff, (w >>> 16) & 0xff, (w >>> 8) & 0xff, w & 0xff);

/** { motorGpio, irGpio, ... } from the image's SWIMBOT_BOARD; throws if a fact is missing or unknown. */
export function boardFacts(elf) {
  const { bytes } = objectBytes(elf, 'SWIMBOT_BOARD');
  if (!bytes) throw new Error(`${elf.path}: SWIMBOT_BOARD is not in a loaded segment`);
  const word = (i) => bytes.readUInt32LE(4 * i);
  if (tagText(word(0)) !== 'SWBD') throw new Error(`${elf.path}: SWIMBOT_BOARD has no SWBD header`);
  const n = word(1);
  if (bytes.length !== 8 + 8 * n) throw new Error(`${elf.path}: SWIMBOT_BOARD is ${bytes.length} B for ${n} pairs`);
  const facts = {};
  for (let i = 0; i < n; i++) {
    const tag = tagText(word(2 + 2 * i));
    const name = NAMES[tag];
    if (!name) throw new Error(`${elf.path}: SWIMBOT_BOARD has an unknown fact '${tag}' (add it to lib/facts.js)`);
    facts[name] = word(3 + 2 * i);
  }
  const missing = Object.values(NAMES).filter((k) => !(k in facts));
  if (missing.length) throw new Error(`${elf.path}: SWIMBOT_BOARD lacks ${missing.join(', ')}`);
  return facts;
}
