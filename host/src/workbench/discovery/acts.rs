//! Where a feature's physics can act: the feature x place table of the
//! search. A law is offered only at a place where its feature could
//! change the physics, so that an unphysical placement cannot win by
//! chance among hundreds of laws.
//!
//! | feature | places | why |
//! |---|---|---|
//! | `density_kg_m3` (the oil's density) | `load.force` | at the robot's Reynolds numbers (far below 1 in the viscous oils it swims in) inertia is absent from the resistances of resistive-force theory; density acts only through buoyancy, an axial force |
//! | every other feature | every place | geometry, kinematics, viscosity and the Reynolds numbers can each set a resistance, a coupling, a load or the drive |
//!
//! References: J. Lighthill, *Mathematical Biofluiddynamics* (1975), ch. 3
//! (resistive-force theory at zero Reynolds number); E. M. Purcell, Am. J.
//! Phys. 45 (1977) 3 (life at low Reynolds number).

use crate::data::quantities::Quantity;
use crate::effects::place::Place;

/// Whether a law in `feature` may sit at `place` (module docs).
pub fn acts_at(feature: &Quantity, place: Place) -> bool {
    match feature.id {
        "density_kg_m3" => place == Place::LoadForce,
        _ => true,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::quantities::FIELDS;

    #[test]
    fn density_acts_only_as_an_axial_load() {
        let rho = FIELDS.iter().find(|q| q.id == "density_kg_m3").unwrap();
        let at: Vec<Place> = Place::ALL
            .into_iter()
            .filter(|&p| acts_at(rho, p))
            .collect();
        assert_eq!(at, vec![Place::LoadForce]);
        let mu = FIELDS.iter().find(|q| q.id == "viscosity_pa_s").unwrap();
        assert!(Place::ALL.into_iter().all(|p| acts_at(mu, p)));
    }
}
