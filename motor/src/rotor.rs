//! The motor turning its tail, and the Hall ring on the coupler: what a
//! board simulator needs from the mechanics. Per step the mean terminal
//! voltage goes in (held over the step, as the host's simulation holds a
//! PWM period's average), the motor advances by one linearly implicit step
//! ([`Motor::step_implicit`], the host's integrator) against the tail's
//! load `tau_0 + c w` (quasi-static Stokes flow: [`TailLoad`]), and the
//! quadrature edges the ring passed come out with their times.
//!
//! The ring has `E` edges a turn (4 per pole pair); edge `n` sits at
//! `(n + e_(n mod E)) / E` turns, `e` a fixed error per edge in pitches
//! (pole pitch and latch placement: the same every turn). After edge `n`
//! the latches read the Gray state `n mod 4` (00, 01, 11, 10 forwards).
//! Edge times within a step are interpolated linearly in angle.
//!
//! Two faults of the drive train: a heavier tail (the load scaled) and a
//! seized coupler, a holding torque far beyond stall added to the Coulomb
//! friction (`set_brake_n_m`): the rotor sticks as friction holds it.

use crate::dc_motor::{Motor, MotorParams, MotorState};
use core::f64::consts::TAU;

/// The tail's torque on the motor: `tau_0 + c w` (N m, N m s), `w` the
/// motor's rate (tail relative to body).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TailLoad {
    pub tau0_n_m: f64,
    pub damping_n_m_s: f64,
}

impl TailLoad {
    pub fn torque_n_m(&self, speed_rad_s: f64) -> f64 {
        self.tau0_n_m + self.damping_n_m_s * speed_rad_s
    }

    fn scaled(self, factor: f64) -> TailLoad {
        TailLoad {
            tau0_n_m: self.tau0_n_m * factor,
            damping_n_m_s: self.damping_n_m_s * factor,
        }
    }
}

/// The most edges a turn the ring may have (a 32-pole ring).
pub const MAX_EDGES_PER_TURN: usize = 64;

/// One edge passed during a step: seconds after the step's start and the
/// latches' levels after it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Crossing {
    pub after_s: f64,
    pub a: bool,
    pub b: bool,
}

const GRAY: [(bool, bool); 4] = [(false, false), (false, true), (true, true), (true, false)];

#[derive(Clone, Debug)]
pub struct Rotor {
    motor: Motor,
    load: TailLoad,
    load_scale: f64,
    brake_n_m: f64,
    state: MotorState,
    /// Motor angle in turns.
    turns: f64,
    edges_per_turn: usize,
    offsets: [f64; MAX_EDGES_PER_TURN],
}

impl Rotor {
    /// At rest, edge 0 just passed. `edges_per_turn` is clamped to
    /// `1..=MAX_EDGES_PER_TURN`.
    pub fn new(motor: Motor, load: TailLoad, edges_per_turn: usize) -> Self {
        Rotor {
            motor,
            load,
            load_scale: 1.0,
            brake_n_m: 0.0,
            state: MotorState::REST,
            turns: 0.0,
            edges_per_turn: edges_per_turn.clamp(1, MAX_EDGES_PER_TURN),
            offsets: [0.0; MAX_EDGES_PER_TURN],
        }
    }

    /// The tail's load times `factor` (a heavier tail, thicker oil).
    pub fn set_load_scale(&mut self, factor: f64) {
        self.load_scale = factor;
    }

    /// A holding torque added to the Coulomb friction (N m): a seized
    /// coupler when it exceeds the stall torque, 0 to free it again.
    pub fn set_brake_n_m(&mut self, torque_n_m: f64) {
        self.brake_n_m = torque_n_m.max(0.0);
    }

    /// Edge `index`'s fixed position error in pitches (clamped to +-0.45
    /// so that the edges stay in order).
    pub fn set_edge_offset(&mut self, index: usize, pitches: f64) {
        if let Some(o) = self.offsets.get_mut(index) {
            *o = pitches.clamp(-0.45, 0.45);
        }
    }

    pub fn speed_rad_s(&self) -> f64 {
        self.state.speed_rad_s
    }

    pub fn rate_hz(&self) -> f64 {
        self.state.speed_rad_s / TAU
    }

    pub fn current_a(&self) -> f64 {
        self.state.current_a
    }

    pub fn turns(&self) -> f64 {
        self.turns
    }

    pub fn edges_per_turn(&self) -> usize {
        self.edges_per_turn
    }

