//! What the robot remembers across a reset: the battery cut-off latch,
//! kept in the RP2040 watchdog's SCRATCH0-3 registers (the bootrom uses
//! SCRATCH4-7 for its own reboot vector). Those registers survive a
//! watchdog or fault reset and are cleared by power-on and brown-out, so a
//! depleted cell that recovers to 3.6 V at rest cannot pass for a charged
//! one after a watchdog reset, while unplugging the cell (to recharge it)
//! does clear the latch.
//!
//! Four words so that garbage cannot pass for a record: a magic, the
//! state, the state inverted, and a version. Anything else reads as "no
//! record" (as after power-on).

/// `SWB` + record version 1.
const MAGIC: u32 = 0x5357_4201;
const LATCHED: u32 = 0xC0FF_0001;
const CLEAR: u32 = 0;

/// The four scratch words for a cut-off latch that is `latched`.
pub const fn encode(latched: bool) -> [u32; 4] {
    let state = if latched { LATCHED } else { CLEAR };
    [MAGIC, state, !state, MAGIC ^ state]
}

/// Whether the scratch words hold a valid record of a latched cut-off.
pub const fn cutoff_latched(words: [u32; 4]) -> bool {
    words[0] == MAGIC && words[1] == LATCHED && words[2] == !LATCHED && words[3] == MAGIC ^ LATCHED
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn round_trips() {
        assert!(cutoff_latched(encode(true)));
        assert!(!cutoff_latched(encode(false)));
        // Power-on value of the registers.
        assert!(!cutoff_latched([0; 4]));
    }

    proptest! {
        /// Any single corrupted word (or random content) is not a latch.
        #[test]
        fn garbage_is_no_record(words in any::<[u32; 4]>(), i in 0usize..4, flip in 1u32..) {
            let mut w = encode(true);
            w[i] ^= flip;
            prop_assert!(!cutoff_latched(w));
            prop_assume!(words != encode(true));
            prop_assert!(!cutoff_latched(words));
        }
    }
}
