//! The force balance of the whole swimmer, paper eqs. 1, 2 and 11.
//!
//! Unknown: the robot's rigid-body velocity `V = [U; Omega_b]` in the
//! swimmer frame. Known: the tail's rotation rate `omega` about x. With the
//! body resistance `B_b`, the tail's `B_t`, extra resistances `B_x` acting
//! on `V` (e.g. a self-consistent back-flow) and known external loads `F`:
//!
//! * [`TailDrive::Absolute`] (the paper): the tail's x-rotation is `omega` in
//!   the lab frame, so the tail's 4th row and column are dropped from the
//!   unknowns (`P = diag(1,1,1,0,1,1)`):
//!   `(B_b + P B_t P + B_x) V = -B_t [0; omega e_x] + F` (eq. 11).
//! * [`TailDrive::RelativeToBody`]: `omega` is the motor's rate, the tail
//!   turns at `Omega_b + omega`; the whole robot's torque balance holds:
//!   `(B_b + B_t + B_x) V = -B_t [0; omega e_x] + F`.
//!
//! Degrees of freedom outside the mask are held at zero by dropping their
//! rows and columns ("one may restrict the motion ... by setting rows and
//! columns to zero", section II.B); the paper's runs keep x-translation and
//! x-rotation only.

use nalgebra::{Matrix6, Vector6};

/// Which rigid-body velocity components are free.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Dofs(pub [bool; 6]);

impl Dofs {
    /// x-translation and x-rotation only: the paper's runs.
    pub const AXIAL: Dofs = Dofs([true, false, false, true, false, false]);
    pub const ALL: Dofs = Dofs([true; 6]);
}

/// How the tail's prescribed rotation rate is to be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TailDrive {
    /// The rate is the tail's absolute rate (the paper's eq. 11).
    Absolute,
    /// The rate is relative to the body (a motor's rate).
    RelativeToBody,
}

/// Everything eq. 11 needs, assembled by the model and its effects.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceBalance {
    pub body: Matrix6<f64>,
    pub tail: Matrix6<f64>,
    /// Extra resistance acting on the robot's velocity `V`.
    pub extra: Matrix6<f64>,
    /// Known external force and torque on the robot (N, N m), e.g. weight.
    pub load: Vector6<f64>,
    pub drive: TailDrive,
    /// Tail rotation rate `omega = 2 pi f` (rad/s).
    pub tail_rate_rad_s: f64,
    pub dofs: Dofs,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    #[error("the force balance is singular or ill-conditioned (reciprocal condition number {rcond:.2e}): some free degree of freedom has no resistance")]
    Singular { rcond: f64 },
    #[error("the force balance has non-finite entries (NaN or infinity): check the inputs")]
    NonFinite,
}

impl ForceBalance {
    /// A balance with only the body and tail, x-only, the paper's drive.
    pub fn new(body: Matrix6<f64>, tail: Matrix6<f64>, tail_rate_rad_s: f64) -> Self {
        ForceBalance {
            body,
            tail,
            extra: Matrix6::zeros(),
            load: Vector6::zeros(),
            drive: TailDrive::Absolute,
            tail_rate_rad_s,
            dofs: Dofs::AXIAL,
        }
    }

    /// The system matrix and right-hand side before the DOF restriction.
    pub fn system(&self) -> (Matrix6<f64>, Vector6<f64>) {
        let tail_in_system = match self.drive {
            TailDrive::Absolute => {
                let mut t = self.tail;
                t.row_mut(3).fill(0.0);
                t.column_mut(3).fill(0.0);
                t
            }
            TailDrive::RelativeToBody => self.tail,
        };
        let a = self.body + tail_in_system + self.extra;
        let rhs = -self.tail.column(3) * self.tail_rate_rad_s + self.load;
        (a, rhs)
    }

    /// Solve for `V = [U; Omega_b]` (m/s, rad/s).
    pub fn solve(&self) -> Result<Vector6<f64>, SolveError> {
        if self.dofs == Dofs::AXIAL {
            return self.solve_axial();
        }
        let (mut a, mut rhs) = self.system();
        if a.iter().chain(rhs.iter()).any(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite);
        }
        // A fixed DOF becomes the trivial equation V_i = 0, scaled like the
        // matrix so the conditioning check below stays meaningful.
        let scale = a.diagonal().amax().max(f64::MIN_POSITIVE);
        for (i, free) in self.dofs.0.iter().enumerate() {
            if !free {
                a.row_mut(i).fill(0.0);
                a.column_mut(i).fill(0.0);
                a[(i, i)] = scale;
                rhs[i] = 0.0;
            }
        }
        let rcond = reciprocal_condition(&a);
        if rcond.is_nan() || rcond < 1e-13 {
            return Err(SolveError::Singular { rcond });
        }
        a.lu().solve(&rhs).ok_or(SolveError::Singular { rcond })
    }
}

