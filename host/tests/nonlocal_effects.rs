//! The wall-resolved confinement effects `tail-confinement-stokeslets` and
//! `body-confinement-exact`, and the non-local matrix cache behind
//! them. One cheap geometry keeps the solves short: the paper's tail #6
//! (wavelength 11 mm, amplitude 7.5 mm, the widest, nearest the wall) cut
//! to two turns, and the paper's body, in the closed 35 mm channel.
//!
//! Every test first points `$SWIMBOT_CACHE_DIR` at a new directory, so the
//! effects really solve (a warm cache from an earlier run would hide a
//! broken solver) and nothing lands in the user's cache.

use nalgebra::Matrix6;
use std::f64::consts::PI;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;
use swimbot::data::{paper, Case};
use swimbot::effects::{by_name, parse_effect_spec};
use swimbot::model::Model;
use swimbot::nonlocal::cache::{cached_matrix_in, DiskCache, CACHE_DIR_ENV};
use swimbot::nonlocal::{tail_resistance, tail_resistance_in_channel, NonlocalSettings};

const TUBE_TAIL: &str = "tail-confinement-stokeslets";
const TUBE_BODY: &str = "body-confinement-exact";

/// A fresh cache directory for this test process, set before any solve.
fn fresh_cache() -> &'static std::path::Path {
    static DIR: OnceLock<std::path::PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = tempfile::Builder::new()
            .prefix("swimbot-test-cache")
            .tempdir()
            .unwrap()
            .keep();
        // Inside the OnceLock: every test calls this before reading the
        // variable (through the effects), so no thread reads it mid-write.
        std::env::set_var(CACHE_DIR_ENV, &dir);
        dir
    })
}

fn short_tail_case() -> Case {
    let mut c = paper().cases[5].clone();
    c.id = "tail-6-two-turns".into();
    c.tail_length_mm = 2.0 * c.wavelength_mm;
    c
}

fn with(spec: &str) -> Model {
    Model::base().with_effect(parse_effect_spec(spec).unwrap())
}

fn tube_tail_matrix(case: &Case) -> Matrix6<f64> {
    fresh_cache();
    with(TUBE_TAIL).tail_matrix(case).unwrap()
}

#[test]
fn both_effects_are_catalogued_parameter_free_and_not_default_candidates() {
    let builtin = swimbot::effects::Catalogue::builtin();
    for name in [TUBE_TAIL, TUBE_BODY] {
        let e = by_name(name).unwrap_or_else(|| panic!("{name} missing"));
        assert!(e.params().is_empty());
        assert!(
            e.costly() && e.candidate(),
            "{name}: proposed only by `diagnose --nonlocal`"
        );
        let default_candidates = swimbot::workbench::diagnose::candidates(
            &builtin,
            &swimbot::model::Model::base(),
            false,
        );
        assert!(default_candidates.iter().all(|c| c.name() != name));
        let nonlocal_candidates = swimbot::workbench::diagnose::candidates(
            &builtin,
            &swimbot::model::Model::base(),
            true,
        );
        assert!(nonlocal_candidates.iter().any(|c| c.name() == name));
        assert_eq!(e.order(), 0);
    }
}

#[test]
fn the_wall_raises_the_tails_axial_drag_and_thrust_coupling() {
    let case = short_tail_case();
    let tube = tube_tail_matrix(&case);
    let free = tail_resistance(
        &case.helix(),
        case.viscosity_pa_s,
        &NonlocalSettings::default(),
    )
    .unwrap();
    let ratio = |i: usize, j: usize| tube[(i, j)] / free[(i, j)];
    println!(
        "two-turn tail #6 in the tube / free: xx {:.3}, x-wx {:.3}, wx-wx {:.3}",
        ratio(0, 0),
        ratio(0, 3),
        ratio(3, 3)
    );
    // same sign (same handedness) and larger in magnitude
    assert!(ratio(0, 0) > 1.05, "{}", ratio(0, 0));
    assert!(ratio(0, 3) > 1.05, "{}", ratio(0, 3));
    assert!(ratio(3, 3) > 1.0, "{}", ratio(3, 3));
    // a resistance matrix stays symmetric
    let asym = (tube - tube.transpose()).abs().max() / tube.abs().max();
    assert!(asym < 0.05, "asymmetry {asym}");
}

