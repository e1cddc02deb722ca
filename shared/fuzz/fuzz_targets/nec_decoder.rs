//! Fuzz the NEC decoder and the remote's key map with arbitrary edge
//! streams: no input may panic, every frame reported must carry a
//! whitelisted address, and only the mapped keys may become commands.
#![no_main]

use libfuzzer_sys::fuzz_target;
use swimbot_shared::{AddressFilter, Command, KeyMap, Level, NecDecoder, NecEvent, Remote};

const KEYS: KeyMap = KeyMap {
    address: 0x00,
    on: 0x45,
    off: 0x47,
};

fuzz_target!(|data: &[u8]| {
    // Each 3-byte chunk is one edge: the top bit of the first byte is the
    // level, the remaining 23 bits the time since the previous edge
    // (up to 8.4 s, so both in-frame timings and long gaps are reachable).
    let mut decoder = NecDecoder::new(AddressFilter::only(KEYS.address).with(0x80));
    let mut remote = Remote::new(KEYS);
    let mut t = u32::from(data.first().copied().unwrap_or(0)) << 24;
    for chunk in data.chunks_exact(3) {
        let level = if chunk[0] & 0x80 != 0 {
            Level::High
        } else {
            Level::Low
        };
        let dt = u32::from(chunk[0] & 0x7F) << 16 | u32::from(chunk[1]) << 8 | u32::from(chunk[2]);
        t = t.wrapping_add(dt);
        if let Some(NecEvent::Frame { address, .. }) = decoder.edge(level, t) {
            assert!(address.low() == KEYS.address || address.low() == 0x80);
        }
        if let Some(c) = remote.edge(level, t) {
            assert!(matches!(c, Command::On | Command::Off));
        }
    }
});
