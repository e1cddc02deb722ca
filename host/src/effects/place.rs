//! The places in the model where a missing effect can act, named as a fluid
//! dynamicist would, and how a correction at each place changes the model.
//!
//! A correction is a multiplier on a resistance or on the tail's rate
//! (`m > 0`, `m = 1` is no change), or an added external load on the body.
//! Each place belongs to one stage of [`crate::model::Model::predict`]:
//!
//! | place | stage | what `m` (or the load) changes |
//! |---|---|---|
//! | `tail.c_t` | local drag (eqs. 4-7) | tangential coefficient `c_t` |
//! | `tail.c_n` | local drag | normal and binormal coefficients `c_n = c_b` |
//! | `tail.viscosity` | local drag | both: an effective viscosity seen by the tail |
//! | `tail.drag` | tail matrix (eq. 3) | `B_t[x,x]`, axial drag |
//! | `tail.thrust` | tail matrix | `B_t[x,wx] = B_t[wx,x]`, the thrust coupling |
//! | `tail.torque` | tail matrix | `B_t[wx,wx]`, axial rotational drag |
//! | `body.D_x` | body matrix (eq. 10) | `D_x`, axial translation |
//! | `body.E_x` | body matrix | `E_x`, axial rotation |
//! | `load.force` | force balance (eq. 11) | adds an axial force on the robot, mN, + forward |
//! | `load.torque` | force balance | adds an axial torque on the body, µN m, + about +x |
//! | `drive.rate` | force balance | the tail's rate: `omega_true = m omega_recorded` |
//!
//! The local-drag places act only on local RFT; with a non-local tail
//! (`--tail-model sbt|stokeslets`, or an effect that replaces the tail
//! matrix) they would change nothing and are refused
//! ([`super::tail_compat`]): the tail-matrix places act there instead.

use crate::physics::coefficients::LocalDrag;
use crate::physics::solve::ForceBalance;
use nalgebra::Matrix6;

/// Where a correction acts; see the module docs for the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Place {
    TailTangential,
    TailNormal,
    TailViscosity,
    TailDrag,
    TailThrust,
    TailTorque,
    BodyTranslation,
    BodyRotation,
    LoadForce,
    LoadTorque,
    DriveRate,
}

/// The part of the robot or of its drive a place belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Part {
    Tail,
    Body,
    Load,
    Drive,
}

impl Place {
    /// What the place's physics allows a law's value (the multiplier, or
    /// the drive's rate over the recorded one) to be; `None` for a load,
    /// which has no scale of its own. The reasons are stated in
    /// `workbench/search/ranges.rs`, where a set outside them is refused.
    pub fn allowed_value(self) -> Option<(f64, f64)> {
        match self {
            Place::DriveRate => Some((0.5, 1.1)),
            Place::LoadForce | Place::LoadTorque => None,
            _ => Some((0.1, 10.0)),
        }
    }

    /// The tail's places: its resistances, its couplings and the oil it
    /// sees.
    pub const TAIL: [Place; 6] = [
        Place::TailTangential,
        Place::TailNormal,
        Place::TailViscosity,
        Place::TailDrag,
        Place::TailThrust,
        Place::TailTorque,
    ];

    pub const ALL: [Place; 11] = [
        Place::TailTangential,
        Place::TailNormal,
        Place::TailViscosity,
        Place::TailDrag,
        Place::TailThrust,
        Place::TailTorque,
        Place::BodyTranslation,
        Place::BodyRotation,
        Place::LoadForce,
        Place::LoadTorque,
        Place::DriveRate,
    ];

