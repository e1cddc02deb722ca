//! The physics-sentence table: what a located correction means, in one
//! sentence a fluid dynamicist would write, from its place, the family of
//! its feature and whether it rises or falls across the data.
//!
//! The families follow the quantity library ([`crate::data::quantities`]):
//! wall proximity of the tail (the gap features), confinement of the body,
//! the rate (shear rate, f, wave speed), and the helix geometry. Where the
//! table has no entry the sentence is composed from the place's meaning.
//!
//! References: J. Happel & H. Brenner, *Low Reynolds number hydrodynamics*
//! (1983), ch. 7 (walls raise resistance); R. B. Bird, R. C. Armstrong &
//! O. Hassager, *Dynamics of Polymeric Liquids* vol. 1 (1987), ch. 4
//! (shear-thinning); J. Lighthill, SIAM Rev. 18 (1976) 161 (RFT's
//! geometry dependence).

use crate::data::Feature;
use crate::effects::place::{Part, Place};
use serde::Serialize;

/// The family a feature belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Family {
    TailWall,
    BodyWall,
    Rate,
    Geometry,
    /// A recorded setup field or one of its groups (the oil, the channel's
    /// length, the body and coupler).
    Setup,
    /// One of the model's own quantities (load torque, thrust, U, ...:
    /// [`crate::data::model_quantities`]).
    Model,
    /// A column the lab recorded ([`crate::data::recorded`]).
    Recorded,
}

pub fn family(f: &Feature) -> Family {
    let Some(q) = f.quantity() else {
        return Family::Recorded;
    };
    match q.id {
        "helix_over_gap" | "tail_clearance" | "tail_gap_ratio" | "wire_over_gap"
        | "tail_length_ratio" | "wavelength_ratio" => Family::TailWall,
        "body_ratio" | "body_gap_ratio" | "body_over_gap" => Family::BodyWall,
        "frequency" | "shear_rate" | "wave_speed" => Family::Rate,
        _ if crate::data::model_quantities::is_model_quantity(q) => Family::Model,
        id if crate::data::quantities::SETUP_GROUPS
            .iter()
            .chain(crate::data::quantities::FIELDS)
            .any(|f| f.id == id) =>
        {
            Family::Setup
        }
        _ => Family::Geometry,
    }
}

/// Whether a quantity grows as the tail nears the wall (`tail_gap_ratio`
/// shrinks then): the sentence speaks of the wall, not of the feature.
fn grows_towards_wall(f: &Feature) -> bool {
    !matches!(&*f.id(), "tail_gap_ratio" | "body_gap_ratio")
}

/// What the design says about a law: whether the channel varies (a wall
/// reading needs it), and the law's range across the cases.
#[derive(Debug, Clone, Copy)]
pub struct Design {
    pub channel_varies: bool,
    /// Smallest and largest value of the multiplier (or load) over the cases.
    pub range: (f64, f64),
}

/// One sentence for a correction at `place` with `feature` on `design`,
/// with its range and the readings the axial model cannot tell apart.
pub fn interpret_on(
    place: Place,
    feature: Option<&Feature>,
    rising: bool,
    mean_value: f64,
    design: Design,
) -> String {
    let mut s = match feature {
        Some(q)
            if !design.channel_varies
                && matches!(family(q), Family::TailWall | Family::BodyWall) =>
        {
            format!(
                "{} {} with {}; the channel is the same in every case, so this design cannot tell a wall effect from a dependence on the helix or body geometry in it (a second tube would)",
                place.meaning(),
                if rising { "rising" } else { "falling" },
                q.name()
            )
        }
        _ => interpret(place, feature, rising, mean_value),
    };
    if feature.is_some() {
        let (lo, hi) = design.range;
        s.push_str(&format!(
            " (from {} to {} across the cases",
            crate::format::fmt_sig(lo, 3),
            crate::format::fmt_sig(hi, 3)
        ));
        s.push(')');
    }
    if let Some((lo, hi)) = place.allowed_value() {
        let (min, max) = design.range;
        if min < lo || max > hi {
            s.push_str(&format!(
                "; outside what this place allows ({lo} to {hi}), so a fit, not an explanation"
            ));
        }
    }
    for e in equivalents(place) {
        s.push_str("; equivalently, ");
        s.push_str(e.reading);
    }
    s
}

