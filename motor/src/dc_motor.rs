//! Brushed coreless DC motor: the electrical and mechanical equations and
//! two integrators, used by the controller tests, by `swimbot sim` and (as
//! WebAssembly) by the emulator's rotor.
//!
//! ```text
//! L di/dt = v - R i - k w
//! J dw/dt = k i - b w - tau_c sgn(w) - tau_load
//! ```
//! (SI units: k in N m/A equals the back-EMF constant in V s/rad.)
//!
//! Direct drive, no gearhead. Table I of the paper lists a 6 mm x 11 mm
//! motor with a 0.8 mm shaft that sticks out of the body into the tail
//! coupler: a bare motor, no room for a gearhead. The battery data agree:
//! 70 mAh in ~10 min is ~0.4 A average, close to this motor's stall current
//! at 3 V (0.43 A), whereas a motor turning a ~1 Hz tail through a 500:1
//! gearhead would run near no-load and draw ~30 mA. So the motor runs close
//! to stall: the viscous tail load in 3.5 Pa s oil (plus the shaft seal)
//! holds it at the observed ~1 Hz, and the speed is set by torque balance.

/// Motor constants. No datasheet exists for the paper's motor; the values
/// are those of typical 6 mm coreless motors (Faulhaber 0615, Nidec/Precision
/// Microdrives 6 mm coreless datasheets span these ranges).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotorParams {
    /// Terminal resistance: 6 mm coreless 3 V windings are 5-10 ohm; 7 ohm
    /// gives a 0.43 A stall current at 3 V, matching the ~0.42 A average
    /// draw implied by 70 mAh in 10 min.
    pub resistance_ohm: f64,
    /// Terminal inductance: coreless (ironless) windings are tens of uH;
    /// 25 uH gives L/R = 3.6 us, typical of these motors.
    pub inductance_h: f64,
    /// Torque constant = back-EMF constant: 0.5-1 mN m/A for 6 mm coreless;
    /// 0.8 mN m/A puts the no-load speed at 3 V near 34 krpm (datasheets:
    /// 20-40 krpm).
    pub torque_constant_n_m_per_a: f64,
    /// Rotor inertia: ~0.01 g cm^2 for a 6 mm coreless rotor.
    pub rotor_inertia_kg_m2: f64,
    /// Viscous friction of bearings and air; with the Coulomb term below it
    /// reproduces a typical no-load current of ~20 mA at 34 krpm.
    pub viscous_friction_n_m_s: f64,
    /// Brush and sleeve-bearing friction (15 mA of no-load current).
    pub coulomb_friction_n_m: f64,
}

impl MotorParams {
    /// The catalogue motor above. The built-in robot file
    /// (`host/data/robot.toml`) carries instead the motor calibrated on the
    /// paper's observed tail rates (`swimbot sim --fit-motor`): k = 2.44
    /// mN m/A and a seal drag b = 1.18e-4 N m s, far outside these
    /// catalogue ranges (the fit's intervals are wide; the model's tail
    /// load may be too small, or the motor not a bare 6 mm one).
    pub const CORELESS_6MM: MotorParams = MotorParams {
        resistance_ohm: 7.0,
        inductance_h: 25e-6,
        torque_constant_n_m_per_a: 0.8e-3,
        rotor_inertia_kg_m2: 1.0e-9,
        viscous_friction_n_m_s: 1.0e-9,
        coulomb_friction_n_m: 1.2e-5,
    };
}

/// Below this speed the Coulomb friction is blended linearly through zero
/// (`tanh`), which keeps the derivatives continuous for RK4. 0.01 rad/s is
/// 0.2 % of the ~6 rad/s working speed.
pub const FRICTION_SMOOTHING_RAD_S: f64 = 0.01;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MotorState {
    pub current_a: f64,
    pub speed_rad_s: f64,
}

impl MotorState {
    pub const REST: MotorState = MotorState {
        current_a: 0.0,
        speed_rad_s: 0.0,
    };
}

/// Time derivatives of a [`MotorState`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotorRates {
    pub current_a_per_s: f64,
    pub speed_rad_per_s2: f64,
}

/// A motor with what it drives: `load_inertia_kg_m2` is the coupler and
/// tail (a 1 mm copper helix of ~1.3 g at 2.5-7.5 mm radius: 1e-8 to 7e-8).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motor {
    pub params: MotorParams,
    pub load_inertia_kg_m2: f64,
}

impl Motor {
    pub fn new(params: MotorParams, load_inertia_kg_m2: f64) -> Self {
        Self {
            params,
            load_inertia_kg_m2,
        }
    }

    /// The paper's motor with tail #1's inertia.
    pub fn coreless_6mm() -> Self {
        Self::new(MotorParams::CORELESS_6MM, 1.0e-8)
    }

    pub fn inertia_kg_m2(&self) -> f64 {
        self.params.rotor_inertia_kg_m2 + self.load_inertia_kg_m2
    }

