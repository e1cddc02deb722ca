//! The tail's rate from timestamped Hall edges: two Hall latches in
//! quadrature over a multi-pole ring magnet on the motor's coupler
//! (`docs/rate-sensing.md`), decoded into signed steps, averaged over one
//! whole turn, and checked for the sensor faults a lab meets: a reversed
//! rotation, one channel gone quiet (a broken wire, a moved sensor), and
//! a rate no tail in oil can have (a lost tail spinning free, or noise).
//!
//! Why a whole turn: the ring's poles are never evenly spaced (pitch errors
//! of a few degrees) and two sensors are never exactly 90 electrical
//! degrees apart, so single edge intervals carry a fixed pattern that
//! repeats every turn. The mean over exactly `edges_per_turn` intervals
//! cancels that pattern whatever it is; the cost is a lag of half a turn,
//! which the controller's gains are designed around.
//!
//! Timestamps are the 1 MHz timer's low 32 bits, as for the IR edges; they
//! wrap every 71.6 min and differences are taken modulo 2^32. An interval
//! that reads as more than 2^31 us (time going backwards, an out-of-order
//! queue) or as zero restarts the window instead of producing a rate.

/// Largest supported ring: 8 pole pairs, 32 quadrature edges per turn.
pub const MAX_EDGES_PER_TURN: usize = 32;

/// Consecutive back-and-forth steps that mean one channel no longer
/// switches: a healthy rotation never reverses step by step.
const ALTERNATIONS_FOR_FAULT: u8 = 4;

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HallConfig {
    /// Pole pairs of the ring magnet: each pair gives 4 quadrature edges
    /// per turn (1..=8).
    pub pole_pairs: u8,
    /// Consecutive backward steps that make a reversal fault.
    pub reverse_steps: u8,
    /// Turn-averaged rates above this cannot be a tail in oil (mHz).
    pub max_plausible_mhz: u32,
    /// A gap between edges longer than this restarts the turn window, so
    /// that a stop is not averaged into the next run's first rate.
    pub window_reset_us: u32,
}

impl HallConfig {
    /// The proposed sensor: an 8-pole (4 pole pairs) ring, 16 edges a turn;
    /// reversal after a quarter turn backwards; 10 Hz is 7x the fastest
    /// tail of the paper (1.5 Hz) and 1/50 of a tail-less motor's speed.
    pub const RING_8_POLE: Self = Self {
        pole_pairs: 4,
        reverse_steps: 4,
        max_plausible_mhz: 10_000,
        window_reset_us: 2_000_000,
    };

    /// Quadrature edges per turn, clamped to the supported range.
    pub const fn edges_per_turn(&self) -> usize {
        let e = 4 * self.pole_pairs as usize;
        if e == 0 {
            4
        } else if e > MAX_EDGES_PER_TURN {
            MAX_EDGES_PER_TURN
        } else {
            e
        }
    }
}

/// A fault that stopped the motor: the first four from the Hall sensor
/// (see `rate::control`), the last two from the motor supervisor
/// (`supervisor`), which reads the same edges independently.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SensorFault {
    /// Driven but no edge for the stall time: a stalled rotor, or both
    /// sensor wires off (the two cannot be told apart from edges alone).
    Stalled,
    /// The quadrature sequence runs backwards.
    Reversed,
    /// Only one channel switches: a broken wire or a misplaced sensor.
    Disconnected,
    /// Faster than any tail in oil: the tail is lost, or the edges are noise.
    Overspeed,
    /// Driven hard but hardly turning: a jammed or nearly jammed tail.
    Jammed,
    /// The `I^2 t` estimate put the winding or the driver past its limit.
    Overheated,
}

/// A turn-averaged rate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RateEstimate {
    pub rate_mhz: u32,
    /// The window spans a whole turn (the pole pattern cancels); before
    /// that the rate is the mean over the edges seen so far.
    pub whole_turn: bool,
    /// Timestamp of the window's oldest edge: the rate describes the time
    /// since then.
    pub since_us: u32,
    /// Edge intervals in the window (1..=edges_per_turn).
    pub intervals: u16,
}

#[derive(Clone, Debug)]
pub struct RateEstimator {
    cfg: HallConfig,
    /// Timestamps of the last forward steps, a ring of `edges_per_turn + 1`.
    times: [u32; MAX_EDGES_PER_TURN + 1],
    head: usize,
    len: usize,
    phase: Option<u8>,
    last_step: i8,
    backward_run: u8,
    alternations: u8,
    forward_edges: u32,
    glitches: u32,
    last_edge_us: Option<u32>,
}