/// A reading of a law that the axial model cannot tell from it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Equivalent {
    /// The other place.
    pub place: &'static str,
    /// How the law maps there: `reciprocal` (the same feature, the
    /// multiplier inverted), `opposite` (the same feature, changing the
    /// other way) or `alike` (the same feature, changing the same way);
    /// the last two are not exact maps, each is fitted at its own optimum.
    pub relation: &'static str,
    /// The reading in words.
    #[serde(skip)]
    pub reading: &'static str,
}

/// The places the axial model cannot tell from `place`.
///
/// - The body's rotation balances the tail's torque: scaling one by a law
///   is scaling the other by its reciprocal (exact).
/// - The speed-only places. In the paper's drive eq. 11 splits into
///   `U = (F - B_t[x,wx] omega) / (D_x + B_t[x,x])` and
///   `Omega_b = (T - B_t[wx,wx] omega) / E_x`: the body's axial drag, the
///   tail's axial drag and its thrust coupling set the speed alone, through
///   one ratio, and the body's rotation does not depend on them at all
///   (with a motor rate relative to the body it does, weakly: 0.06-0.6 %
///   for a 70 % change of the tail's drag on the paper's cases). The speeds
///   fix the ratio, not how a law splits between them: a law on `D_x` is a
///   law on `B_t[x,x]` rising the same way (scaled by `D_x / B_t[x,x]`, which
///   varies with the geometry), a law on either is a thrust law falling
///   instead. On ten drawn designs with a tail drag rising near the wall,
///   the best drag law and the best thrust law (each at its own optimum)
///   both reached the noise floor on all ten, their speeds differed by at
///   most 1.3-4.1 standard errors in the most different case, and the
///   AICc preferred either by up to 42 (docs/discovery.md): a preference
///   set by which form the search can write, not by the place.
pub fn equivalents(place: Place) -> &'static [Equivalent] {
    const TO_BODY_E_X: Equivalent = Equivalent {
        place: "body.E_x",
        relation: "reciprocal",
        reading: "body.E_x scaled by the reciprocal law",
    };
    const TO_TAIL_TORQUE: Equivalent = Equivalent {
        place: "tail.torque",
        relation: "reciprocal",
        reading: "tail.torque scaled by the reciprocal law",
    };
    // The two readings of eq. 11's speed, said once.
    macro_rules! ratio {
        () => {
            "in the paper's drive the speed is the thrust over the axial drag of body and tail, and the body's rotation depends on none of them"
        };
    }
    macro_rules! sum {
        () => {
            "in the paper's drive the speed sets only the sum of the body's and the tail's axial drag, D_x + B_t[x,x], not how it splits between them"
        };
    }
    const DRAG_TO_THRUST: Equivalent = Equivalent {
        place: "tail.thrust",
        relation: "opposite",
        reading: concat!(
            "tail.thrust changing the other way with the same feature (",
            ratio!(),
            "; the data of docs/discovery.md's study could not tell them apart)"
        ),
    };
    const THRUST_TO_DRAG: Equivalent = Equivalent {
        place: "tail.drag",
        relation: "opposite",
        reading: concat!(
            "tail.drag changing the other way with the same feature (",
            ratio!(),
            "; the data of docs/discovery.md's study could not tell them apart)"
        ),
    };
    const BODY_TO_THRUST: Equivalent = Equivalent {
        place: "tail.thrust",
        relation: "opposite",
        reading: concat!(
            "tail.thrust changing the other way with the same feature (",
            ratio!(),
            ")"
        ),
    };
    const THRUST_TO_BODY: Equivalent = Equivalent {
        place: "body.D_x",
        relation: "opposite",
        reading: concat!(
            "body.D_x changing the other way with the same feature (",
            ratio!(),
            ")"
        ),
    };
    const BODY_TO_DRAG: Equivalent = Equivalent {
        place: "tail.drag",
        relation: "alike",
        reading: concat!(
            "tail.drag changing the same way with the same feature (",
            sum!(),
            ")"
        ),
    };
    const DRAG_TO_BODY: Equivalent = Equivalent {
        place: "body.D_x",
        relation: "alike",
        reading: concat!(
            "body.D_x changing the same way with the same feature (",
            sum!(),
            ")"
        ),
    };
    match place {
        Place::TailTorque => &[TO_BODY_E_X],
        Place::BodyRotation => &[TO_TAIL_TORQUE],
        Place::TailDrag => &[DRAG_TO_THRUST, DRAG_TO_BODY],
        Place::TailThrust => &[THRUST_TO_DRAG, THRUST_TO_BODY],
        Place::BodyTranslation => &[BODY_TO_DRAG, BODY_TO_THRUST],
        _ => &[],
    }
}