    pub fn torque_n_m(&self, current_a: f64) -> f64 {
        self.params.torque_constant_n_m_per_a * current_a
    }

    pub fn back_emf_v(&self, speed_rad_s: f64) -> f64 {
        self.params.torque_constant_n_m_per_a * speed_rad_s
    }

    /// Bearing, brush and seal friction at `speed_rad_s` (N m).
    pub fn friction_n_m(&self, speed_rad_s: f64) -> f64 {
        let p = &self.params;
        p.viscous_friction_n_m_s * speed_rad_s
            + p.coulomb_friction_n_m * libm::tanh(speed_rad_s / FRICTION_SMOOTHING_RAD_S)
    }

    /// d/dt of the state with `volts` across the terminals and
    /// `load_torque_n_m` opposing positive rotation.
    pub fn derivatives(&self, s: MotorState, volts: f64, load_torque_n_m: f64) -> MotorRates {
        let p = &self.params;
        MotorRates {
            current_a_per_s: (volts
                - p.resistance_ohm * s.current_a
                - self.back_emf_v(s.speed_rad_s))
                / p.inductance_h,
            speed_rad_per_s2: (self.torque_n_m(s.current_a)
                - self.friction_n_m(s.speed_rad_s)
                - load_torque_n_m)
                / self.inertia_kg_m2(),
        }
    }

    /// Classic RK4 with inputs held over the step. Explicit: needs
    /// `dt_s` below ~2.5 L/R (about 9 us here) to stay stable, and with the
    /// tail's drag the mechanical time constant J / c is only ~0.2 ms.
    pub fn step_rk4(
        &self,
        s: MotorState,
        volts: f64,
        load_torque_n_m: f64,
        dt_s: f64,
    ) -> MotorState {
        let f = |s: MotorState| self.derivatives(s, volts, load_torque_n_m);
        let add = |s: MotorState, r: MotorRates, h: f64| MotorState {
            current_a: s.current_a + h * r.current_a_per_s,
            speed_rad_s: s.speed_rad_s + h * r.speed_rad_per_s2,
        };
        let k1 = f(s);
        let k2 = f(add(s, k1, dt_s / 2.0));
        let k3 = f(add(s, k2, dt_s / 2.0));
        let k4 = f(add(s, k3, dt_s));
        MotorState {
            current_a: s.current_a
                + dt_s / 6.0
                    * (k1.current_a_per_s
                        + 2.0 * k2.current_a_per_s
                        + 2.0 * k3.current_a_per_s
                        + k4.current_a_per_s),
            speed_rad_s: s.speed_rad_s
                + dt_s / 6.0
                    * (k1.speed_rad_per_s2
                        + 2.0 * k2.speed_rad_per_s2
                        + 2.0 * k3.speed_rad_per_s2
                        + k4.speed_rad_per_s2),
        }
    }

    /// Linearly implicit (Rosenbrock-Euler) step, stable for any `dt_s`:
    /// the electrical time constant is microseconds and the loaded
    /// mechanical one a fraction of a millisecond, so millisecond
    /// control-loop steps need an implicit method. `load_damping_n_m_s` is d(load)/d(speed) (the
    /// tail's viscous coefficient), treated implicitly with the rest.
    pub fn step_implicit(
        &self,
        s: MotorState,
        volts: f64,
        load_torque_n_m: f64,
        load_damping_n_m_s: f64,
        dt_s: f64,
    ) -> MotorState {
        let p = &self.params;
        let r = self.derivatives(s, volts, load_torque_n_m);
        let j = self.inertia_kg_m2();
        let k = p.torque_constant_n_m_per_a;
        let x = s.speed_rad_s / FRICTION_SMOOTHING_RAD_S;
        let cosh = libm::cosh(x);
        let sech2 = 1.0 / (cosh * cosh);
        let dfric =
            p.viscous_friction_n_m_s + p.coulomb_friction_n_m * sech2 / FRICTION_SMOOTHING_RAD_S;
        // Jacobian of (di/dt, dw/dt) with respect to (i, w).
        let a11 = -p.resistance_ohm / p.inductance_h;
        let a12 = -k / p.inductance_h;
        let a21 = k / j;
        let a22 = -(dfric + load_damping_n_m_s) / j;
        // Solve (I - dt A) d = dt f.
        let m11 = 1.0 - dt_s * a11;
        let m12 = -dt_s * a12;
        let m21 = -dt_s * a21;
        let m22 = 1.0 - dt_s * a22;
        let det = m11 * m22 - m12 * m21;
        let b1 = dt_s * r.current_a_per_s;
        let b2 = dt_s * r.speed_rad_per_s2;
        let mut next = MotorState {
            current_a: s.current_a + (b1 * m22 - m12 * b2) / det,
            speed_rad_s: s.speed_rad_s + (m11 * b2 - m21 * b1) / det,
        };
        // Stiction: the linearisation cannot follow the friction's sign
        // change, and a long step would overshoot through zero and
        // oscillate. If the step crossed zero and the remaining torque at
        // standstill cannot beat the Coulomb friction, the rotor sticks.
        if next.speed_rad_s * s.speed_rad_s <= 0.0 && s.speed_rad_s != 0.0 {
            let load_at_rest = load_torque_n_m - load_damping_n_m_s * s.speed_rad_s;
            if (self.torque_n_m(next.current_a) - load_at_rest).abs() <= p.coulomb_friction_n_m {
                next.speed_rad_s = 0.0;
            }
        }
        next
    }

