//! The leak-free tube solver (`swimbot::nonlocal::tube`): free-space limit,
//! leak diagnostics against the old wall, a sphere on the tube axis against
//! Haberman & Sayre (1958), symmetry and positive-definiteness, and the
//! `helix --channel-diameter-mm` command. Small cases only (coarse walls,
//! two-turn tails); the converged studies are in `examples/tail_tube.rs`.

use crate::common;
use common::swimbot;
use nalgebra::Matrix6;
use swimbot::data::paper;
use swimbot::nonlocal::rigid::spd_check;
use swimbot::nonlocal::tube::{
    sphere_resistance_in_tube, tail_resistance_in_tube, TubeSettings, WallModel,
};
use swimbot::nonlocal::{
    free_body_resistance, tail_resistance, tail_resistance_in_channel, NonlocalSettings,
};
use swimbot::physics::geometry::{Body, Channel, Helix};

fn free_sphere(ns: &NonlocalSettings) -> Matrix6<f64> {
    let unit = Body {
        length_m: 2.0,
        diameter_m: 2.0,
    };
    free_body_resistance(&unit, 1.0, ns).unwrap()
}

const MU: f64 = 3.5;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn axial(m: &Matrix6<f64>) -> [f64; 3] {
    [m[(0, 0)], m[(0, 3)], m[(3, 3)]]
}

fn closed(d_m: f64) -> Channel {
    Channel {
        diameter_m: d_m,
        length_m: f64::INFINITY,
        closed: true,
        vertical: true,
    }
}

/// Paper tail #6 (the widest, nearest the wall) cut to two turns.
fn two_turn_tail6() -> Helix {
    let c = &paper().cases[5];
    let mut h = c.helix();
    h.axial_length_m = 2.0 * h.wavelength_m;
    h
}

#[test]
fn far_wall_tends_to_the_free_space_stokeslet_result() {
    let h = Helix::from_mm(10.0, 2.5, 20.0, 1.0);
    let free = axial(&tail_resistance(&h, MU, &NonlocalSettings::default()).unwrap());
    let mut errs = vec![];
    for r in [0.2, 0.4] {
        // the wall resolution only has to follow the wall's own scale here
        let s = TubeSettings {
            wall_spacing_m: r / 3.0,
            ..TubeSettings::default()
        };
        let t = tail_resistance_in_tube(&h, &closed(2.0 * r), MU, &s).unwrap();
        let a = axial(&t.matrix);
        let e: Vec<f64> = (0..3).map(|k| a[k] / free[k] - 1.0).collect();
        println!("R = {r} m: tube/free - 1 = {e:?}");
        errs.push(e);
    }
    for k in 0..3 {
        // the wall's effect decays like 1/R (Stokeslet in a tube): halving
        assert!(errs[0][k] >= 0.0 && errs[1][k] >= 0.0, "{errs:?}");
        let ratio = errs[1][k] / errs[0][k];
        assert!(ratio > 0.35 && ratio < 0.65, "k {k}: ratio {ratio}");
        // Richardson extrapolation to R -> infinity recovers free space
        let extra = 2.0 * errs[1][k] - errs[0][k];
        assert!(extra.abs() < 0.005, "k {k}: extrapolated {extra}");
    }
}