/// Position in the Gray sequence 00 -> 01 -> 11 -> 10 (A leads B forward).
const fn gray(a: bool, b: bool) -> u8 {
    match (a, b) {
        (false, false) => 0,
        (false, true) => 1,
        (true, true) => 2,
        (true, false) => 3,
    }
}

impl RateEstimator {
    pub const fn new(cfg: HallConfig) -> Self {
        Self {
            cfg,
            times: [0; MAX_EDGES_PER_TURN + 1],
            head: 0,
            len: 0,
            phase: None,
            last_step: 0,
            backward_run: 0,
            alternations: 0,
            forward_edges: 0,
            glitches: 0,
            last_edge_us: None,
        }
    }

    pub fn config(&self) -> &HallConfig {
        &self.cfg
    }

    /// Forget the window and the fault counters (at every motor start);
    /// the sensor's last level and the edge counters stay.
    pub fn restart(&mut self) {
        self.len = 0;
        self.backward_run = 0;
        self.alternations = 0;
        self.last_step = 0;
    }

    /// One queued edge: its timestamp and both channels' levels read in the
    /// same interrupt.
    pub fn edge(&mut self, t_us: u32, a: bool, b: bool) {
        let now = gray(a, b);
        let Some(before) = self.phase.replace(now) else {
            // The first edge marks a position: the window starts here.
            self.last_edge_us = Some(t_us);
            self.push(t_us);
            return;
        };
        let step: i8 = match now.wrapping_sub(before) & 3 {
            0 => return, // a bounce that the queue saw twice: no movement
            1 => 1,
            3 => -1,
            _ => {
                // Both channels changed between two interrupts: an edge was
                // lost, so the next interval would be wrong.
                self.glitches = self.glitches.wrapping_add(1);
                self.len = 0;
                self.last_edge_us = Some(t_us);
                return;
            }
        };
        let gap_us = self.last_edge_us.map(|t| t_us.wrapping_sub(t));
        self.last_edge_us = Some(t_us);
        if gap_us.is_some_and(|g| g == 0 || g > self.cfg.window_reset_us) {
            self.len = 0;
        }
        self.alternations = if step == -self.last_step {
            self.alternations.saturating_add(1)
        } else {
            0
        };
        self.last_step = step;
        if step < 0 {
            self.backward_run = self.backward_run.saturating_add(1);
            self.len = 0;
            return;
        }
        self.backward_run = 0;
        self.forward_edges = self.forward_edges.wrapping_add(1);
        self.push(t_us);
    }

    fn push(&mut self, t_us: u32) {
        let cap = self.cfg.edges_per_turn() + 1;
        self.head = (self.head + 1) % cap;
        self.times[self.head] = t_us;
        self.len = (self.len + 1).min(cap);
    }

    /// The mean rate over the window (up to one turn); `None` before two
    /// forward edges.
    pub fn estimate(&self) -> Option<RateEstimate> {
        if self.len < 2 {
            return None;
        }
        let e = self.cfg.edges_per_turn();
        let cap = e + 1;
        let oldest = self.times[(self.head + cap - (self.len - 1)) % cap];
        let span_us = self.times[self.head].wrapping_sub(oldest);
        let intervals = (self.len - 1) as u64;
        // intervals / e turns over span_us: mHz = intervals * 1e9 / (e span),
        // rounded to the nearest mHz (truncating read 0.5 mHz low on
        // average: 0.05-0.1 % at 0.5-1 Hz, in the run log's rates too).
        let denom = e as u64 * u64::from(span_us);
        let rate = (intervals * 1_000_000_000 + denom / 2).checked_div(denom)?;
        Some(RateEstimate {
            rate_mhz: u32::try_from(rate).unwrap_or(u32::MAX),
            whole_turn: self.len == cap,
            since_us: oldest,
            intervals: u16::try_from(intervals).unwrap_or(u16::MAX),
        })
    }