    /// The motor as it is now: friction plus the brake.
    fn driven(&self) -> Motor {
        let mut m = self.motor;
        m.params.coulomb_friction_n_m += self.brake_n_m;
        m
    }

    fn load(&self) -> TailLoad {
        self.load.scaled(self.load_scale)
    }

    /// Mean terminal voltage for a steady motor rate `rate_hz` against
    /// the present load: `V = R (tau_c + tau_0) / k + 2 pi f (R (b + c) / k + k)`.
    pub fn volts_for_rate(&self, rate_hz: f64) -> f64 {
        let MotorParams {
            resistance_ohm: r,
            torque_constant_n_m_per_a: k,
            viscous_friction_n_m_s: b,
            coulomb_friction_n_m: tc,
            ..
        } = self.driven().params;
        let l = self.load();
        r * (tc + l.tau0_n_m) / k + TAU * rate_hz * (r * (b + l.damping_n_m_s) / k + k)
    }

    /// The load scale at which the steady rate at `volts` is `rate_hz`
    /// (the balance above is linear in the scale); `None` if no positive
    /// scale gets there (the unloaded motor is already slower).
    pub fn load_scale_for(&self, volts: f64, rate_hz: f64) -> Option<f64> {
        let p = self.driven().params;
        let (r, k) = (p.resistance_ohm, p.torque_constant_n_m_per_a);
        let w = TAU * rate_hz;
        let fixed = r * p.coulomb_friction_n_m / k + w * (r * p.viscous_friction_n_m_s / k + k);
        let per_scale = r * (self.load.tau0_n_m + self.load.damping_n_m_s * w) / k;
        let scale = (volts - fixed) / per_scale;
        (scale.is_finite() && scale > 0.0).then_some(scale)
    }

    /// Advances `dt_s` at mean terminal voltage `volts`; writes the edges
    /// passed into `out` (at most its length; a step passing more drops the
    /// rest) and returns how many it wrote.
    pub fn step(&mut self, volts: f64, dt_s: f64, out: &mut [Crossing]) -> usize {
        let load = self.load();
        let w0 = self.state.speed_rad_s;
        self.state = self.driven().step_implicit(
            self.state,
            volts,
            load.torque_n_m(w0),
            load.damping_n_m_s,
            dt_s,
        );
        let e = self.edges_per_turn as f64;
        let from = self.turns * e;
        self.turns += 0.5 * (w0 + self.state.speed_rad_s) * dt_s / TAU;
        let to = self.turns * e;
        self.crossings(from, to, dt_s, out)
    }

    /// Position of edge `n` in edge pitches.
    fn edge_at(&self, n: i64) -> f64 {
        n as f64 + self.offsets[n.rem_euclid(self.edges_per_turn as i64) as usize]
    }

