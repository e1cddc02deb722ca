//! The profile-likelihood interval a study stores beside the covariance's:
//! reported where it is asymmetric (as `diagnose` reports it), an open end
//! said as open, a record without one (an earlier swimbot's) read and
//! reported as before. The binary's study on a case with an asymmetric
//! profile: `host/tests/study_profile.rs`.

use super::file::{ParamRecord, ProfileRecord};
use crate::report::steps_table::param;

/// A fitted parameter `2.00 ± 0.50` (95 % 1.02 .. 2.98), with `profile`.
fn fitted(profile: Option<ProfileRecord>) -> ParamRecord {
    ParamRecord {
        effect: "law".into(),
        name: "p".into(),
        unit: "1".into(),
        value: 2.0,
        status: "fitted".into(),
        lo: Some(2.0 - 1.96 * 0.5),
        hi: Some(2.0 + 1.96 * 0.5),
        standard_uncertainty: Some(0.5),
        at_bound: false,
        reason: None,
        profile,
    }
}

#[test]
fn an_asymmetric_profile_is_the_interval_reported() {
    let p = fitted(Some(ProfileRecord {
        low: Some(1.6),
        high: Some(3.9),
        asymmetric: true,
    }));
    let r = p.report();
    assert_eq!(r.interval, "profile");
    assert_eq!((r.ci95_low, r.ci95_high), (Some(1.6), Some(3.9)));
    // The standard uncertainty stays the covariance's.
    assert_eq!(r.standard_uncertainty, Some(0.5));
    assert_eq!(
        param(&r),
        "p = 2.00 ± 0.50 (25\u{a0}%, 95\u{a0}% profile 1.60\u{a0}..\u{a0}3.90)"
    );
}

#[test]
fn an_open_end_prints_as_open_never_as_a_number() {
    let p = fitted(Some(ProfileRecord {
        low: Some(1.6),
        high: None,
        asymmetric: true,
    }));
    let said = param(&p.report());
    assert!(
        said.contains("95\u{a0}% profile 1.60\u{a0}..\u{a0}open"),
        "{said}"
    );
    for bad in ["NaN", "inf", "None"] {
        assert!(!said.contains(bad), "{said}");
    }
}

#[test]
fn a_symmetric_profile_keeps_the_covariance_interval() {
    let p = fitted(Some(ProfileRecord {
        low: Some(1.03),
        high: Some(2.97),
        asymmetric: false,
    }));
    let r = p.report();
    assert_eq!(r.interval, "covariance");
    assert_eq!((r.ci95_low, r.ci95_high), (p.lo, p.hi));
    assert_eq!(r, fitted(None).report());
}

#[test]
fn a_record_without_a_profile_reads_and_reports_as_before() {
    // A parameter as a swimbot before the profile wrote it.
    let old = "effect = \"law\"\nname = \"p\"\nunit = \"1\"\nvalue = 2.0\n\
               status = \"fitted\"\nlo = 1.02\nhi = 2.98\nstandard_uncertainty = 0.5\n";
    let p: ParamRecord = toml::from_str(old).unwrap();
    assert_eq!(p.profile, None);
    let said = param(&p.report());
    assert_eq!(
        said,
        "p = 2.00 ± 0.50 (25\u{a0}%, 95\u{a0}% 1.02\u{a0}..\u{a0}2.98)"
    );
    // And it is written back without the field.
    assert!(!toml::to_string(&p).unwrap().contains("profile"));
}

#[test]
fn a_profile_with_an_open_end_round_trips_through_the_file() {
    let p = fitted(Some(ProfileRecord {
        low: None,
        high: Some(3.9),
        asymmetric: true,
    }));
    let text = toml::to_string(&p).unwrap();
    assert!(
        !text.contains("low"),
        "an open end is a missing key: {text}"
    );
    let back: ParamRecord = toml::from_str(&text).unwrap();
    assert_eq!(back, p);
    let unknown = format!("{text}extra = 1\n");
    assert!(toml::from_str::<ParamRecord>(&unknown).is_err());
}