    /// The fault the edges show, if any (stall is judged by the
    /// controller, which knows whether the motor is driven).
    pub fn fault(&self) -> Option<SensorFault> {
        if self.alternations >= ALTERNATIONS_FOR_FAULT {
            Some(SensorFault::Disconnected)
        } else if self.backward_run >= self.cfg.reverse_steps.max(1) {
            Some(SensorFault::Reversed)
        } else if self
            .estimate()
            .is_some_and(|r| r.whole_turn && r.rate_mhz > self.cfg.max_plausible_mhz)
        {
            Some(SensorFault::Overspeed)
        } else {
            None
        }
    }

    /// Forward edges since power-up (wrapping): a change means a new rate.
    pub fn forward_edges(&self) -> u32 {
        self.forward_edges
    }

    /// Lost-edge transitions since power-up, for the log.
    pub fn glitches(&self) -> u32 {
        self.glitches
    }

    /// Timestamp of the last edge of either direction.
    pub fn last_edge_us(&self) -> Option<u32> {
        self.last_edge_us
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Forward quadrature levels for step `k`.
    fn levels(k: u32) -> (bool, bool) {
        [(false, false), (false, true), (true, true), (true, false)][(k % 4) as usize]
    }

    fn spin(est: &mut RateEstimator, t0: u32, dt_us: u32, steps: u32) -> u32 {
        let mut t = t0;
        for k in 1..=steps {
            t = t.wrapping_add(dt_us);
            let (a, b) = levels(k);
            est.edge(t, a, b);
        }
        t
    }

    #[test]
    fn one_hertz_over_a_whole_turn_across_the_timer_wrap() {
        let mut est = RateEstimator::new(HallConfig::RING_8_POLE);
        est.edge(u32::MAX - 200_000, false, false);
        // 16 edges a turn at 1 Hz: 62.5 ms apart.
        spin(&mut est, u32::MAX - 200_000, 62_500, 20);
        let r = est.estimate().expect("rate");
        assert!(r.whole_turn);
        assert_eq!(r.rate_mhz, 1_000);
        assert_eq!(est.fault(), None);
    }

    #[test]
    fn a_fixed_pole_pattern_cancels_over_a_turn() {
        // Intervals alternating 20 % long and short: single intervals are
        // off by 20 %, the whole-turn mean is exact.
        let mut est = RateEstimator::new(HallConfig::RING_8_POLE);
        est.edge(0, false, false);
        let mut t = 0u32;
        for k in 1..=40u32 {
            t += if k % 2 == 0 { 75_000 } else { 50_000 };
            let (a, b) = levels(k);
            est.edge(t, a, b);
        }
        assert_eq!(est.estimate().map(|r| r.rate_mhz), Some(1_000));
    }

    #[test]
    fn faults_from_the_edge_pattern() {
        let cfg = HallConfig::RING_8_POLE;
        // Backwards: the Gray sequence read in reverse.
        let mut est = RateEstimator::new(cfg);
        est.edge(0, false, false);
        for k in 1..=4u32 {
            let (a, b) = levels(4 - k % 4);
            est.edge(k * 1_000, a, b);
        }
        assert_eq!(est.fault(), Some(SensorFault::Reversed));
        // Channel B stuck low: A toggles alone, steps alternate.
        let mut est = RateEstimator::new(cfg);
        for k in 0..6u32 {
            est.edge(k * 50_000, k % 2 == 1, false);
        }
        assert_eq!(est.fault(), Some(SensorFault::Disconnected));
        // 20 Hz whole-turn rate: overspeed.
        let mut est = RateEstimator::new(cfg);
        est.edge(0, false, false);
        spin(&mut est, 0, 3_125, 17);
        assert_eq!(est.fault(), Some(SensorFault::Overspeed));
        est.restart();
        assert_eq!(est.estimate(), None);
    }

    #[test]
    fn a_lost_edge_or_a_long_gap_restarts_the_window() {
        let mut est = RateEstimator::new(HallConfig::RING_8_POLE);
        est.edge(0, false, false);
        let t = spin(&mut est, 0, 62_500, 20);
        est.edge(t + 62_500, true, true); // 00 -> 11 after step 20 (00): skipped 01
        assert_eq!(est.estimate(), None);
        assert_eq!(est.glitches(), 1);
        let mut est = RateEstimator::new(HallConfig::RING_8_POLE);
        est.edge(0, false, false);
        let t = spin(&mut est, 0, 62_500, 20);
        est.edge(t + 3_000_000, false, true);
        assert_eq!(est.estimate(), None, "one edge after a stop is no rate");
    }
}
