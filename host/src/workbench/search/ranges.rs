//! What each place's physics allows a law's value to be, case by case: a
//! set whose fitted law puts a place outside it explains nothing, however
//! well it fits, and is not offered as an explanation.
//!
//! A law's value is read at every case of the data (the multiplier after
//! its floor, [`LocatedCorrection::value`]); the whole set is out when one
//! value of one member is out.
//!
//! | place | allowed | why |
//! |---|---|---|
//! | `drive.rate` | 0.5 .. 1.1 of the recorded rate | the tail's rate is recorded (counted on video in the paper, to about 2 %); a slip loses rate under load and cannot gain it, so more than the recorded rate is allowed only within a calibration error of 10 %; a tail turning at less than half the recorded rate would have been seen |
//! | `tail.c_t`, `tail.c_n`, `tail.viscosity`, `tail.drag`, `tail.thrust`, `tail.torque`, `body.D_x`, `body.E_x` | 0.1 .. 10 times the model's | resistive-force theory's coefficients agree with slender-body theory to some tens of per cent for slender filaments, and a wall raises a resistance by a few times at the gap ratios of the robot's tubes; an oil the tail sees at a tenth of its measured viscosity, or a resistance ten times the model's, is a wrong unit or a wrong model, not a missing correction |
//! | `load.force`, `load.torque` | the law's own bounds (+-100 times the load scale) | a load has no physical scale of its own here: a buoyancy, a tether or a bearing can each be of any size the data call for |
//!
//! Catalogue effects carry their own parameter bounds (their effect files)
//! and are not read here. The ranges are physics, stated once, and hold
//! for every dataset: none was set on a drawn truth.
//!
//! References: J. Lighthill, *Mathematical Biofluiddynamics* (1975), ch. 3
//! (resistive-force theory); R. E. Johnson & C. J. Brokaw, Biophys. J. 25
//! (1979) 113 (RFT against slender-body theory); C. Brennen & H. Winet,
//! Annu. Rev. Fluid Mech. 9 (1977) 339 (wall effects on slender bodies).

use crate::data::Dataset;
use crate::effects::correction::LocatedCorrection;
use crate::effects::place::Place;

/// The allowed interval of a place's value (module docs); `None`: no range
/// beyond the law's own bounds.
pub fn allowed(place: Place) -> Option<(f64, f64)> {
    place.allowed_value()
}

/// The first case whose value of the law lies outside its place's range:
/// `(case id, value, (lo, hi))`; `None` when every case is inside.
pub fn outside(
    c: &LocatedCorrection,
    values: &[f64],
    data: &Dataset,
) -> Option<(String, f64, (f64, f64))> {
    let (lo, hi) = allowed(c.place)?;
    data.cases.iter().find_map(|case| {
        let v = c.value(values, case);
        (!(lo..=hi).contains(&v)).then(|| (case.id.clone(), v, (lo, hi)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::effects::correction::Form;

    fn constant(place: Place) -> LocatedCorrection {
        LocatedCorrection::new(place, None, Form::Constant, 1.0, 1.0)
            .expect("a constant fits every place")
    }

    #[test]
    fn a_drive_at_a_tenth_of_its_recorded_rate_is_out_and_a_slip_is_in() {
        let data = crate::data::paper();
        let drive = constant(Place::DriveRate);
        let (case, v, range) = outside(&drive, &[0.12], &data).expect("out");
        assert_eq!(case, data.cases[0].id);
        assert!((v - 0.12).abs() < 1e-12 && range == (0.5, 1.1));
        assert!(outside(&drive, &[0.85], &data).is_none());
        assert!(
            outside(&drive, &[1.3], &data).is_some(),
            "a slip gains no rate"
        );
    }

    #[test]
    fn an_oil_at_a_few_percent_of_its_viscosity_is_out_and_loads_are_free() {
        let data = crate::data::paper();
        let oil = constant(Place::TailViscosity);
        assert!(outside(&oil, &[0.03], &data).is_some());
        assert!(outside(&oil, &[0.6], &data).is_none());
        assert!(outside(&oil, &[12.0], &data).is_some());
        let force = LocatedCorrection::new(Place::LoadForce, None, Form::Constant, 1.0, 1.0)
            .expect("a constant load");
        assert!(outside(&force, &[-90.0], &data).is_none());
    }
}
