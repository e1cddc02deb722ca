//! The pre-start self-test: before the motor leaves Off, the gate pin must
//! read low, both Hall lines must read high with the latches unpowered
//! (their open-drain outputs released, the pull-ups holding the lines), and
//! the battery must allow the motor: that last is the controller's own
//! start interlock (`StartRefused(LowBattery)`, its event and LED pattern),
//! so it is not repeated here. A gate that reads high at rest is a
//! shorted driver or a pin in the wrong function; a Hall line held low
//! while the latches are off is a short to ground or a latch fed from
//! elsewhere, and the rate sensing would start blind. What it cannot see:
//! an open Hall wire reads high like a healthy one; the rate sensor finds
//! that once the motor turns (`SensorFault::Disconnected` or `Stalled`).
//! (Crazyflie's supervisor runs the same kind of pre-arm checks.)

/// Why a start was refused.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SelfTestFault {
    /// The motor's gate reads high with the motor off.
    GateHigh,
    /// A Hall line reads low with the latches unpowered.
    HallLineLow,
}

/// What the pins read in the last pass, motor off and latches unpowered.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PreStart {
    pub gate_high: bool,
    pub hall_a_high: bool,
    pub hall_b_high: bool,
}

impl PreStart {
    /// A healthy board at rest (the default: a simulation without pins).
    pub const HEALTHY: Self = Self {
        gate_high: false,
        hall_a_high: true,
        hall_b_high: true,
    };

    /// The first reason not to start, if any.
    pub fn check(&self) -> Option<SelfTestFault> {
        if self.gate_high {
            Some(SelfTestFault::GateHigh)
        } else if !(self.hall_a_high && self.hall_b_high) {
            Some(SelfTestFault::HallLineLow)
        } else {
            None
        }
    }
}

impl Default for PreStart {
    fn default() -> Self {
        Self::HEALTHY
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nec::{for_each_edge, frame_pulses_us};
    use crate::{board, Level, MainLoop, MotorState};

    fn on(m: &mut MainLoop, t0: u64) -> crate::PassOutput {
        let mut edges = heapless::Vec::<(Level, u32), 80>::new();
        let pulses = frame_pulses_us(board::NEC_ADDRESS, board::NEC_CMD_ON);
        for_each_edge(t0 as u32, &pulses, |l, t| {
            let _ = edges.push((l, t));
        });
        let counts = board::BATTERY.mv_to_counts(3_900);
        m.pass(t0 + 80_000, edges, [], || counts)
    }

    #[test]
    fn a_failed_self_test_refuses_the_start_and_a_passed_one_allows_it() {
        let counts = board::BATTERY.mv_to_counts(3_900);
        for (pins, fault) in [
            (
                PreStart {
                    gate_high: true,
                    ..PreStart::HEALTHY
                },
                SelfTestFault::GateHigh,
            ),
            (
                PreStart {
                    hall_b_high: false,
                    ..PreStart::HEALTHY
                },
                SelfTestFault::HallLineLow,
            ),
        ] {
            let mut m = MainLoop::new(false);
            m.pass(0, [], [], || counts);
            m.set_prestart(pins);
            let o = on(&mut m, 200_000);
            assert_eq!(
                (o.state, o.refused_self_test),
                (MotorState::Off, Some(fault))
            );
            m.set_prestart(PreStart::HEALTHY);
            let o = on(&mut m, 400_000);
            assert_eq!((o.state, o.refused_self_test), (MotorState::Ramping, None));
            // Running: the latches are powered, the lines switch; the test
            // is for starts from Off only.
            m.set_prestart(pins);
            assert_ne!(on(&mut m, 600_000).state, MotorState::Off);
        }
    }
}
