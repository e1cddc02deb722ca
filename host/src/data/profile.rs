//! The optional `body_profile` of a case (`[[length_mm, diameter_mm], ...]`,
//! nose first) and `body_rounded_mm`, checked against the case: every
//! section positive and finite and inside the channel, the total length and
//! the largest diameter within [`PROFILE_TOLERANCE`] of `body_length_mm`
//! and `body_diameter_mm`, a rim fillet that fits. Errors name the field,
//! `body_profile[i]` for a section (nose = 0).
//!
//! References: docs/data-format.md; the profile type,
//! `crate::physics::profile`.

use super::{Case, DataError};
use crate::physics::profile::{BodyProfile, Section};

/// Relative tolerance between the profile's total length and largest
/// diameter and `body_length_mm` / `body_diameter_mm`, which the rest of
/// the model (RFT body, buoyancy, back-flow) keeps using.
pub const PROFILE_TOLERANCE: f64 = 0.01;

pub(super) fn resolve(
    fail: impl Fn(&str, String) -> DataError,
    case: &Case,
    sections: Option<&Vec<[f64; 2]>>,
    rounded_mm: Option<f64>,
) -> Result<Option<BodyProfile>, DataError> {
    let Some(sections) = sections else {
        if rounded_mm.is_some() {
            return Err(fail(
                "body_rounded_mm",
                "given without `body_profile`".into(),
            ));
        }
        return Ok(None);
    };
    if sections.is_empty() {
        return Err(fail(
            "body_profile",
            "needs at least one [length_mm, diameter_mm] section".into(),
        ));
    }
    for (i, [l, d]) in sections.iter().enumerate() {
        let field = format!("body_profile[{i}]");
        for (what, v) in [("length_mm", l), ("diameter_mm", d)] {
            if !v.is_finite() || *v <= 0.0 {
                return Err(fail(
                    &field,
                    format!(
                        "section {i} (nose = 0): {what} must be a positive finite number, got {v}"
                    ),
                ));
            }
        }
        if *d >= case.channel_diameter_mm {
            return Err(fail(
                &field,
                format!(
                    "section {i} (nose = 0): diameter {d} mm does not fit in the {} mm channel",
                    case.channel_diameter_mm
                ),
            ));
        }
    }
    let profile = BodyProfile::Sections {
        sections: sections
            .iter()
            .map(|&[length_mm, diameter_mm]| Section {
                length_mm,
                diameter_mm,
            })
            .collect(),
        rounded_mm: rounded_mm.unwrap_or(0.0),
    };
    profile
        .validate()
        .map_err(|e| fail("body_rounded_mm", e.to_string()))?;
    let (len, dia) = (profile.length_mm(), profile.max_diameter_mm());
    if (len / case.body_length_mm - 1.0).abs() > PROFILE_TOLERANCE {
        return Err(fail(
            "body_profile",
            format!(
                "the sections add up to {len} mm, but body_length_mm is {} mm (allowed: within {} %)",
                case.body_length_mm,
                100.0 * PROFILE_TOLERANCE
            ),
        ));
    }
    if (dia / case.body_diameter_mm - 1.0).abs() > PROFILE_TOLERANCE {
        return Err(fail(
            "body_profile",
            format!(
                "the largest section diameter is {dia} mm, but body_diameter_mm is {} mm (allowed: within {} %)",
                case.body_diameter_mm,
                100.0 * PROFILE_TOLERANCE
            ),
        ));
    }
    Ok(Some(profile))
}
