//! The rate sensor on the host: a multi-pole ring magnet on the motor's
//! coupler passing two Hall latches in quadrature (`docs/rate-sensing.md`),
//! turned into the timestamped edges the firmware's interrupt would queue.
//!
//! What a real sensor adds to the ideal edge angles `2 pi n / E`, each
//! modelled because each reaches the estimator differently:
//! - a fixed angular error per edge (pole pitch and sensor placement), the
//!   same every turn: drawn once from `N(0, pitch_error_deg)`;
//! - interrupt latency, uniform in `0..=latency_max_us` per edge (a wake
//!   from sleep, an IR edge being served);
//! - the 1 MHz timer: timestamps are whole microseconds, low 32 bits.
//!
//! Edge times are interpolated linearly in angle within a simulation tick
//! (the loaded mechanical time constant is ~0.2 ms, the tick 1 ms, an edge
//! interval tens of ms).

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, Normal};
use std::f64::consts::TAU;

/// Imperfections of the sensor and the timestamping.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorNoise {
    /// RMS angular error of each edge position (mechanical degrees).
    pub pitch_error_deg: f64,
    /// Largest interrupt latency (us); uniform from 0.
    pub latency_max_us: f64,
    /// RMS noise of the battery ADC reading (LSB).
    pub adc_noise_lsb: f64,
    pub seed: u64,
}

impl SensorNoise {
    pub const NONE: SensorNoise = SensorNoise {
        pitch_error_deg: 0.0,
        latency_max_us: 0.0,
        adc_noise_lsb: 0.0,
        seed: 0,
    };

    /// A plausible board: 1.5 degree edge errors (a few per cent of the
    /// 22.5 degree pitch of an 8-pole ring), up to 5 us latency, and the
    /// RP2040 ADC's ~2 LSB RMS noise (about 9 effective bits of 12).
    pub const TYPICAL: SensorNoise = SensorNoise {
        pitch_error_deg: 1.5,
        latency_max_us: 5.0,
        adc_noise_lsb: 2.0,
        seed: 26,
    };
}

/// A sensor failure, from a time on, for the fault scenarios.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Failure {
    /// Channel B stops switching (a broken wire): only A's edges arrive.
    ChannelStuck,
    /// No edge at all (both wires off, or the rotor jammed in its bearing
    /// while the model's rotor turns on).
    Silent,
    /// A and B wired the other way round: the sequence runs backwards.
    Swapped,
}

/// One queued edge: timer low word and both channels' levels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HallEdge {
    pub t_us: u32,
    pub a: bool,
    pub b: bool,
}

/// The ring and its two sensors, following the rotor's angle.
#[derive(Debug, Clone)]
pub struct HallRing {
    edges_per_turn: usize,
    offsets_rad: Vec<f64>,
    latency_max_us: f64,
    /// Edges passed, signed: the sensor state is `levels(index)`.
    index: i64,
    rng: StdRng,
    failure: Option<(f64, Failure)>,
    /// B's level when it got stuck.
    stuck_b: Option<bool>,
}

/// Channel levels after `index` forward steps (Gray sequence 00 01 11 10).
pub fn levels(index: i64) -> (bool, bool) {
    [(false, false), (false, true), (true, true), (true, false)][index.rem_euclid(4) as usize]
}

impl HallRing {
    pub fn new(edges_per_turn: usize, noise: &SensorNoise) -> Self {
        let edges_per_turn = edges_per_turn.max(1);
        let mut rng = StdRng::seed_from_u64(noise.seed);
        let sd = noise.pitch_error_deg.abs().to_radians();
        let offsets_rad = (0..edges_per_turn)
            .map(|_| match Normal::new(0.0, sd) {
                Ok(n) if sd > 0.0 => n.sample(&mut rng),
                _ => 0.0,
            })
            .collect();
        Self {
            edges_per_turn,
            offsets_rad,
            latency_max_us: noise.latency_max_us.max(0.0),
            index: 0,
            rng,
            failure: None,
            stuck_b: None,
        }
    }

    /// The sensor fails at `at_s` (robot time).
    pub fn with_failure(mut self, at_s: f64, failure: Failure) -> Self {
        self.failure = Some((at_s, failure));
        self
    }

    /// Angle of edge `n` (rad), pattern included.
    fn edge_angle(&self, n: i64) -> f64 {
        let e = self.edges_per_turn as i64;
        n as f64 * TAU / e as f64 + self.offsets_rad[n.rem_euclid(e) as usize]
    }