#[test]
fn mfs_wall_keeps_the_flux_the_old_wall_leaks() {
    let h = two_turn_tail6();
    let ch = closed(35e-3);
    let mfs = tail_resistance_in_tube(
        &h,
        &ch,
        MU,
        &TubeSettings {
            wall_spacing_m: 6e-3,
            ..TubeSettings::default()
        },
    )
    .unwrap();
    let leaky = tail_resistance_in_tube(
        &h,
        &ch,
        MU,
        &TubeSettings {
            wall: WallModel::Leaky,
            wall_spacing_m: 6e-3,
            cap_margin_over_radius: 2.0,
            ..TubeSettings::default()
        },
    )
    .unwrap();
    let (dm, dl) = (&mfs.diagnostics, &leaky.diagnostics);
    println!("MFS: {dm:?}\nleaky: {dl:?}");
    let qm = dm
        .flux_over_piston_translation
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    let ql = dl
        .flux_over_piston_translation
        .iter()
        .fold(0.0_f64, |m, v| m.max(v.abs()));
    assert!(qm < 0.01, "MFS flux {qm}");
    assert!(ql > 0.12, "old wall flux {ql}");
    // the leak costs the old wall a large part of the axial drag and thrust
    let (am, al) = (axial(&mfs.matrix), axial(&leaky.matrix));
    assert!(
        am[0] > 1.15 * al[0] && am[1].abs() > 1.15 * al[1].abs(),
        "{am:?} {al:?}"
    );
    // axial rotation builds no pressure difference: both walls agree
    assert!(rel(am[2], al[2]) < 0.01, "{am:?} {al:?}");
}

#[test]
fn the_old_wall_rebuilt_here_is_the_old_solver() {
    let h = two_turn_tail6();
    let ch = closed(35e-3);
    let old_settings = NonlocalSettings {
        wall_spacing_m: 6e-3,
        ..NonlocalSettings::default()
    };
    let old = tail_resistance_in_channel(&h, &ch, MU, &old_settings).unwrap();
    let new = tail_resistance_in_tube(
        &h,
        &ch,
        MU,
        &TubeSettings {
            tail: old_settings,
            wall: WallModel::Leaky,
            wall_spacing_m: 6e-3,
            cap_margin_over_radius: old_settings.tube_end_margin_over_radius,
            ..TubeSettings::default()
        },
    )
    .unwrap();
    let diff = (old - new.matrix).abs().max() / old.abs().max();
    assert!(diff < 1e-9, "{diff}");
}

#[test]
fn sphere_on_the_axis_matches_haberman_sayre() {
    // Haberman & Sayre (1958) wall factor, sphere on the axis of a tube with
    // fluid at rest far away, lambda = a / R = 0.3.
    let lam: f64 = 0.3;
    let k_hs = (1.0 - 0.75857 * lam.powi(5))
        / (1.0 - 2.1050 * lam + 2.0865 * lam.powi(3) - 1.7068 * lam.powi(5)
            + 0.72603 * lam.powi(6));
    let ch = closed(2.0 / lam);
    // The MFS wall is converged at 0.7 a (0.14 % from 0.5 a, measured); the
    // remaining error is the sphere's own first-order regularization error,
    // so refine the sphere and extrapolate linearly in its spacing.
    let mut k = vec![];
    let spacings = [0.3, 0.22];
    for hs in spacings {
        let ns = NonlocalSettings {
            body_spacing_m: hs,
            ..NonlocalSettings::default()
        };
        let free = free_sphere(&ns);
        let s = TubeSettings {
            tail: ns,
            wall_spacing_m: 0.7,
            ..TubeSettings::default()
        };
        let t = sphere_resistance_in_tube(1.0, hs, &ch, 1.0, &s).unwrap();
        println!(
            "sphere spacing {hs}: K = {:.4}; {:?}",
            t.matrix[(0, 0)] / free[(0, 0)],
            t.diagnostics
        );
        assert!(t.diagnostics.max_flux() < 0.01, "{:?}", t.diagnostics);
        k.push(t.matrix[(0, 0)] / free[(0, 0)]);
    }
    let k_extra = k[1] - (k[0] - k[1]) * spacings[1] / (spacings[0] - spacings[1]);
    println!("K {k:?}, extrapolated {k_extra:.4}, Haberman & Sayre {k_hs:.4}");
    assert!(
        rel(k[1], k_hs) < rel(k[0], k_hs) && rel(k[1], k_hs) < 0.03,
        "{k:?}"
    );
    assert!(rel(k_extra, k_hs) < 0.015, "{k_extra} vs {k_hs}");
    let (k, ns) = (
        k[1],
        NonlocalSettings {
            body_spacing_m: 0.22,
            ..NonlocalSettings::default()
        },
    );
    // the old wall at the same spacing is far off (it leaks)
    let leaky = TubeSettings {
        tail: ns,
        wall: WallModel::Leaky,
        wall_spacing_m: 0.7,
        cap_margin_over_radius: ns.tube_end_margin_over_radius,
        ..TubeSettings::default()
    };
    let old = sphere_resistance_in_tube(1.0, 0.22, &ch, 1.0, &leaky)
        .unwrap()
        .matrix;
    let free = free_sphere(&ns);
    let k_old = old[(0, 0)] / free[(0, 0)];
    assert!(rel(k_old, k_hs) > 2.0 * rel(k, k_hs), "{k_old}");
}

