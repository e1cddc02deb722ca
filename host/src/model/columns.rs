//! The model's own per-case quantities ([`crate::data::model_quantities`]:
//! load torque, thrust, body drag, tail power, U, Omega_b, Reynolds
//! numbers), computed from one force balance (eq. 11) per case and
//! attached to the cases, so that a law in one of them reads a number
//! instead of solving the model again.
//!
//! The quantities are those of the model made of the effects before the
//! first effect that reads a model quantity ([`Model::quantities_model`]):
//! a law in the tail's load torque, fitted on top of a model, scales with
//! that model's torque, not with the torque of a model that already holds
//! the law (which would make the law depend on itself).

use super::{Model, ModelError};
use crate::data::model_quantities::{slot, Derived, N_MODEL};
use crate::data::{Case, Dataset};
use crate::physics::solve::TailDrive;
use nalgebra::Vector6;
use rayon::prelude::*;

/// The model quantities of `case` under `model` (all its effects), in the
/// order of [`crate::data::model_quantities::MODEL_QUANTITIES`].
pub fn of_case(model: &Model, case: &Case) -> Result<[f64; N_MODEL], ModelError> {
    let fb = model.force_balance(case)?;
    let v = fb.solve().map_err(|source| ModelError::Solve {
        case: case.id.clone(),
        source,
    })?;
    let p = super::prediction(case, v)?;
    // The tail's own motion: the body's translation, and its rate in the
    // lab frame (the motor's rate plus the body's for a relative drive).
    let omega_t = match fb.drive {
        TailDrive::Absolute => fb.tail_rate_rad_s,
        TailDrive::RelativeToBody => fb.tail_rate_rad_s + v[3],
    };
    let mut vt: Vector6<f64> = v;
    vt[3] = omega_t;
    let tail_wrench = fb.tail * vt;
    let body_wrench = fb.body * v;
    let mu = case.viscosity_pa_s;
    let rho = case.density_kg_m3;
    let wire_speed = ((omega_t * case.amplitude_mm * 1e-3).powi(2) + v[0].powi(2)).sqrt();
    let mut out = [0.0; N_MODEL];
    out[slot::TAIL_TORQUE] = tail_wrench[3];
    out[slot::THRUST] = -fb.tail[(0, 3)] * omega_t;
    out[slot::BODY_DRAG] = body_wrench[0];
    out[slot::TAIL_POWER] = vt.dot(&tail_wrench);
    out[slot::U] = p.u_mm_s;
    out[slot::OMEGA_BODY] = p.omega_body_hz;
    out[slot::BODY_REYNOLDS] = rho * v[0] * case.body_diameter_mm * 1e-3 / mu;
    out[slot::TAIL_REYNOLDS] = rho * wire_speed * case.wire_diameter_mm * 1e-3 / mu;
    Ok(out)
}

/// Identifies a model within one run: its coefficients, tail method,
/// degrees of freedom and every effect (by identity) with its values.
/// Attached quantities carry the key of the model they came from; a model
/// whose [`Model::quantities_model`] has another key recomputes them.
pub fn key(model: &Model) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut h = std::collections::hash_map::DefaultHasher::new();
    format!(
        "{:?} {:?} {:?}",
        model.coefficients, model.tail_method, model.dofs
    )
    .hash(&mut h);
    for e in &model.effects {
        // The name too: compiled-in effects are unit structs, and two
        // zero-sized statics may share one address, so their identities
        // alone could not tell body-confinement from motor-frame.
        e.effect.name().hash(&mut h);
        e.effect.identity().hash(&mut h);
        for v in &e.values {
            v.to_bits().hash(&mut h);
        }
    }
    h.finish()
}

/// `case` carrying the quantities of `model` (all its effects).
pub fn with_quantities(model: &Model, case: &Case) -> Result<Case, ModelError> {
    Ok(Case {
        derived: Derived {
            model: Some(of_case(model, case)?),
            key: key(model),
        },
        ..case.clone()
    })
}