    /// The edges while the rotor turns from `theta0` at `t0_s` to `theta1`
    /// at `t1_s`, in order.
    pub fn advance(&mut self, theta0: f64, theta1: f64, t0_s: f64, t1_s: f64) -> Vec<HallEdge> {
        let mut out = Vec::new();
        let at = |theta: f64| {
            if theta1 == theta0 {
                t1_s
            } else {
                t0_s + (t1_s - t0_s) * ((theta - theta0) / (theta1 - theta0)).clamp(0.0, 1.0)
            }
        };
        while theta1 >= self.edge_angle(self.index + 1) {
            self.index += 1;
            let t = at(self.edge_angle(self.index));
            out.extend(self.stamp(t, self.index - 1));
        }
        while theta1 < self.edge_angle(self.index) {
            let t = at(self.edge_angle(self.index));
            self.index -= 1;
            out.extend(self.stamp(t, self.index + 1));
        }
        out
    }

    /// The edge from state `before` to the current one, as the interrupt
    /// would queue it (none if the failed sensor gives none).
    fn stamp(&mut self, t_s: f64, before: i64) -> Option<HallEdge> {
        let edge = self.ideal(t_s);
        let failure = self.failure.filter(|f| t_s >= f.0).map(|f| f.1);
        match failure {
            None => Some(edge),
            Some(Failure::Silent) => None,
            Some(Failure::Swapped) => Some(HallEdge {
                a: edge.b,
                b: edge.a,
                ..edge
            }),
            Some(Failure::ChannelStuck) => {
                let stuck = *self.stuck_b.get_or_insert(levels(before).1);
                // B's own edges raise no interrupt any more.
                (levels(before).0 != edge.a).then_some(HallEdge { b: stuck, ..edge })
            }
        }
    }

    fn ideal(&mut self, t_s: f64) -> HallEdge {
        let latency = if self.latency_max_us > 0.0 {
            self.rng.gen_range(0.0..=self.latency_max_us)
        } else {
            0.0
        };
        let (a, b) = levels(self.index);
        HallEdge {
            // The timer's low word: whole microseconds, wrapping.
            t_us: (t_s * 1e6 + latency).floor() as u64 as u32,
            a,
            b,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_turn_gives_e_edges_in_gray_order_and_back() {
        let mut ring = HallRing::new(16, &SensorNoise::NONE);
        let edges = ring.advance(0.0, TAU + 1e-9, 0.0, 1.0);
        assert_eq!(edges.len(), 16);
        // 1 Hz: 62.5 ms to the first edge, floored to the microsecond.
        assert!((62_499..=62_500).contains(&edges[0].t_us), "{:?}", edges[0]);
        assert_eq!((edges[15].a, edges[15].b), (false, false));
        let back = ring.advance(TAU, TAU - 0.5, 1.0, 1.1);
        // 0.5 rad back crosses two edges (22.5 degrees = 0.39 rad apart).
        assert_eq!(back.len(), 2);
        assert_eq!((back[0].a, back[0].b), levels(15));
    }

    #[test]
    fn failures_change_what_the_interrupt_sees() {
        let turn = |f: Failure| {
            let mut ring = HallRing::new(16, &SensorNoise::NONE).with_failure(0.0, f);
            ring.advance(0.0, TAU + 1e-9, 0.0, 1.0)
        };
        assert!(turn(Failure::Silent).is_empty());
        let stuck = turn(Failure::ChannelStuck);
        assert_eq!(stuck.len(), 8, "A's edges only");
        assert!(stuck.iter().all(|e| !e.b));
        let swapped = turn(Failure::Swapped);
        assert_eq!(
            (swapped[0].a, swapped[0].b),
            (true, false),
            "00 -> 10: backwards"
        );
    }

    #[test]
    fn the_pattern_repeats_every_turn() {
        let noise = SensorNoise {
            pitch_error_deg: 2.0,
            ..SensorNoise::NONE
        };
        let mut ring = HallRing::new(16, &noise);
        let edges = ring.advance(0.0, 3.0 * TAU, 0.0, 3.0);
        let dt = |i: usize| f64::from(edges[i + 1].t_us) - f64::from(edges[i].t_us);
        for i in 0..16 {
            assert!((dt(i) - dt(i + 16)).abs() <= 1.0);
        }
        // Whole turns are whole seconds at 1 Hz, to the microsecond.
        assert!((f64::from(edges[16].t_us) - f64::from(edges[0].t_us) - 1e6).abs() <= 1.0);
    }
}