#[test]
fn tube_matrix_is_symmetric_positive_definite() {
    let t = tail_resistance_in_tube(
        &two_turn_tail6(),
        &closed(35e-3),
        MU,
        &TubeSettings {
            wall_spacing_m: 6e-3,
            ..TubeSettings::default()
        },
    )
    .unwrap();
    let (min_eig, asym) = spd_check(&t.matrix);
    println!("min eigenvalue {min_eig:.3e}, asymmetry {asym:.3e}");
    assert!(min_eig > 0.0, "{min_eig}");
    assert!(asym < 0.02, "{asym}");
}

const TAIL6_2: [&str; 8] = [
    "helix",
    "--wavelength-mm",
    "11",
    "--amplitude-mm",
    "7.5",
    "--tail-length-mm",
    "22",
    "--format=json",
];

#[test]
fn cli_gives_the_tube_matrix_with_its_diagnostics() {
    let mut a = TAIL6_2.to_vec();
    a.extend(["--channel-diameter-mm", "35", "--wall-spacing-mm", "6"]);
    let out = swimbot(&a);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let free = swimbot(&[&TAIL6_2[..], &["--tail-model", "stokeslets"]].concat());
    let f: serde_json::Value = serde_json::from_slice(&free.stdout).unwrap();
    for key in ["drag_n_s_per_m", "thrust_n_s", "torque_n_m_s"] {
        let (t, f) = (v[key].as_f64().unwrap(), f[key].as_f64().unwrap());
        assert!(t.abs() > f.abs(), "{key}: tube {t} free {f}");
    }
    let d = &v["tube"]["diagnostics"];
    assert_eq!(v["tube"]["closed"], true);
    assert_eq!(
        d["flux_over_piston_translation"].as_array().unwrap().len(),
        3
    );
    assert!(d["wall_slip_over_u"].as_f64().unwrap() >= 0.0);
}

#[test]
fn cli_rejects_bad_tubes_with_exit_2() {
    let cases: [(&[&str], &str); 7] = [
        (&["--channel-diameter-mm", "12"], "does not fit"),
        // the field limit, before any counting or building
        (&["--channel-diameter-mm", "1e9"], "channel-diameter-mm"),
        // counted, not built: 10 GB would be refused in milliseconds
        (
            &["--channel-diameter-mm", "35", "--wall-spacing-mm", "0.01"],
            "above --max-memory-gb",
        ),
        (
            &["--channel-diameter-mm", "35", "--max-memory-gb", "1e9"],
            "more than this machine has",
        ),
        (&["--channel-diameter-mm=-5"], "channel-diameter-mm"),
        (
            &["--channel-diameter-mm", "35", "--max-memory-gb", "0.001"],
            "GB",
        ),
        (
            &["--channel-diameter-mm", "35", "--channel-length-mm", "10"],
            "channel of length",
        ),
    ];
    for (extra, msg) in cases {
        let out = swimbot(&[&TAIL6_2[..], extra].concat());
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {err}");
        assert!(err.contains(msg), "{extra:?}: {err}");
    }
}