    fn crossings(&self, from: f64, to: f64, dt_s: f64, out: &mut [Crossing]) -> usize {
        if from == to {
            return 0;
        }
        let forwards = to > from;
        let (lo, hi) = if forwards { (from, to) } else { (to, from) };
        let mut written = 0;
        // Offsets are below half a pitch: only edges within one of the
        // interval's ends can lie inside it.
        let first = libm::floor(lo) as i64 - 1;
        let last = libm::ceil(hi) as i64 + 1;
        for i in 0..=(last - first) {
            let n = if forwards { first + i } else { last - i };
            let p = self.edge_at(n);
            let inside = if forwards {
                p > lo && p <= hi
            } else {
                p >= lo && p < hi
            };
            if !inside || written == out.len() {
                continue;
            }
            // Forwards past edge n: state n; backwards past it: state n - 1.
            let state = if forwards { n } else { n - 1 };
            let (a, b) = GRAY[state.rem_euclid(4) as usize];
            out[written] = Crossing {
                after_s: (p - from) / (to - from) * dt_s,
                a,
                b,
            };
            written += 1;
        }
        written
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotor() -> Rotor {
        let params = MotorParams {
            torque_constant_n_m_per_a: 2.44e-3,
            viscous_friction_n_m_s: 1.18e-4,
            ..MotorParams::CORELESS_6MM
        };
        let load = TailLoad {
            tau0_n_m: 0.0,
            damping_n_m_s: 1.27e-5,
        };
        Rotor::new(Motor::new(params, 1e-8), load, 16)
    }

    fn run(r: &mut Rotor, volts: f64, seconds: f64) -> usize {
        let mut buf = [Crossing::default(); 8];
        let mut n = 0;
        for _ in 0..(seconds * 1e3) as usize {
            n += r.step(volts, 1e-3, &mut buf);
        }
        n
    }

    #[test]
    fn settles_on_its_steady_line() {
        let mut r = rotor();
        run(&mut r, 3.0, 2.0);
        let v = r.volts_for_rate(r.rate_hz());
        assert!((v - 3.0).abs() < 1e-6, "{v} V for {} Hz", r.rate_hz());
    }

    #[test]
    fn edges_match_turns_and_run_in_gray_order() {
        let mut r = rotor();
        let mut buf = [Crossing::default(); 8];
        let mut last = (false, false);
        let mut count = 0;
        for _ in 0..5_000 {
            let n = r.step(3.0, 1e-3, &mut buf);
            for c in &buf[..n] {
                let i = GRAY.iter().position(|g| *g == last).unwrap();
                assert_eq!((c.a, c.b), GRAY[(i + 1) % 4], "forwards Gray order");
                assert!((0.0..=1e-3).contains(&c.after_s));
                last = (c.a, c.b);
            }
            count += n;
        }
        assert_eq!(count as i64, libm::floor(r.turns() * 16.0) as i64);
    }

    #[test]
    fn a_heavier_tail_turns_slower_and_a_seized_one_not_at_all() {
        let mut free = rotor();
        run(&mut free, 3.0, 2.0);
        let mut heavy = rotor();
        heavy.set_load_scale(20.0);
        run(&mut heavy, 3.0, 2.0);
        assert!(
            heavy.rate_hz() < 0.5 * free.rate_hz(),
            "{} {}",
            heavy.rate_hz(),
            free.rate_hz()
        );
        let mut seized = rotor();
        seized.set_brake_n_m(1e-2);
        assert_eq!(run(&mut seized, 3.7, 10.0), 0);
        seized.set_brake_n_m(0.0);
        assert!(run(&mut seized, 3.0, 2.0) > 0, "freed again");
    }

    #[test]
    fn the_load_scale_for_a_rate_gives_that_rate() {
        let mut r = rotor();
        let scale = r.load_scale_for(3.0, 0.2).unwrap();
        r.set_load_scale(scale);
        assert!((r.volts_for_rate(0.2) - 3.0).abs() < 1e-9);
        run(&mut r, 3.0, 3.0);
        assert!((r.rate_hz() / 0.2 - 1.0).abs() < 1e-6, "{}", r.rate_hz());
        assert!(rotor().load_scale_for(3.0, 100.0).is_none());
    }

    #[test]
    fn edge_offsets_move_edges_but_not_their_count() {
        let mut a = rotor();
        let mut b = rotor();
        for i in 0..16 {
            b.set_edge_offset(i, if i % 2 == 0 { 0.2 } else { -0.2 });
        }
        let (na, nb) = (run(&mut a, 3.0, 10.0), run(&mut b, 3.0, 10.0));
        assert!(na.abs_diff(nb) <= 1, "{na} {nb}");
    }

    proptest::proptest! {
        /// Whatever the drive (forwards, backwards, reversing) and the
        /// edge errors, the latches read the Gray state of the last edge
        /// behind the rotor's angle, and every reported edge is a step to
        /// a neighbouring state.
        #[test]
        fn the_latches_follow_the_angle(
            volts in proptest::collection::vec(-4.0f64..4.0, 1..120),
            offsets in proptest::collection::vec(-0.4f64..0.4, 16),
        ) {
            let mut r = rotor();
            for (i, o) in offsets.iter().enumerate() {
                r.set_edge_offset(i, *o);
            }
            // The state of the last edge at or behind the angle (edge
            // positions n + e_n, in pitches).
            let behind = |r: &Rotor| {
                let at = r.turns() * 16.0;
                let mut n = libm::floor(at) as i64 + 1;
                while r.edge_at(n) > at {
                    n -= 1;
                }
                n.rem_euclid(4) as usize
            };
            let mut buf = [Crossing::default(); MAX_EDGES_PER_TURN];
            let mut state = behind(&r);
            for v in volts {
                for _ in 0..20 {
                    let n = r.step(v, 1e-3, &mut buf);
                    for c in &buf[..n] {
                        let next = GRAY.iter().position(|g| *g == (c.a, c.b)).unwrap();
                        proptest::prop_assert!(next == (state + 1) % 4 || next == (state + 3) % 4);
                        state = next;
                    }
                }
            }
            proptest::prop_assert_eq!(state, behind(&r));
        }
    }
}