    /// Steady state (positive rotation) at `volts` against a load
    /// `tau = load_n_m + load_damping_n_m_s * w`; `None` if the motor
    /// cannot break away.
    pub fn steady_state(
        &self,
        volts: f64,
        load_n_m: f64,
        load_damping_n_m_s: f64,
    ) -> Option<MotorState> {
        let p = &self.params;
        let k = p.torque_constant_n_m_per_a;
        // k (v - k w) / R = b w + tau_c + load + c w
        let drive = k * volts / p.resistance_ohm - p.coulomb_friction_n_m - load_n_m;
        if drive <= 0.0 {
            return None;
        }
        let w = drive / (k * k / p.resistance_ohm + p.viscous_friction_n_m_s + load_damping_n_m_s);
        Some(MotorState {
            current_a: (volts - k * w) / p.resistance_ohm,
            speed_rad_s: w,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO_PI: f64 = core::f64::consts::TAU;

    fn assert_close(a: f64, b: f64, rel: f64) {
        assert!(
            (a - b).abs() <= rel * b.abs(),
            "{a} vs {b} (relative {rel})"
        );
    }

    #[test]
    fn datasheet_figures() {
        let m = Motor::coreless_6mm();
        // No load at 3 V: 20-40 krpm, ~20 mA.
        let s = m.steady_state(3.0, 0.0, 0.0).expect("turns");
        let krpm = s.speed_rad_s * 60.0 / TWO_PI / 1_000.0;
        assert!((20.0..=40.0).contains(&krpm), "{krpm} krpm");
        assert!((0.010..0.030).contains(&s.current_a), "{} A", s.current_a);
        // Stall at 3 V: ~0.43 A.
        assert!((3.0 / m.params.resistance_ohm - 0.43).abs() <= 0.01);
        // Electrical time constant in the microseconds.
        let tau_e = m.params.inductance_h / m.params.resistance_ohm;
        assert!((1e-6..1e-5).contains(&tau_e));
    }

    #[test]
    fn rk4_and_implicit_reach_the_analytic_steady_state() {
        let m = Motor::coreless_6mm();
        let c = 5e-5;
        let want = m.steady_state(3.0, 0.0, c).expect("turns");
        let mut a = MotorState::REST;
        let mut b = MotorState::REST;
        for _ in 0..10_000 {
            a = m.step_rk4(a, 3.0, c * a.speed_rad_s, 1e-6);
        }
        for _ in 0..100 {
            b = m.step_implicit(b, 3.0, c * b.speed_rad_s, c, 1e-3);
        }
        assert_close(a.speed_rad_s, want.speed_rad_s, 1e-3);
        assert_close(a.current_a, want.current_a, 1e-3);
        assert_close(b.speed_rad_s, want.speed_rad_s, 1e-3);
        assert_close(b.current_a, want.current_a, 1e-3);
    }

    #[test]
    fn implicit_tracks_rk4_through_a_transient() {
        // Spin-down from no-load speed with the terminals shorted (the
        // electrical transient is microseconds, the mechanical time constant
        // J R / k^2 = 0.12 s without tail drag): the implicit step at 2 us
        // follows the 0.2 us RK4 reference within 1 % of the start speed.
        let m = Motor::coreless_6mm();
        let start = m.steady_state(3.0, 0.0, 0.0).expect("turns");
        let (mut a, mut b) = (start, start);
        for _ in 0..100 {
            for _ in 0..2_000 {
                a = m.step_rk4(a, 0.0, 0.0, 0.2e-6);
            }
            for _ in 0..200 {
                b = m.step_implicit(b, 0.0, 0.0, 0.0, 2e-6);
            }
            assert!(
                (a.speed_rad_s - b.speed_rad_s).abs() < 0.01 * start.speed_rad_s,
                "{a:?} {b:?}"
            );
        }
        // 40 ms of 120 ms time constant.
        assert!(b.speed_rad_s < 0.8 * start.speed_rad_s, "braking: {b:?}");
    }

    #[test]
    fn friction_holds_a_weakly_driven_rotor() {
        let m = Motor::coreless_6mm();
        // 10 mV cannot beat the Coulomb friction (needs ~0.1 V).
        assert!(m.steady_state(0.01, 0.0, 0.0).is_none());
        let mut s = MotorState::REST;
        for _ in 0..1_000 {
            s = m.step_implicit(s, 0.01, 0.0, 0.0, 1e-3);
        }
        assert!(s.speed_rad_s.abs() < FRICTION_SMOOTHING_RAD_S, "{s:?}");
    }
}
