//! One missing effect that is not in the catalogue (host/tests/fixtures/
//! truths.rs: each acts at a different place and scales with a different
//! feature, in a law that is not one of the search's forms), located at
//! its place with its feature and read from the design
//! (src/workbench/discovery/{places,interpret}.rs). Synthetic data on the
//! rich design, 2 % noise, five trials; the accepted equivalent features
//! are listed in host/tests/fixtures/diagnosed.rs.

use crate::fixtures;

use fixtures::diagnosed::{
    assert_located, assert_no_repeats, base_with, drawn_data, run, WALL_FEATURES,
};
use fixtures::{drawn, truths};
use swimbot::effects::parse_effect_spec;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, VerdictKind};

#[test]
fn locates_wall_proximity_on_the_tail_normal_resistance() {
    let (d, data) = run(base_with(&truths::WALL));
    assert_eq!(d.verdict.kind, VerdictKind::Located, "{}", d.verdict.note);
    assert_located(
        &d,
        &data,
        "tail.c_n",
        &[
            "wire_over_gap",
            "helix_over_gap",
            "tail_clearance",
            "tail_gap_ratio",
        ],
    );
    assert!(d.verdict.located[0].interpretation.contains("wall"));
}

#[test]
fn locates_a_shear_thinning_oil_on_the_tail_viscosity() {
    let (d, data) = run(base_with(&truths::SHEAR));
    assert_eq!(d.verdict.kind, VerdictKind::Located, "{}", d.verdict.note);
    assert_located(&d, &data, "tail.viscosity", &["shear_rate"]);
    assert!(d.verdict.located[0]
        .interpretation
        .contains("shear-thinning"));
}

#[test]
fn locates_a_drive_turning_slower_than_recorded() {
    let (d, data) = run(base_with(&truths::SLIP));
    assert_eq!(d.verdict.kind, VerdictKind::Located, "{}", d.verdict.note);
    assert_located(&d, &data, "drive.rate", &[]);
    let k = &d.verdict.located[0].params[0];
    let ci = k.ci95.expect("identifiable");
    assert!(
        (k.value - 0.85).abs() < 3.0 * ci.max(1e-3),
        "{} ± {ci}",
        k.value
    );
}

#[test]
fn locates_a_quartic_body_confinement_on_the_body_drag() {
    let (d, data) = run(base_with(&truths::BODY));
    // backflow + body-correction is a two-parameter confinement law on the
    // body too: when it fits as well, the honest verdict is
    // indistinguishable, with the located law and a separating case.
    assert!(
        matches!(
            d.verdict.kind,
            VerdictKind::Located | VerdictKind::Indistinguishable
        ),
        "{}",
        d.verdict.note
    );
    if d.verdict.kind == VerdictKind::Indistinguishable {
        assert!(d
            .verdict
            .suggestion
            .as_ref()
            .is_some_and(|g| g.in_sigma >= 3.0));
    }
    assert_located(
        &d,
        &data,
        "body.D_x",
        &["body_ratio", "body_gap_ratio", "body_over_gap"],
    );
}

#[test]
fn names_the_catalogue_effect_and_locates_the_remainder() {
    let truth = Model::base()
        .with_effect(parse_effect_spec("body-confinement").unwrap())
        .with_effect(truths::instance(&truths::SLIP));
    let (d, data) = run(truth);
    assert_eq!(
        d.verdict.kind,
        VerdictKind::Identified,
        "{}",
        d.verdict.note
    );
    assert_eq!(
        d.verdict.effect.as_deref(),
        Some("body-confinement"),
        "{}",
        d.verdict.note
    );
    assert!(d.verdict.effect_explained_fraction.is_some_and(|f| f > 0.3));
    assert_located(&d, &data, "drive.rate", &[]);
}

/// On a fresh draw (seed 41, tests/fixtures/drawn.rs): a tail
/// drag rising near the wall is located on the tail with a wall feature
/// (on `tail.drag`, or on `tail.thrust` falling: in the axial model both
/// change the ratio of thrust to drag, and the law says so in its
/// `equivalent`), never on `drive.rate`.
#[test]
fn a_tail_drag_rising_near_the_wall_is_placed_on_the_tail() {
    let seed = 41;
    let truth = Model::base().with_effect(drawn::tail_wall_drag(seed));
    let data = drawn_data(&truth, &drawn::design(&swimbot::data::paper(), seed), seed);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    let v = &d.verdict;
    let l = v.located.first().unwrap_or_else(|| panic!("{}", v.note));
    assert!(
        ["tail.drag", "tail.thrust"].contains(&l.place),
        "{}",
        v.note
    );
    let stated = l.place == "tail.drag"
        || l.equivalent
            .iter()
            .any(|e| e.place == "tail.drag" && e.relation == "opposite");
    assert!(stated, "{}: {:?}", l.describe(), l.equivalent);
    assert!(
        l.feature
            .as_deref()
            .is_some_and(|f| WALL_FEATURES.contains(&f)),
        "{}",
        v.note
    );
    assert!(
        v.located.iter().all(|l| l.place != "drive.rate"),
        "{}",
        v.note
    );
    assert_no_repeats(v);
}

/// Held-out seed 207 of the recovery study: body-confinement
/// with a tail drag rising near the wall. The catalogue pair
/// body-confinement + buoyancy reaches the floor too (a free trim stands in
/// for the drag), and must not be identified without the located law
/// being weighed against it; the catalogue effect with the law on top of it wins by
/// the margin plus the search's charge, as a law alone must.
#[test]
fn a_catalogue_pair_at_the_floor_is_weighed_against_the_effect_with_a_law() {
    let seed = 207;
    let truth = Model::base()
        .with_effect(parse_effect_spec("body-confinement").unwrap())
        .with_effect(drawn::tail_wall_drag(seed));
    let data = drawn_data(&truth, &drawn::design(&swimbot::data::paper(), seed), seed);
    let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
    let v = &d.verdict;
    assert_eq!(v.kind, VerdictKind::Identified, "{}", v.note);
    assert_eq!(v.effect.as_deref(), Some("body-confinement"), "{}", v.note);
    let l = v.located.first().unwrap_or_else(|| panic!("{}", v.note));
    let on_the_drag = l.place == "tail.drag"
        || l.equivalent
            .iter()
            .any(|e| e.place == "tail.drag" && e.relation == "opposite");
    assert!(on_the_drag, "{}", v.note);
    assert!(
        l.feature
            .as_deref()
            .is_some_and(|f| WALL_FEATURES.contains(&f)),
        "{}",
        v.note
    );
}
