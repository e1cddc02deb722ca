//! Where a feature's physics can act: the feature x place table of the
//! search. A law is offered only at a place where its feature could
//! change the physics, so that an unphysical placement cannot win by
//! chance among hundreds of laws.
//!
//! | feature | places | why |
//! |---|---|---|
//! | `density_kg_m3` (the oil's density) | `load.force` | at the robot's Reynolds numbers (far below 1 in the viscous oils it swims in) inertia is absent from the resistances of resistive-force theory; density acts only through buoyancy, an axial force |
//! | `model_tail_torque_n_m` (the tail's load torque) | `drive.rate`, `load.torque` | a real motor slows under load (its rate falls along its torque-speed line), and a bearing's friction grows with the torque it carries |
//! | `model_tail_power_w` (the tail's power) | `drive.rate`, `load.torque` | a motor limited by its power (or its supply's current) slows as the power drawn grows; otherwise as the torque, which sets the power at a given rate |
//! | `model_thrust_n` (the tail's thrust) | `tail.drag`, `load.force`, `load.torque` | the thrust presses the shaft on its thrust bearing, whose friction is a torque on the body |
//! | `model_body_drag_n` (the body's drag) | `load.force` | an axial load that grows with the drag (a drag not linear in U is a law in the predicted U) |
//! | `model_u_mm_s` (the predicted U) | `body.D_x`, `tail.drag`, `load.force` | a speed sets translational resistances (a drag not linear in U, a back-flow growing with U) and speed-dependent axial loads (a wall's friction) |
//! | `model_omega_body_hz` (the predicted Omega_b) | `body.E_x`, `load.torque` | the body's rotation sets its rotational resistance and a rotating seal's friction torque; not the drive: a motor held relative to the body is the catalogue's `motor-frame` (exact, in `f + Omega_b`), and the body's balance `E_x Omega_b` is the torque the motor carries, so a drive law in Omega_b would only shadow one in the load torque |
//! | `model_body_reynolds` (Re_b at the predicted U) | `body.D_x`, `body.E_x` | a Reynolds number changes the resistance of the body it is built on (inertial corrections to Stokes drag), and nothing else |
//! | `model_tail_reynolds` (Re_t at the wire's speed) | `tail.c_t`, `tail.c_n`, `tail.viscosity`, `tail.drag`, `tail.thrust`, `tail.torque` | the same for the wire: its local resistances and the tail matrix built on them |
//! | a recorded column (`recorded.NAME`) | every place | the lab's name for it says nothing the tool can read: a temperature may set the viscosity (acting against the weight, as a load), a day the robot's trim, a cell voltage the drive; the criterion, not the library, decides |
//! | every other feature | every place | geometry, kinematics, viscosity and the recorded Reynolds numbers can each set a resistance, a coupling, a load or the drive |
//!
//! The model's own quantities ([`crate::data::model_quantities`]) are
//! placed by their physics only: a law in the load torque at the body's
//! translational resistance would be a number that happens to order the
//! cases, not a mechanism. Nor is one offered at the place that computes
//! it: a tail torque scaled by a power of the model's own tail torque (or
//! power), a thrust by its thrust, a body drag by its drag, only reshapes
//! that output across the cases (on the paper's data such a law took 96 %
//! of what `body-correction` leaves, as `tau^-0.84`: the measured Omega_b
//! follows the rate less than the model's, a description, not a
//! mechanism).
//!
//! The model's Reynolds numbers must also be large enough to act at all
//! ([`large_enough`]): inertia changes a Stokes resistance by a relative
//! `O(Re)` (Oseen's `3 Re/16` for a sphere), under 2 % below `Re = 0.1`,
//! the size of a good measurement's noise; a law in a Reynolds number that
//! stays below it on every case would put a visible change where inertia
//! can make none (the paper's robot: `Re_t` about 0.01). They then stay
//! out of the library. (The recorded `reynolds` and `body_reynolds`
//! groups are features of the setup and stay in it as before.)
//!
//! References: J. Lighthill, *Mathematical Biofluiddynamics* (1975), ch. 3
//! (resistive-force theory at zero Reynolds number); E. M. Purcell, Am. J.
//! Phys. 45 (1977) 3 (life at low Reynolds number); P. Oseen, *Neuere
//! Methoden und Ergebnisse in der Hydrodynamik* (1927) (the first inertial
//! correction to Stokes drag); A. Hughes, *Electric Motors and Drives*,
//! 4th ed. (2013), ch. 3 (a DC motor's torque-speed line).

use crate::data::quantities::Quantity;
use crate::data::{Dataset, Feature};
use crate::effects::place::Place;

/// Below this on every case a model Reynolds number cannot act (module docs).
pub const MIN_ACTING_REYNOLDS: f64 = 0.1;

/// Whether `feature` can act at all on this design: false for a model
/// Reynolds number below [`MIN_ACTING_REYNOLDS`] on every case (module docs).
pub fn large_enough(feature: &Quantity, data: &Dataset) -> bool {
    if !matches!(feature.id, "model_body_reynolds" | "model_tail_reynolds") {
        return true;
    }
    data.cases
        .iter()
        .any(|c| feature.of(c).abs() >= MIN_ACTING_REYNOLDS)
}