#[test]
fn the_wall_raises_the_bodys_drag_towards_the_annular_gap_limit() {
    fresh_cache();
    let case = paper().cases[0].clone();
    let free = Model::base().body_matrix(&case).unwrap();
    let tube = with(TUBE_BODY).body_matrix(&case).unwrap();
    // The coaxial-cylinder (annular Couette-Poiseuille) drag of
    // `body-confinement`, closed tube. The built-in body is the robot's
    // parts, whose 18 mm waist widens the gap: the exact drag is 0.945 of the
    // formula (the plain spheroid's 0.58, a sharp 50 x 20 mm cylinder's 1.15;
    // see docs/body-in-tube.md).
    let k = case.body_diameter_mm / case.channel_diameter_mm;
    let cylinder = 2.0 * PI * case.viscosity_pa_s * case.body_length_mm * 1e-3
        / ((1.0 / k).ln() - (1.0 - k * k) / (1.0 + k * k));
    let (r_free, r_cyl) = (tube[(0, 0)] / free[(0, 0)], tube[(0, 0)] / cylinder);
    println!(
        "body axial drag: free {:.3} N s/m, in tube {:.3} N s/m ({r_free:.2} x free), cylinder formula {cylinder:.3} N s/m ({r_cyl:.3} x); torque {:.3e} vs free {:.3e} N m s",
        free[(0, 0)],
        tube[(0, 0)],
        tube[(3, 3)],
        free[(3, 3)]
    );
    assert!(r_free > 2.0, "{r_free}");
    assert!(r_cyl > 0.1 && r_cyl < 1.0, "{r_cyl}");
    assert!(tube[(3, 3)] > free[(3, 3)]);
    // only the two axial entries are replaced
    assert_eq!(tube[(1, 1)], free[(1, 1)]);
}

#[test]
fn the_effects_compose_with_the_model() {
    let case = short_tail_case();
    let _ = tube_tail_matrix(&case);
    let both = with(TUBE_TAIL).with_effect(parse_effect_spec(TUBE_BODY).unwrap());
    let p = both.predict(&case).unwrap();
    let base = Model::base().predict(&case).unwrap();
    println!(
        "two-turn tail #6: U {:.4} mm/s (base {:.4}), Omega_b {:.4} Hz (base {:.4})",
        p.u_mm_s, base.u_mm_s, p.omega_body_hz, base.omega_body_hz
    );
    assert!(p.u_mm_s.is_finite() && p.omega_body_hz.is_finite());
    assert!(
        p.u_mm_s > 0.0 && p.u_mm_s < base.u_mm_s,
        "the closed tube slows the robot"
    );
}

#[test]
fn a_geometry_the_wall_cannot_hold_is_an_error_not_a_prediction() {
    fresh_cache();
    let mut case = short_tail_case();
    // narrower than the 20 mm body and the 16 mm tail envelope plus wall points
    case.channel_diameter_mm = 17.0;
    let tail_err = with(TUBE_TAIL).predict(&case).unwrap_err().to_string();
    assert!(tail_err.contains(TUBE_TAIL), "{tail_err}");
    let body_err = with(TUBE_BODY).predict(&case).unwrap_err().to_string();
    assert!(
        body_err.contains(TUBE_BODY) && body_err.contains("does not fit"),
        "the body's failed solve names the effect and why: {body_err}"
    );
}

