//! The feature library the search draws on: a recorded setup field is a
//! feature when it varies and does not repeat one already in the library
//! (src/workbench/discovery/search.rs, src/workbench/features.rs).

use crate::fixtures::truths;

/// A recorded setup field is a feature when it varies: the oil's
/// viscosity on a design with three oils; a field that does not vary (the
/// channel) is left out, and so is a field that orders the cases exactly
/// as a feature already in the library.
#[test]
fn varying_setup_fields_are_features_and_constant_ones_are_not() {
    let oils = truths::oil_design(&swimbot::data::paper());
    let ids: Vec<String> = swimbot::workbench::discovery::search::usable_features(&oils)
        .iter()
        .map(|u| u.feature.id().into_owned())
        .collect();
    let ids: Vec<&str> = ids.iter().map(String::as_str).collect();
    assert!(ids.contains(&"viscosity_pa_s"), "{ids:?}");
    assert!(ids.contains(&"reynolds"), "{ids:?}");
    assert!(!ids.contains(&"channel_diameter_mm"), "{ids:?}");
    assert!(!ids.contains(&"channel_length_ratio"), "{ids:?}");
    // `frequency` is in the derived library: its field twin is left out.
    assert!(
        ids.contains(&"frequency") && !ids.contains(&"frequency_hz"),
        "{ids:?}"
    );
}