/// One sentence for a correction at `place` with `feature`; `rising` is
/// whether the multiplier (or load) grows with the feature across the data,
/// `mean_value` its mean (multiplier, or load in mN / µN m).
pub fn interpret(place: Place, feature: Option<&Feature>, rising: bool, mean_value: f64) -> String {
    let what = place.meaning();
    let Some(q) = feature else {
        return match place {
            Place::DriveRate if mean_value < 1.0 => format!(
                "tail turning slower than recorded (by {:.0} %): the recorded f overstates the tail's rate",
                100.0 * (1.0 - mean_value)
            ),
            Place::DriveRate => "tail turning faster than recorded: the recorded f understates the tail's rate".into(),
            Place::LoadForce => format!(
                "a constant axial force of {mean_value:.3} mN on the robot: a buoyancy trim error or a tether"
            ),
            Place::LoadTorque => format!(
                "a constant axial torque of {mean_value:.3} µN m on the body: friction in the joint or at the wall"
            ),
            _ => format!(
                "{what} {} by a constant factor {mean_value:.3}: a coefficient or viscosity error",
                if mean_value > 1.0 { "too small" } else { "too large" }
            ),
        };
    };
    let towards_wall = rising == grows_towards_wall(q);
    let updown = |up: bool| if up { "rising" } else { "falling" };
    match (place.part(), family(q)) {
        (Part::Tail, Family::TailWall) => format!(
            "{what} {} as the helix nears the wall: wall proximity (scaling with {})",
            updown(towards_wall),
            q.name()
        ),
        (Part::Tail, Family::Rate) => {
            if rising {
                format!("{what} rising with shear rate ({}): a shear-thickening oil", q.name())
            } else {
                format!("{what} falling with shear rate ({}): a shear-thinning oil", q.name())
            }
        }
        (Part::Body, Family::BodyWall) => format!(
            "{what} {} with confinement ({}): the narrow annular gap around the body",
            updown(towards_wall),
            q.name()
        ),
        (Part::Drive, Family::Model) => format!(
            "the tail's true rate {} as the model's {} grows: a motor {} under load (a torque-speed line)",
            if rising { "gaining" } else { "lagging" },
            q.name(),
            if rising { "speeding up" } else { "slowing" }
        ),
        (_, Family::Model) => format!(
            "{what} {} with the model's own {}: a resistance or load set by the motion or the loads the model computes, not by a dataset field alone",
            updown(rising),
            q.name()
        ),
        (Part::Drive, Family::Rate) => format!(
            "the tail's true rate {} with the recorded rate ({}): the drive slips more at {} speed",
            if rising { "gaining" } else { "lagging" },
            q.name(),
            if rising { "low" } else { "high" }
        ),
        (Part::Drive, _) => format!(
            "tail turning {} than recorded, depending on {}: a load-dependent drive slip",
            if mean_value < 1.0 { "slower" } else { "faster" },
            q.name()
        ),
        (Part::Tail, Family::Geometry) => format!(
            "{what} {} with {}: the RFT coefficients' dependence on the helix geometry is off (non-local hydrodynamics)",
            updown(rising),
            q.name()
        ),
        (Part::Load, Family::Recorded) => format!(
            "{what} {} with {}: a load that follows what the lab recorded beside each run (a viscosity common to body and tail that follows it acts only against the robot's net weight, as such a load)",
            updown(rising),
            q.name()
        ),
        (_, Family::Recorded) => format!(
            "{what} {} with {}: a dependence on what the lab recorded beside each run, which the model does not read",
            updown(rising),
            q.name()
        ),
        (_, Family::Setup) => format!(
            "{what} {} with {}: a dependence on the recorded setup (the oil or the robot's build) that the model does not carry",
            updown(rising),
            q.name()
        ),
        (Part::Load, _) => format!(
            "{what} {} with {}: a load outside the model's hydrodynamics",
            updown(rising),
            q.name()
        ),
        _ => format!("{what} {} with {}", updown(rising), q.name()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::data::Feature;

    fn by_id(id: &str) -> Option<Feature> {
        crate::data::quantities::by_id(id).map(Feature::Quantity)
    }

    #[test]
    fn wall_shear_and_rate_laws_read_as_physical_effects() {
        let w = by_id("wire_over_gap").unwrap();
        assert!(interpret(Place::TailNormal, Some(&w), true, 1.2)
            .contains("nears the wall: wall proximity"));
        let g = by_id("tail_gap_ratio").unwrap();
        assert!(interpret(Place::TailNormal, Some(&g), false, 1.2)
            .contains("rising as the helix nears the wall"));
        let s = by_id("shear_rate").unwrap();
        assert!(interpret(Place::TailViscosity, Some(&s), false, 0.8).contains("shear-thinning"));
        assert!(interpret(Place::DriveRate, None, false, 0.85).contains("slower than recorded"));
    }

    #[test]
    fn the_design_decides_the_reading() {
        let fixed = Design {
            channel_varies: false,
            range: (0.9, 1.2),
        };
        let l = by_id("wavelength_ratio").unwrap();
        let s = interpret_on(Place::TailNormal, Some(&l), false, 1.0, fixed);
        assert!(
            s.contains("the same in every case") && !s.contains("nears the wall"),
            "{s}"
        );
        assert!(s.contains("from 0.900 to 1.20"), "{s}");
        let varied = Design {
            channel_varies: true,
            ..fixed
        };
        let s = interpret_on(Place::TailNormal, Some(&l), false, 1.0, varied);
        assert!(s.contains("wall"), "{s}");
        let mu = by_id("viscosity_pa_s").unwrap();
        let s = interpret_on(Place::TailViscosity, Some(&mu), false, 1.0, varied);
        assert!(
            s.contains("recorded setup") && !s.contains("non-local"),
            "{s}"
        );
        let t = interpret_on(Place::TailTorque, None, false, 1.2, varied);
        assert!(t.contains("body.E_x scaled by the reciprocal"), "{t}");
        let g = by_id("tail_clearance").unwrap();
        let d = interpret_on(Place::TailDrag, Some(&g), true, 1.1, varied);
        assert!(d.contains("tail.thrust changing the other way"), "{d}");
        let temp = Feature::recorded("temperature_c").unwrap();
        let r = interpret_on(Place::LoadForce, Some(&temp), true, 0.1, varied);
        assert!(
            r.contains("temperature_c (recorded)") && r.contains("net weight"),
            "{r}"
        );
    }

    /// An equivalence read one way is stated the other way too, with the
    /// same relation; places without one state none.
    #[test]
    fn equivalent_readings_are_mutual() {
        for place in Place::ALL {
            for e in equivalents(place) {
                let other = Place::from_name(e.place).unwrap();
                let back = equivalents(other);
                assert!(
                    back.iter()
                        .any(|b| b.place == place.name() && b.relation == e.relation),
                    "{} -> {}",
                    place.name(),
                    e.place
                );
            }
        }
        assert_eq!(equivalents(Place::TailDrag)[0].place, "tail.thrust");
        assert!(equivalents(Place::TailNormal).is_empty());
    }
}