/// What a `none-needed` verdict says of the recorded columns on a design
/// at neutral trim (net weight 0 on every case): a viscosity common to body
/// and tail scales every resistance of the Stokes balance alike, so with
/// no non-viscous force to act against it cancels from U and Omega_b, and
/// a column that set it leaves no trace. `None` when the design has a net
/// weight (the viscosity then acts against it, as a load the search tries)
/// or no recorded column the search could use.
pub fn unobservable_note(data: &Dataset) -> Option<String> {
    if data.cases.iter().any(|c| c.net_weight_g != 0.0) {
        return None;
    }
    let columns: Vec<String> = super::search::usable_features(data)
        .into_iter()
        .filter_map(|u| match u.feature {
            Feature::Recorded(n) => Some(n.to_string()),
            Feature::Quantity(_) => None,
        })
        .collect();
    (!columns.is_empty()).then(|| {
        format!(
            "a viscosity that followed the recorded {} on body and tail alike would cancel from the Stokes balance at this neutral trim (net weight 0): these data cannot show it; a run with a net weight would",
            columns.join(", ")
        )
    })
}

/// Where each model quantity's physics can act (module docs).
const MODEL_PLACES: &[(&str, &[Place])] = &[
    (
        "model_tail_torque_n_m",
        &[Place::DriveRate, Place::LoadTorque],
    ),
    ("model_tail_power_w", &[Place::DriveRate, Place::LoadTorque]),
    (
        "model_thrust_n",
        &[Place::TailDrag, Place::LoadForce, Place::LoadTorque],
    ),
    ("model_body_drag_n", &[Place::LoadForce]),
    (
        "model_u_mm_s",
        &[Place::BodyTranslation, Place::TailDrag, Place::LoadForce],
    ),
    (
        "model_omega_body_hz",
        &[Place::BodyRotation, Place::LoadTorque],
    ),
    (
        "model_body_reynolds",
        &[Place::BodyTranslation, Place::BodyRotation],
    ),
    ("model_tail_reynolds", &Place::TAIL),
];

/// Whether a law in `feature` may sit at `place` (module docs): a recorded
/// column at every place.
pub fn acts_at(feature: &Feature, place: Place) -> bool {
    feature
        .quantity()
        .is_none_or(|q| quantity_acts_at(q, place))
}

/// Whether a law in the library quantity `feature` may sit at `place`.
pub fn quantity_acts_at(feature: &Quantity, place: Place) -> bool {
    if feature.id == "density_kg_m3" {
        return place == Place::LoadForce;
    }
    match MODEL_PLACES.iter().find(|(id, _)| *id == feature.id) {
        Some((_, places)) => places.contains(&place),
        None => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::model_quantities::MODEL_QUANTITIES;
    use crate::data::quantities::FIELDS;

    fn places_of(q: &Quantity) -> Vec<Place> {
        Place::ALL
            .into_iter()
            .filter(|&p| quantity_acts_at(q, p))
            .collect()
    }

    #[test]
    fn the_papers_reynolds_numbers_are_too_small_to_act() {
        let paper = crate::data::paper();
        let data = crate::model::columns::attach(&crate::model::Model::base(), &paper).unwrap();
        let re_t = MODEL_QUANTITIES
            .iter()
            .find(|q| q.id == "model_tail_reynolds")
            .unwrap();
        assert!(!large_enough(re_t, &data));
        // The same oil a hundred times thinner: Re a hundred times larger.
        let mut thin = paper.clone();
        for c in &mut thin.cases {
            c.viscosity_pa_s /= 100.0;
        }
        let thin = crate::model::columns::attach(&crate::model::Model::base(), &thin).unwrap();
        assert!(large_enough(re_t, &thin));
        assert!(large_enough(&MODEL_QUANTITIES[0], &data));
    }

    #[test]
    fn no_model_quantity_acts_at_the_place_that_computes_it() {
        let own = [
            ("model_tail_torque_n_m", Place::TailTorque),
            ("model_tail_power_w", Place::TailTorque),
            ("model_thrust_n", Place::TailThrust),
            ("model_body_drag_n", Place::BodyTranslation),
        ];
        for (id, place) in own {
            let q = MODEL_QUANTITIES.iter().find(|q| q.id == id).unwrap();
            assert!(!quantity_acts_at(q, place), "{id} at {place:?}");
        }
    }

    #[test]
    fn density_acts_only_as_an_axial_load() {
        let rho = FIELDS.iter().find(|q| q.id == "density_kg_m3").unwrap();
        assert_eq!(places_of(rho), vec![Place::LoadForce]);
        let mu = FIELDS.iter().find(|q| q.id == "viscosity_pa_s").unwrap();
        assert!(Place::ALL.into_iter().all(|p| quantity_acts_at(mu, p)));
    }

    #[test]
    fn every_model_quantity_has_its_places_and_the_load_torque_acts_on_the_drive() {
        for q in MODEL_QUANTITIES {
            let at = places_of(q);
            assert!(
                !at.is_empty() && at.len() < Place::ALL.len(),
                "{}: {at:?}",
                q.id
            );
        }
        assert!(MODEL_PLACES
            .iter()
            .all(|(id, _)| MODEL_QUANTITIES.iter().any(|q| q.id == *id)));
        let tau = &MODEL_QUANTITIES[0];
        assert_eq!(tau.id, "model_tail_torque_n_m");
        assert!(
            quantity_acts_at(tau, Place::DriveRate)
                && !quantity_acts_at(tau, Place::BodyTranslation)
        );
        let re_b = MODEL_QUANTITIES
            .iter()
            .find(|q| q.id == "model_body_reynolds")
            .unwrap();
        assert!(places_of(re_b)
            .iter()
            .all(|p| p.name().starts_with("body.")));
    }
}