/// `data` with every case carrying the model quantities of
/// [`Model::quantities_model`] (parallel over cases; one force balance
/// each).
pub fn attach(model: &Model, data: &Dataset) -> Result<Dataset, ModelError> {
    let beneath = model.quantities_model();
    let cases = data
        .cases
        .par_iter()
        .map(|c| with_quantities(&beneath, c))
        .collect::<Result<Vec<Case>, ModelError>>()?;
    Ok(Dataset {
        cases,
        ..data.clone()
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::model_quantities::MODEL_QUANTITIES;
    use crate::physics::body::BodyResistance;
    use crate::physics::tail::axial_closed_form;

    /// The columns against eqs. 3, 10 and 11 solved by hand for the paper's
    /// x-only runs: the tail's three axial resistances from the closed
    /// form, the body's from the spheroid, the 2x2 balance by Cramer.
    #[test]
    fn the_columns_agree_with_the_force_balance_solved_by_hand() {
        let data = crate::data::paper();
        let model = Model::base();
        let attached = attach(&model, &data).unwrap();
        for (case, with) in data.cases.iter().zip(&attached.cases) {
            let helix = case.helix();
            let drag = model
                .coefficients
                .local_drag(&helix, case.viscosity_pa_s)
                .unwrap();
            let a = axial_closed_form(&helix, drag);
            let body = BodyResistance::prolate_spheroid(&case.body(), case.viscosity_pa_s)
                .unwrap()
                .matrix();
            let (dx, ex) = (body[(0, 0)], body[(3, 3)]);
            let w = 2.0 * std::f64::consts::PI * case.frequency_hz;
            // Row x: (D_x + B11) U = -B14 w; row wx (tail row dropped): E_x W = -B44 w.
            let u = -a.thrust_n_s * w / (dx + a.drag_n_s_per_m);
            let big_w = -a.torque_n_m_s * w / ex;
            let torque = a.thrust_n_s * u + a.torque_n_m_s * w;
            let power =
                a.drag_n_s_per_m * u * u + 2.0 * a.thrust_n_s * u * w + a.torque_n_m_s * w * w;
            let want = [
                ("model_tail_torque_n_m", torque),
                ("model_thrust_n", -a.thrust_n_s * w),
                ("model_body_drag_n", dx * u),
                ("model_tail_power_w", power),
                ("model_u_mm_s", u * 1e3),
                ("model_omega_body_hz", -big_w / (2.0 * std::f64::consts::PI)),
            ];
            for (id, x) in want {
                let q = MODEL_QUANTITIES.iter().find(|q| q.id == id).unwrap();
                let got = q.of(with);
                assert!(
                    (got - x).abs() <= 1e-10 * x.abs(),
                    "{id} on {}: {got} against {x}",
                    case.id
                );
            }
            // The model's own outputs agree too.
            let p = model.predict(case).unwrap();
            assert_eq!(with.derived.model(slot::U), p.u_mm_s);
            // Physics: the thrust balances the drag of body and tail at U,
            // and the tail's power is its torque times its rate plus the
            // axial force times U (B_t symmetric).
            let total_drag = (dx + a.drag_n_s_per_m) * u;
            assert!((-a.thrust_n_s * w - total_drag).abs() <= 1e-12 * total_drag.abs());
            let f_t = a.drag_n_s_per_m * u + a.thrust_n_s * w;
            assert!((power - (torque * w + f_t * u)).abs() <= 1e-10 * power.abs());
            assert!(power > 0.0 && torque > 0.0, "{}", case.id);
        }
    }

    #[test]
    fn the_reynolds_numbers_follow_their_definitions_and_scale_with_density() {
        let data = crate::data::paper();
        let a = attach(&Model::base(), &data).unwrap();
        let mut denser = data.clone();
        for c in &mut denser.cases {
            c.density_kg_m3 *= 2.0;
        }
        let b = attach(&Model::base(), &denser).unwrap();
        for (x, y) in a.cases.iter().zip(&b.cases) {
            let re = x.density_kg_m3 * x.derived.model(slot::U) * 1e-3 * x.body_diameter_mm * 1e-3
                / x.viscosity_pa_s;
            let got = x.derived.model(slot::BODY_REYNOLDS);
            assert!((got - re).abs() <= 1e-12 * re.abs());
            // Density does not enter the Stokes balance: U is unchanged and
            // both Reynolds numbers double exactly.
            assert_eq!(x.derived.model(slot::U), y.derived.model(slot::U));
            for s in [slot::BODY_REYNOLDS, slot::TAIL_REYNOLDS] {
                let r = y.derived.model(s) / x.derived.model(s);
                assert!((r - 2.0).abs() < 1e-12, "{r}");
            }
        }
    }
}
