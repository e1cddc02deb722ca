//! The body's shape as uncertain inputs: the lengths of the profile's end
//! sections (`body_nose_length_mm`, `body_rear_length_mm`: on the paper's
//! robot the cork and the sealing element), and how the body's overall
//! length and diameter move the profile when they are varied.
//!
//! The paper gives the parts' diameters (cork 20 mm, casing 18 mm, seal
//! 20 mm) and the 50 mm total only, so the section lengths are unknown
//! while the total is known: varying an end section moves the joint to its
//! inner neighbour, which takes up the difference, and the total stays
//! `body_length_mm`. Varying `body_length_mm` or `body_diameter_mm` scales
//! every section's length or diameter by the same factor, so that the
//! axisymmetric solver (`body-confinement-exact`) sees the body the RFT
//! spheroid sees; before, a perturbed body length or diameter left the
//! profile, and so the physics preset's body drag, unchanged.
//!
//! Both end-section inputs need a profile of at least three sections (an
//! end section and an inner neighbour that is not the other end); the
//! parser says so otherwise (`check`).
//!
//! References: the paper, section II (the robot's parts) and Table I;
//! docs/physics.md, section 3 (what the section lengths do to the drag).

use super::Case;
use crate::physics::profile::BodyProfile;

/// The nose section's length (the cork on the paper's robot).
pub const NOSE: &str = "body_nose_length_mm";
/// The rear section's length (the sealing element on the paper's robot).
pub const REAR: &str = "body_rear_length_mm";

/// The sections of a profile given as sections, with at least three.
fn sections_of(case: &Case) -> Option<&Vec<crate::physics::profile::Section>> {
    match &case.body_profile {
        Some(BodyProfile::Sections { sections, .. }) if sections.len() >= 3 => Some(sections),
        _ => None,
    }
}

/// The value of an end-section input, `None` for another name; NaN when
/// the case has no profile of three sections (the parser refuses an
/// uncertainty on it then, so no band reads it).
pub fn value(case: &Case, field: &str) -> Option<f64> {
    let end = |s: &Vec<crate::physics::profile::Section>| match field {
        NOSE => s[0].length_mm,
        _ => s[s.len() - 1].length_mm,
    };
    matches!(field, NOSE | REAR).then(|| sections_of(case).map_or(f64::NAN, end))
}

/// Set one of the inputs this module handles; `false` for any other name.
/// A value that leaves the inner section without length is set as asked:
/// the profile's own check refuses it where it is solved.
pub fn set(case: &mut Case, field: &str, v: f64) -> bool {
    match field {
        "body_length_mm" => {
            scale(case, |s, k| s.length_mm *= k, v / case.body_length_mm);
            case.body_length_mm = v;
        }
        "body_diameter_mm" => {
            scale(case, |s, k| s.diameter_mm *= k, v / case.body_diameter_mm);
            case.body_diameter_mm = v;
        }
        NOSE | REAR => {
            if let Some(BodyProfile::Sections { sections, .. }) = &mut case.body_profile {
                let n = sections.len();
                if n >= 3 {
                    let (end, inner) = if field == NOSE {
                        (0, 1)
                    } else {
                        (n - 1, n - 2)
                    };
                    sections[inner].length_mm -= v - sections[end].length_mm;
                    sections[end].length_mm = v;
                }
            }
        }
        _ => return false,
    }
    true
}

fn scale(case: &mut Case, f: fn(&mut crate::physics::profile::Section, f64), k: f64) {
    if let Some(BodyProfile::Sections { sections, .. }) = &mut case.body_profile {
        sections.iter_mut().for_each(|s| f(s, k));
    }
}

/// The parser's check: an end-section uncertainty needs a profile of at
/// least three sections. The error is the message for `uncertainty.KEY`.
pub fn check(case: &Case, field: &str) -> Result<(), EndSectionWithoutProfile> {
    if matches!(field, NOSE | REAR) && sections_of(case).is_none() {
        return Err(EndSectionWithoutProfile {
            field: field.to_string(),
        });
    }
    Ok(())
}

/// An end section's uncertainty (`field`) on a body without the profile
/// of three sections it moves.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "`{field}` needs a `body_profile` of at least three sections (nose, inner, rear): \
     the inner neighbour takes up the change so that the body keeps its length"
)]
pub struct EndSectionWithoutProfile {
    pub field: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn end_sections_move_the_joint_and_keep_the_total() {
        let mut c = crate::data::paper().cases[0].clone();
        assert_eq!(value(&c, NOSE), Some(10.0));
        assert!(set(&mut c, NOSE, 14.0) && set(&mut c, REAR, 7.0));
        let p = c.body_profile.clone().unwrap();
        assert!((p.length_mm() - 50.0).abs() < 1e-12);
        assert_eq!(value(&c, NOSE), Some(14.0));
        assert_eq!(value(&c, REAR), Some(7.0));
        let BodyProfile::Sections { sections, .. } = p else {
            panic!("sections")
        };
        assert!((sections[1].length_mm - 29.0).abs() < 1e-12);
        // length and diameter scale the profile with them
        assert!(set(&mut c, "body_length_mm", 55.0) && set(&mut c, "body_diameter_mm", 21.0));
        let p = c.body_profile.clone().unwrap();
        assert!((p.length_mm() - 55.0).abs() < 1e-12);
        assert!((p.max_diameter_mm() - 21.0).abs() < 1e-12);
        assert!(!set(&mut c, "amplitude_mm", 1.0));
        c.body_profile = None;
        assert!(value(&c, NOSE).unwrap().is_nan());
        assert!(check(&c, REAR)
            .unwrap_err()
            .to_string()
            .contains("three sections"));
    }
}