    /// `part.target`, as written in effect files and printed by `diagnose`.
    pub fn name(self) -> &'static str {
        match self {
            Place::TailTangential => "tail.c_t",
            Place::TailNormal => "tail.c_n",
            Place::TailViscosity => "tail.viscosity",
            Place::TailDrag => "tail.drag",
            Place::TailThrust => "tail.thrust",
            Place::TailTorque => "tail.torque",
            Place::BodyTranslation => "body.D_x",
            Place::BodyRotation => "body.E_x",
            Place::LoadForce => "load.force",
            Place::LoadTorque => "load.torque",
            Place::DriveRate => "drive.rate",
        }
    }

    pub fn part(self) -> Part {
        match self {
            Place::TailTangential
            | Place::TailNormal
            | Place::TailViscosity
            | Place::TailDrag
            | Place::TailThrust
            | Place::TailTorque => Part::Tail,
            Place::BodyTranslation | Place::BodyRotation => Part::Body,
            Place::LoadForce | Place::LoadTorque => Part::Load,
            Place::DriveRate => Part::Drive,
        }
    }

    /// The target within the part: `c_t`, `D_x`, `force`, `rate`, ...
    pub fn target(self) -> &'static str {
        let name = self.name();
        &name[name.find('.').map_or(0, |i| i + 1)..]
    }

    /// Look a place up by [`Place::name`].
    pub fn from_name(name: &str) -> Option<Place> {
        Place::ALL.into_iter().find(|p| p.name() == name)
    }

    /// The local drag coefficients of resistive-force theory, which only a
    /// local tail has (see [`super::tail_compat`]).
    pub fn is_local_drag(self) -> bool {
        matches!(
            self,
            Place::TailTangential | Place::TailNormal | Place::TailViscosity
        )
    }

    /// Loads are added (value in mN or µN m); everything else is a multiplier.
    pub fn is_additive(self) -> bool {
        matches!(self, Place::LoadForce | Place::LoadTorque)
    }

    /// The unit of the value a correction gives at this place.
    pub fn unit(self) -> &'static str {
        match self {
            Place::LoadForce => "mN",
            Place::LoadTorque => "µN m",
            _ => "1 (multiplier)",
        }
    }

    /// What the place means, in one phrase.
    pub fn meaning(self) -> &'static str {
        match self {
            Place::TailTangential => "the tail's local tangential resistance c_t",
            Place::TailNormal => "the tail's local normal resistance c_n",
            Place::TailViscosity => "the viscosity seen by the tail (c_t and c_n together)",
            Place::TailDrag => "the tail's axial drag B_t[x,x]",
            Place::TailThrust => "the tail's thrust coupling B_t[x,wx]",
            Place::TailTorque => "the tail's axial rotational drag B_t[wx,wx]",
            Place::BodyTranslation => "the body's axial translational resistance D_x",
            Place::BodyRotation => "the body's axial rotational resistance E_x",
            Place::LoadForce => "an external axial force on the robot",
            Place::LoadTorque => "an external axial torque on the body",
            Place::DriveRate => "the tail's true rate against the recorded f",
        }
    }

    /// Apply a multiplier at a local-drag place; other places are untouched.
    pub fn apply_local_drag(self, m: f64, drag: &mut LocalDrag) {
        match self {
            Place::TailTangential => drag.tangential *= m,
            Place::TailNormal => drag.normal *= m,
            Place::TailViscosity => *drag = drag.scaled(m),
            _ => {}
        }
    }

    /// Apply a multiplier at a tail-matrix place.
    pub fn apply_tail(self, m: f64, tail: &mut Matrix6<f64>) {
        match self {
            Place::TailDrag => tail[(0, 0)] *= m,
            Place::TailThrust => {
                tail[(0, 3)] *= m;
                tail[(3, 0)] *= m;
            }
            Place::TailTorque => tail[(3, 3)] *= m,
            _ => {}
        }
    }

    /// Apply a multiplier at a body place.
    pub fn apply_body(self, m: f64, body: &mut Matrix6<f64>) {
        match self {
            Place::BodyTranslation => body[(0, 0)] *= m,
            Place::BodyRotation => body[(3, 3)] *= m,
            _ => {}
        }
    }

    /// Apply a load (mN, µN m) or a rate multiplier to the force balance.
    pub fn apply_balance(self, value: f64, fb: &mut ForceBalance) {
        match self {
            Place::LoadForce => fb.load[0] += value * 1e-3,
            Place::LoadTorque => fb.load[3] += value * 1e-6,
            Place::DriveRate => fb.tail_rate_rad_s *= value,
            _ => {}
        }
    }
}

impl std::fmt::Display for Place {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tail_places_are_every_place_of_the_tail() {
        let tail: Vec<Place> = Place::ALL
            .into_iter()
            .filter(|p| p.part() == Part::Tail)
            .collect();
        assert_eq!(tail, Place::TAIL.to_vec());
    }

    #[test]
    fn names_round_trip_and_split_into_part_and_target() {
        for p in Place::ALL {
            assert_eq!(Place::from_name(p.name()), Some(p));
            let (part, target) = p.name().split_once('.').unwrap();
            assert_eq!(target, p.target());
            let part_json = serde_json::to_string(&p.part()).unwrap();
            assert_eq!(part_json, format!("\"{part}\""));
        }
        assert_eq!(Place::from_name("tail.speed"), None);
    }

    #[test]
    fn a_unit_multiplier_changes_nothing_and_a_zero_load_adds_nothing() {
        let mut tail = Matrix6::from_fn(|i, j| 1.0 + (i * 6 + j) as f64);
        let before = tail;
        let mut body = tail;
        let mut drag = LocalDrag {
            tangential: 2.0,
            normal: 3.0,
        };
        let mut fb = ForceBalance::new(body, tail, 5.0);
        let fb0 = fb.clone();
        for p in Place::ALL {
            let neutral = if p.is_additive() { 0.0 } else { 1.0 };
            p.apply_local_drag(neutral, &mut drag);
            p.apply_tail(neutral, &mut tail);
            p.apply_body(neutral, &mut body);
            p.apply_balance(neutral, &mut fb);
        }
        assert_eq!((tail, body), (before, before));
        assert_eq!((drag.tangential, drag.normal), (2.0, 3.0));
        assert_eq!(fb, fb0);
    }

    #[test]
    fn the_thrust_coupling_stays_symmetric() {
        let mut tail = Matrix6::from_fn(|i, j| ((i + 1) * (j + 1)) as f64);
        Place::TailThrust.apply_tail(0.5, &mut tail);
        assert_eq!(tail, tail.transpose());
        assert_eq!(tail[(0, 3)], 2.0);
    }
}
