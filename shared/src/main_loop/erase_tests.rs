//! Dormancy and pending flash erases, on the host: the firmware's order of
//! a pass (VBUS and the pending erase handed in, the pass, then one erase
//! if it allows one) around a count of 64 KiB blocks still to erase, each
//! stalling the chip before the next pass. DORMANT must never cut the
//! sequence, and must still come once it is done.
use super::*;
use proptest::prelude::*;
use std::vec::Vec;

extern crate std;

const MV: u32 = 3_900;
const PASS_US: u64 = 1_000;
/// A 64 KiB block erase, typical (W25Q16JV datasheet, tBE2).
const BLOCK_US: u64 = 150_000;

/// The firmware's loop around a pass, with `left` blocks to erase.
struct Chip {
    m: MainLoop,
    left: u32,
    t_us: u64,
    /// Pass times of the erases, and the first pass that may go dormant.
    erased_at: Vec<u64>,
    dormant_at: Option<u64>,
}

impl Chip {
    fn new(left: u32) -> Self {
        Self {
            m: MainLoop::new(false),
            left,
            t_us: 0,
            erased_at: Vec::new(),
            dormant_at: None,
        }
    }

    /// One pass at the current time; the next comes a wake period later,
    /// or after the stall of the erase it ran.
    fn pass(&mut self, usb: bool, ir_edge: bool) -> PassOutput {
        let now = self.t_us;
        self.m.set_usb_connected(usb);
        self.m.set_erase_pending(self.left > 0);
        let edges = ir_edge.then_some((Level::Low, now as u32));
        let out = self
            .m
            .pass(now, edges, [], || board::BATTERY.mv_to_counts(MV));
        self.t_us += PASS_US;
        if out.may_erase_flash && self.left > 0 {
            self.left -= 1;
            self.erased_at.push(now);
            self.t_us += BLOCK_US;
        }
        if out.may_go_dormant && self.dormant_at.is_none() {
            self.dormant_at = Some(now);
        }
        out
    }

    /// Passes until `until_us` or the first that may go dormant.
    fn run(&mut self, until_us: u64, usb: bool) {
        while self.t_us < until_us && self.dormant_at.is_none() {
            self.pass(usb, false);
        }
    }
}

#[test]
fn an_erase_pending_when_usb_is_unplugged_after_the_idle_time_finishes_before_dormant() {
    let mut chip = Chip::new(8);
    let unplug_us = board::DORMANT_AFTER_IDLE_US + 2_000_000;
    chip.run(unplug_us, true);
    assert_eq!(chip.dormant_at, None, "dormant with USB connected");
    assert!(chip.erased_at.is_empty(), "an erase with USB connected");
    chip.run(unplug_us + 8 * (BLOCK_US + PASS_US) + 10 * PASS_US, false);
    assert_eq!(chip.left, 0, "dormant with {} blocks to erase", chip.left);
    let last = *chip.erased_at.last().unwrap_or(&0);
    // The idle time is long over: each pass erases, and the one after the
    // last erase goes dormant.
    assert_eq!(chip.erased_at[0], unplug_us);
    assert_eq!(chip.dormant_at, Some(last + BLOCK_US + PASS_US));
}

#[test]
fn an_ir_edge_during_the_erases_pauses_them_and_restarts_the_idle_time() {
    let mut chip = Chip::new(8);
    let start_us = board::DORMANT_AFTER_IDLE_US + 2_000_000;
    chip.run(start_us, true);
    while chip.erased_at.len() < 3 {
        chip.pass(false, false);
    }
    let edge_us = chip.t_us;
    let o = chip.pass(false, true);
    assert!(!o.may_erase_flash && !o.may_go_dormant);
    chip.run(edge_us + 2 * board::DORMANT_AFTER_IDLE_US, false);
    assert_eq!(chip.left, 0);
    assert!(
        chip.erased_at[3] >= edge_us + ERASE_QUIET_US,
        "an erase in a frame"
    );
    let dormant = chip.dormant_at.unwrap_or(u64::MAX);
    assert!(dormant >= edge_us + board::DORMANT_AFTER_IDLE_US);
    assert!(dormant <= edge_us + board::DORMANT_AFTER_IDLE_US + PASS_US);
}

#[test]
fn no_erase_pending_sleeps_after_the_idle_time_as_before() {
    let mut chip = Chip::new(0);
    chip.run(2 * board::DORMANT_AFTER_IDLE_US, false);
    let dormant = chip.dormant_at.unwrap_or(u64::MAX);
    assert!(dormant >= board::DORMANT_AFTER_IDLE_US);
    assert!(dormant <= board::DORMANT_AFTER_IDLE_US + PASS_US);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1024))]

    /// Any number of blocks, USB unplugged at any time, IR noise at any
    /// times: never dormant with a block left, never an erase with USB in
    /// or within the quiet time of an edge, and dormant in the end.
    #[test]
    fn dormant_never_cuts_an_erase_and_always_comes(
        blocks in 0u32..=8,
        unplug_ms in 0u64..20_000,
        noise_ms in proptest::collection::vec(0u64..25_000, 0..4),
    ) {
        let mut chip = Chip::new(blocks);
        let mut last_ir = None;
        let mut previous: Option<u64> = None;
        let end_us = 60_000_000;
        while chip.t_us < end_us && chip.dormant_at.is_none() {
            let now = chip.t_us;
            let usb = now < unplug_ms * 1_000;
            // Noise since the previous pass (queued through any stall).
            let edge = noise_ms
                .iter()
                .map(|n| n * 1_000)
                .any(|n| n <= now && previous.is_none_or(|p| n > p));
            previous = Some(now);
            if edge {
                last_ir = Some(now);
            }
            let erased = chip.erased_at.len();
            let o = chip.pass(usb, edge);
            if chip.erased_at.len() > erased {
                prop_assert!(!usb, "an erase with USB in at {} us", now);
                prop_assert!(last_ir.is_none_or(|t| now - t >= ERASE_QUIET_US));
            }
            if o.may_go_dormant {
                prop_assert_eq!(chip.left, 0, "dormant at {} us", now);
            }
        }
        prop_assert!(chip.dormant_at.is_some(), "never dormant ({} blocks left)", chip.left);
    }
}