#[test]
fn the_disk_cache_returns_the_identical_matrix_and_survives_corruption() {
    let dir = tempfile::tempdir().unwrap();
    let disk = DiskCache::new(dir.path());
    let case = short_tail_case();
    let (h, ch, mu) = (case.helix(), case.channel(), case.viscosity_pa_s);
    let s = NonlocalSettings {
        wall_spacing_m: 5e-3,
        ..Default::default()
    };
    let key = [h.axial_length_m.to_bits(), s.wall_spacing_m.to_bits()];
    let solves = AtomicUsize::new(0);
    let solve = || {
        solves.fetch_add(1, Ordering::SeqCst);
        tail_resistance_in_channel(&h, &ch, mu, &s)
    };
    let first = disk.get_or_compute("test-tail", &key, solve).unwrap();
    let second = disk.get_or_compute("test-tail", &key, solve).unwrap();
    assert_eq!(
        solves.load(Ordering::SeqCst),
        1,
        "second call read the file"
    );
    assert!(first
        .iter()
        .zip(second.iter())
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    let path = disk.path("test-tail", &key);
    for garbage in [
        "",
        "not a cache file\n",
        "swimbot-nonlocal-cache revision 1 test-tail\n00\n",
    ] {
        std::fs::write(&path, garbage).unwrap();
        assert!(disk.load("test-tail", &key).is_none());
        let again = disk.get_or_compute("test-tail", &key, solve).unwrap();
        assert_eq!(again, first);
    }
    assert_eq!(solves.load(Ordering::SeqCst), 4);
    // the rewritten file is valid again, and a different key misses it
    assert_eq!(disk.load("test-tail", &key), Some(first));
    assert_eq!(disk.load("test-tail", &[key[0], 0]), None);
    // no temporary file is left behind: the matrix's file and the key's
    // lock file, which stays by design (nonlocal/cache.rs, `lock`)
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names.len(), 2, "{names:?}");
    assert!(
        names[0].ends_with(".lock") && names[1].ends_with(".txt"),
        "{names:?}"
    );
}

#[test]
fn the_memory_layer_solves_each_key_once_and_remembers_failures() {
    let dir = tempfile::tempdir().unwrap();
    let disk = DiskCache::new(dir.path());
    let calls = AtomicUsize::new(0);
    let m = Matrix6::from_fn(|i, j| (1 + i + j) as f64);
    for _ in 0..3 {
        let got = cached_matrix_in(&disk, "test-memory", &[7], || {
            calls.fetch_add(1, Ordering::SeqCst);
            Ok::<_, String>(m)
        });
        assert_eq!(got, Ok(m));
    }
    for _ in 0..3 {
        let got = cached_matrix_in(&disk, "test-memory", &[8], || {
            calls.fetch_add(1, Ordering::SeqCst);
            Err("singular".to_string())
        })
        // The failure is kept as the solver's message.
        .map_err(|e| e.to_string());
        assert_eq!(got, Err("singular".to_string()));
    }
    assert_eq!(calls.load(Ordering::SeqCst), 2);
}

/// Both wall-resolved effects solve at 1 Pa s and scale (Stokes flow is
/// linear in the viscosity): the effect's matrix equals a direct solve at
/// the case's viscosity, and a perturbed viscosity scales it exactly.
#[test]
fn the_wall_effects_scale_with_the_viscosity_as_a_direct_solve_does() {
    use swimbot::nonlocal::tube::{tail_resistance_in_tube, TubeSettings};
    fresh_cache();
    let case = short_tail_case();
    let effect = tube_tail_matrix(&case);
    let direct = tail_resistance_in_tube(
        &case.helix(),
        &case.channel(),
        case.viscosity_pa_s,
        &TubeSettings::default(),
    )
    .unwrap()
    .matrix;
    let diff = (effect - direct).abs().max() / direct.abs().max();
    assert!(diff < 1e-12, "{diff}");
    let mut thicker = case.clone();
    thicker.viscosity_pa_s *= 1.37;
    let scaled = tube_tail_matrix(&thicker);
    assert!((scaled - effect * 1.37).abs().max() < 1e-12 * effect.abs().max());
    let body = |c: &Case| with(TUBE_BODY).body_matrix(c).unwrap();
    let (b, b2) = (body(&case), body(&thicker));
    assert!((b2[(0, 0)] / b[(0, 0)] - 1.37).abs() < 1e-12);
    assert!((b2[(3, 3)] / b[(3, 3)] - 1.37).abs() < 1e-12);
    let exact = swimbot::nonlocal::axisym::solve_body(
        &case.body_profile(),
        &swimbot::nonlocal::axisym::Confinement::of_channel(&case.channel()),
        0.0,
        thicker.viscosity_pa_s,
        &swimbot::nonlocal::axisym::AxisymSettings::default(),
    )
    .unwrap();
    assert!((b2[(0, 0)] / exact.drag_n_s_per_m - 1.0).abs() < 1e-12);
}
