//! The observed tail rate is the motor's rate, relative to the body. The
//! paper prescribes it as the tail's absolute rate and drops the tail's
//! x-torque row from the balance; with a motor between body and tail, the
//! tail turns at `Omega_b + omega` and the whole robot is torque-free, so
//! the body's counter-rotation is solved together with the swimming speed.
//!
//! Reference: Purcell, Proc. Natl. Acad. Sci. 94 (1997) 11307 (torque-free
//! swimmer with a counter-rotating body); the paper, eq. 11 and section II.B.

use super::Effect;
use crate::data::Case;
use crate::physics::solve::{ForceBalance, TailDrive};

pub struct MotorFrame;

impl Effect for MotorFrame {
    fn name(&self) -> &'static str {
        "motor-frame"
    }
    fn statement(&self) -> &'static str {
        "f is the tail's rate relative to the body; the whole robot is torque-free (no free parameter)"
    }
    fn reference(&self) -> &'static str {
        "Purcell, PNAS 94 (1997) 11307"
    }
    fn balance(&self, _p: &[f64], _case: &Case, fb: &mut ForceBalance) {
        fb.drive = TailDrive::RelativeToBody;
    }
}