/// The ring solver is an exact rearrangement of the dense solve: the same
/// forces to round-off, for both cap layouts, open and closed tubes.
#[test]
fn ring_solver_equals_the_dense_solve() {
    use swimbot::nonlocal::tube::{CapLayout, WallSolver};
    let h = two_turn_tail6();
    for (caps, closed_tube) in [
        (CapLayout::Rings, true),
        (CapLayout::Graded, true),
        (CapLayout::Rings, false),
    ] {
        let mut ch = closed(35e-3);
        ch.closed = closed_tube;
        let s = TubeSettings {
            wall_spacing_m: 6e-3,
            caps,
            ..TubeSettings::default()
        };
        let dense = tail_resistance_in_tube(
            &h,
            &ch,
            MU,
            &TubeSettings {
                solver: WallSolver::Dense,
                ..s
            },
        )
        .unwrap();
        let ring = tail_resistance_in_tube(&h, &ch, MU, &s).unwrap();
        let diff = (dense.matrix - ring.matrix).abs().max() / dense.matrix.abs().max();
        println!("{caps:?} closed {closed_tube}: {diff:e}");
        assert!(diff < 1e-9, "{caps:?} {closed_tube}: {diff}");
        let (qd, qr) = (dense.diagnostics.max_flux(), ring.diagnostics.max_flux());
        assert!((qd - qr).abs() < 1e-9 + 1e-6 * qd.abs(), "{qd} {qr}");
    }
}

/// Peak resident memory of this process so far (`VmHWM`), bytes.
fn vm_hwm_bytes() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    Some(1024 * line.split_whitespace().nth(1)?.parse::<u64>().ok()?)
}

const PROBE_ENV: &str = "SWIMBOT_TUBE_MEMORY_PROBE";

/// The child half of the memory test below, in a process of its own (so
/// that no other test's allocations count): the whole paper tail #3 in the
/// closed tube at a 4 mm wall, its estimate and the measured peak growth.
#[test]
#[ignore = "the child process of tube_memory_estimate_holds_against_the_measured_peak"]
fn tube_memory_probe() {
    if std::env::var_os(PROBE_ENV).is_none() {
        return;
    }
    let c = &paper().cases[2];
    let s = TubeSettings {
        wall_spacing_m: 4e-3,
        ..TubeSettings::default()
    };
    let (h, ch) = (c.helix(), c.channel());
    let budget = swimbot::nonlocal::tube::tail_in_tube_budget(&h, &ch, &s).unwrap();
    let before = vm_hwm_bytes().unwrap();
    let r = tail_resistance_in_tube(&h, &ch, MU, &s).unwrap();
    let after = vm_hwm_bytes().unwrap();
    assert!(r.matrix[(0, 0)] > 0.0);
    println!("PROBE {} {before} {after}", budget.peak_bytes);
}

#[test]
fn tube_memory_estimate_holds_against_the_measured_peak() {
    if vm_hwm_bytes().is_none() {
        println!("no /proc/self/status here: nothing to measure");
        return;
    }
    let out = std::process::Command::new(std::env::current_exe().unwrap())
        .args([
            "--exact",
            "tail_tube::tube_memory_probe",
            "--ignored",
            "--nocapture",
            "--test-threads=1",
        ])
        .env(PROBE_ENV, "1")
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    let line = text
        .lines()
        .find_map(|l| l.split("PROBE ").nth(1))
        .unwrap_or_else(|| panic!("probe printed no result: {text}"));
    let v: Vec<f64> = line
        .split_whitespace()
        .map(|x| x.parse().unwrap())
        .collect();
    let (estimate, grown) = (v[0], v[2] - v[1]);
    println!(
        "estimated {:.1} MB, measured peak growth {:.1} MB",
        estimate / 1e6,
        grown / 1e6
    );
    // honest means neither low (the solve would exceed its budget) nor
    // wildly high (a budget that refuses what would fit)
    assert!(grown <= estimate, "{grown} > {estimate}");
    assert!(grown >= 0.6 * estimate, "{grown} << {estimate}");
}