impl ForceBalance {
    /// The paper's x-only system is 2x2 (rows and columns 1 and 4): solved
    /// in closed form, with the same conditioning check, because sweeps of
    /// millions of geometries spend most of their time here.
    fn solve_axial(&self) -> Result<Vector6<f64>, SolveError> {
        let (a, rhs) = self.system();
        let (a00, a03, a30, a33) = (a[(0, 0)], a[(0, 3)], a[(3, 0)], a[(3, 3)]);
        let (r0, r3) = (rhs[0], rhs[3]);
        if ![a00, a03, a30, a33, r0, r3].iter().all(|v| v.is_finite()) {
            return Err(SolveError::NonFinite);
        }
        let det = a00 * a33 - a03 * a30;
        let norm = (a00.abs() + a30.abs()).max(a03.abs() + a33.abs());
        let inv_norm = (a33.abs() + a30.abs()).max(a03.abs() + a00.abs()) / det.abs();
        let rcond = 1.0 / (norm * inv_norm);
        if rcond.is_nan() || rcond < 1e-13 {
            return Err(SolveError::Singular {
                rcond: if rcond.is_nan() { 0.0 } else { rcond },
            });
        }
        let mut v = Vector6::zeros();
        v[0] = (a33 * r0 - a03 * r3) / det;
        v[3] = (a00 * r3 - a30 * r0) / det;
        Ok(v)
    }
}

/// Cheap 1-norm reciprocal condition estimate of a small matrix, exact
/// enough to tell a healthy system from a degenerate one.
fn reciprocal_condition(a: &Matrix6<f64>) -> f64 {
    let norm1 = |m: &Matrix6<f64>| m.column_iter().map(|c| c.lp_norm(1)).fold(0.0, f64::max);
    match a.try_inverse() {
        Some(inv) => 1.0 / (norm1(a) * norm1(&inv)),
        None => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diag(v: [f64; 6]) -> Matrix6<f64> {
        Matrix6::from_diagonal(&Vector6::from_row_slice(&v))
    }

    #[test]
    fn axial_solution_matches_the_two_equations_by_hand() {
        let body = diag([2.0, 3.0, 3.0, 5.0, 7.0, 7.0]);
        let mut tail = diag([1.0, 1.0, 1.0, 0.5, 1.0, 1.0]);
        tail[(0, 3)] = -0.2;
        tail[(3, 0)] = -0.2;
        let omega = 6.0;
        let v = ForceBalance::new(body, tail, omega).solve().unwrap();
        // (D + B11) U = -B14 omega ;  E Omega = -B44 omega (tail row 4 dropped)
        assert!((v[0] - 0.2 * 6.0 / 3.0).abs() < 1e-14);
        assert!((v[3] + 0.5 * 6.0 / 5.0).abs() < 1e-14);
        assert_eq!(v[1], 0.0);
    }

    #[test]
    fn axial_fast_path_equals_the_general_masked_solve() {
        let body = diag([2.0, 3.0, 3.0, 5.0, 7.0, 7.0]);
        let mut tail = diag([1.0, 1.5, 1.2, 0.5, 1.0, 1.1]);
        tail[(0, 3)] = -0.2;
        tail[(3, 0)] = -0.2;
        tail[(1, 3)] = 0.05;
        tail[(3, 1)] = 0.05;
        for drive in [TailDrive::Absolute, TailDrive::RelativeToBody] {
            let mut fb = ForceBalance::new(body, tail, 6.0);
            fb.drive = drive;
            fb.load[0] = 0.3;
            let fast = fb.solve().unwrap();
            // The general path, by hand: masked 6x6 LU.
            let (mut a, mut rhs) = fb.system();
            for i in [1, 2, 4, 5] {
                a.row_mut(i).fill(0.0);
                a.column_mut(i).fill(0.0);
                a[(i, i)] = 1.0;
                rhs[i] = 0.0;
            }
            let reference = a.lu().solve(&rhs).unwrap();
            assert!((fast - reference).norm() < 1e-14 * reference.norm());
        }
    }

    #[test]
    fn relative_drive_keeps_the_whole_torque_balance() {
        let body = diag([2.0, 3.0, 3.0, 5.0, 7.0, 7.0]);
        let mut tail = diag([1.0, 1.0, 1.0, 0.5, 1.0, 1.0]);
        tail[(0, 3)] = -0.2;
        tail[(3, 0)] = -0.2;
        let mut fb = ForceBalance::new(body, tail, 6.0);
        fb.drive = TailDrive::RelativeToBody;
        let v = fb.solve().unwrap();
        // Net torque on body + tail is zero: E Om + B41 U + B44 (Om + omega) = 0
        let torque = 5.0 * v[3] - 0.2 * v[0] + 0.5 * (v[3] + 6.0);
        let force = 2.0 * v[0] + 1.0 * v[0] - 0.2 * (v[3] + 6.0);
        assert!(torque.abs() < 1e-13 && force.abs() < 1e-13);
    }

    #[test]
    fn a_free_dof_without_resistance_is_reported_not_nan() {
        let fb = ForceBalance {
            dofs: Dofs::ALL,
            ..ForceBalance::new(diag([1.0, 0.0, 1.0, 1.0, 1.0, 1.0]), Matrix6::zeros(), 1.0)
        };
        assert!(matches!(fb.solve(), Err(SolveError::Singular { .. })));
        let fb = ForceBalance::new(
            diag([f64::NAN, 1.0, 1.0, 1.0, 1.0, 1.0]),
            Matrix6::zeros(),
            1.0,
        );
        assert_eq!(fb.solve(), Err(SolveError::NonFinite));
    }
}
