//! Validation and convergence tables of the axisymmetric body solver
//! (`swimbot::nonlocal::axisym`), printed as markdown for
//! docs/body-in-tube.md, and asserted: sphere vs Stokes, spheroids vs
//! Chwang & Wu (1975), sphere on a tube axis vs Haberman & Sayre (1958) /
//! Bohlin (1960), long cylinders vs the annular closed forms, mass
//! conservation, and the paper's body in the paper's tube.
//!
//! `cargo run --release -p swimbot --example axisym_validation [-- section]`
//! with section one of `free`, `tube`, `cylinder`, `paper`, `all` (default).

use std::f64::consts::PI;
use swimbot::nonlocal::axisym::{
    annular_formula, solve_body, AxisymSettings, BodySolve, Confinement,
};
use swimbot::physics::profile::BodyProfile;

fn settings(resolution: f64) -> AxisymSettings {
    AxisymSettings {
        resolution,
        ..AxisymSettings::default()
    }
}

fn solve(p: &BodyProfile, c: Confinement, res: f64) -> BodySolve {
    solve_body(p, &c, 0.0, 1.0, &settings(res)).expect("solve")
}

/// Chwang & Wu (1975): axial translation and rotation of a prolate spheroid
/// of semi-axes `a > b`, `mu = 1`.
fn chwang_wu(a: f64, b: f64) -> (f64, f64) {
    let e = (1.0 - (b / a).powi(2)).sqrt();
    let l = ((1.0 + e) / (1.0 - e)).ln();
    let f = 16.0 * PI * a * e.powi(3) / ((1.0 + e * e) * l - 2.0 * e);
    let t = 32.0 / 3.0 * PI * a.powi(3) * e.powi(3) * (1.0 - e * e) / (2.0 * e - (1.0 - e * e) * l);
    (f, t)
}

/// Haberman & Sayre (1958) wall factor, their closed-form fit.
fn haberman_sayre(l: f64) -> f64 {
    (1.0 - 0.75857 * l.powi(5))
        / (1.0 - 2.1050 * l + 2.0865 * l.powi(3) - 1.7068 * l.powi(5) + 0.72603 * l.powi(6))
}

/// Bohlin (1960) series for the same factor.
fn bohlin(l: f64) -> f64 {
    1.0 / (1.0 - 2.10443 * l + 2.08877 * l.powi(3) - 0.94813 * l.powi(5) - 1.372 * l.powi(6)
        + 3.87 * l.powi(8)
        - 4.19 * l.powi(10))
}

fn free() {
    println!("\n### Free space\n");
    println!(
        "| body | resolution | elements | drag / exact - 1 | torque / exact - 1 | time (ms) |"
    );
    println!("|---|---|---|---|---|---|");
    for (name, a, b) in [
        ("sphere", 1.0, 1.0),
        ("spheroid 2.5:1", 2.5, 1.0),
        ("spheroid 10:1", 10.0, 1.0),
    ] {
        let p = BodyProfile::spheroid(2e3 * a, 2e3 * b);
        let (f, t) = if a == b {
            (6.0 * PI * a, 8.0 * PI * a.powi(3))
        } else {
            chwang_wu(a, b)
        };
        for res in [4.0, 8.0, 16.0] {
            let s = solve(&p, Confinement::Free, res);
            println!(
                "| {name} | {res} | {} | {:+.2e} | {:+.2e} | {:.1} |",
                s.body_elements,
                s.drag_n_s_per_m / f - 1.0,
                s.rotational_drag_n_m_s / t - 1.0,
                1e3 * s.seconds
            );
            if res == 8.0 {
                assert!((s.drag_n_s_per_m / f - 1.0).abs() < 0.01);
                assert!((s.rotational_drag_n_m_s / t - 1.0).abs() < 0.01);
            }
        }
    }
}

fn tube() {
    println!("\n### Sphere on the axis of a closed tube (caps 4 R from the sphere)\n");
    println!("| a/R | resolution | K computed | Haberman-Sayre fit | Bohlin series | vs H&S | vs Bohlin | flux error | elements | time (ms) |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for l in [0.1, 0.2, 0.3, 0.4, 0.5, 0.6] {
        let a = 1.0;
        let r = a / l;
        let p = BodyProfile::spheroid(2e3 * a, 2e3 * a);
        for res in [4.0, 8.0, 16.0] {
            let c = Confinement::Closed {
                diameter_m: 2.0 * r,
                length_m: 2.0 * (a + 4.0 * r),
            };
            let s = solve(&p, c, res);
            let k = s.drag_n_s_per_m / (6.0 * PI * a);
            println!(
                "| {l} | {res} | {k:.4} | {:.4} | {:.4} | {:+.2}% | {:+.2}% | {:.1e} | {} | {:.1} |",
                haberman_sayre(l),
                bohlin(l),
                100.0 * (k / haberman_sayre(l) - 1.0),
                100.0 * (k / bohlin(l) - 1.0),
                s.flux_error().unwrap(),
                s.body_elements + s.wall_elements,
                1e3 * s.seconds
            );
        }
    }
    println!("\n### Cap distance (sphere a/R = 0.4, resolution 8)\n");
    println!("| cap distance / R | K | flux error |");
    println!("|---|---|---|");
    for d in [0.5, 1.0, 2.0, 4.0, 8.0] {
        let (a, r) = (1.0, 2.5);
        let c = Confinement::Closed {
            diameter_m: 2.0 * r,
            length_m: 2.0 * (a + d * r),
        };
        let s = solve(&BodyProfile::spheroid(2e3, 2e3), c, 8.0);
        println!(
            "| {d} | {:.4} | {:.1e} |",
            s.drag_n_s_per_m / (6.0 * PI * a),
            s.flux_error().unwrap()
        );
    }
}

fn tube_of(closed: bool, diameter_m: f64, length_m: f64) -> Confinement {
    if closed {
        Confinement::Closed {
            diameter_m,
            length_m,
        }
    } else {
        Confinement::Open {
            diameter_m,
            length_m,
        }
    }
}

/// Per-length drag and torque of a cylinder of radius 1 from lengths
/// `l1 < l2`, in a tube of radius `1/k` reaching `margin` beyond its ends.
fn per_length(
    closed: bool,
    k: f64,
    res: f64,
    margin: f64,
    l1: f64,
    l2: f64,
) -> (f64, f64, BodySolve) {
    let b = 1.0 / k;
    let run = |len: f64| {
        solve(
            &BodyProfile::cylinder(1e3 * len, 2e3, 0.0),
            tube_of(closed, 2.0 * b, len + 2.0 * margin),
            res,
        )
    };
    let (s1, s2) = (run(l1), run(l2));
    let df = (s2.drag_n_s_per_m - s1.drag_n_s_per_m) / (l2 - l1);
    let dt = (s2.rotational_drag_n_m_s - s1.rotational_drag_n_m_s) / (l2 - l1);
    (df, dt, s2)
}

fn cylinder() {
    println!("\n### Long cylinder (a = 1) in a closed tube (caps 3 b beyond its ends), per-length drag and torque from lengths 8 and 16\n");
    println!("| k = a/b | resolution | drag/length vs Couette-Poiseuille | torque/length vs Couette | flux error | elements |");
    println!("|---|---|---|---|---|---|");
    for k in [0.5, 0.8] {
        for res in [4.0, 8.0, 16.0] {
            let (df, dt, s2) = per_length(true, k, res, 3.0 / k, 8.0, 16.0);
            let (f, t) = annular_formula(1.0, 1.0 / k, 1.0, 1.0, true);
            println!(
                "| {k} | {res} | {:+.3}% | {:+.3}% | {:.1e} | {} |",
                100.0 * (df / f - 1.0),
                100.0 * (dt / t - 1.0),
                s2.flux_error().unwrap(),
                s2.body_elements + s2.wall_elements
            );
            if res == 8.0 {
                assert!((df / f - 1.0).abs() < 0.01 && (dt / t - 1.0).abs() < 0.01);
            }
        }
    }
    println!("\n### Long cylinder in an open tube (k = 0.5, resolution 8): the pressure drop of a finite open pipe\n");
    println!("| pipe beyond each end | lengths | drag/length vs Couette (ln 1/k) | torque/length vs Couette | flux error |");
    println!("|---|---|---|---|---|");
    for (margin_b, l1, l2) in [
        (1.0, 8.0, 16.0),
        (0.25, 8.0, 16.0),
        (0.25, 16.0, 32.0),
        (0.1, 16.0, 32.0),
    ] {
        let (df, dt, s2) = per_length(false, 0.5, 8.0, margin_b * 2.0, l1, l2);
        let (f, t) = annular_formula(1.0, 2.0, 1.0, 1.0, false);
        println!(
            "| {margin_b} b | {l1}, {l2} | {:+.3}% | {:+.3}% | {:.1e} |",
            100.0 * (df / f - 1.0),
            100.0 * (dt / t - 1.0),
            s2.flux_error().unwrap()
        );
    }
}

fn paper() {
    let (d_mm, l_mm, mu) = (35.0, 350.0, 3.5);
    let bodies = [
        ("spheroid 50 x 20", BodyProfile::spheroid(50.0, 20.0)),
        (
            "cylinder 50 x 20, sharp",
            BodyProfile::cylinder(50.0, 20.0, 0.0),
        ),
        (
            "paper body 10:20,30:18,10:20",
            BodyProfile::parse_sections("10:20,30:18,10:20", 0.0).unwrap(),
        ),
        (
            "paper body, rims rounded 2 mm",
            BodyProfile::parse_sections("10:20,30:18,10:20", 2.0).unwrap(),
        ),
    ];
    for closed in [true, false] {
        println!(
            "\n### The paper's body in the paper's {} tube (35 mm x 350 mm, 3.5 Pa s)\n",
            if closed { "closed" } else { "open" }
        );
        let (fa, ta) = annular_formula(0.01, 0.0175, 0.05, mu, closed);
        println!("annular formula (50 x 20 mm cylinder, no ends): drag {fa:.4} N s/m, rotational drag {ta:.4e} N m s\n");
        println!("| body | drag (N s/m) | / free | / annular | rot. drag (N m s) | / free | / annular | flux error | elements | time (ms) |");
        println!("|---|---|---|---|---|---|---|---|---|---|");
        for (name, p) in &bodies {
            let s = solve_body(
                p,
                &tube_of(closed, d_mm * 1e-3, l_mm * 1e-3),
                0.0,
                mu,
                &settings(8.0),
            )
            .unwrap();
            let free = solve_body(p, &Confinement::Free, 0.0, mu, &settings(8.0)).unwrap();
            println!(
                "| {name} | {:.4} | {:.2} | {:.3} | {:.4e} | {:.3} | {:.3} | {:.1e} | {} | {:.0} |",
                s.drag_n_s_per_m,
                s.drag_n_s_per_m / free.drag_n_s_per_m,
                s.drag_n_s_per_m / fa,
                s.rotational_drag_n_m_s,
                s.rotational_drag_n_m_s / free.rotational_drag_n_m_s,
                s.rotational_drag_n_m_s / ta,
                s.flux_error().unwrap(),
                s.body_elements + s.wall_elements,
                1e3 * s.seconds
            );
        }
    }
    println!("\n### Resolution and position (paper spheroid, closed tube)\n");
    println!("| resolution | body centre (mm) | drag (N s/m) | rot. drag (N m s) | flux error | elements | time (ms) |");
    println!("|---|---|---|---|---|---|---|");
    for (res, pos) in [
        (4.0, 0.0),
        (8.0, 0.0),
        (16.0, 0.0),
        (32.0, 0.0),
        (8.0, 100.0),
        (8.0, 140.0),
    ] {
        let s = solve_body(
            &BodyProfile::spheroid(50.0, 20.0),
            &tube_of(true, 0.035, 0.35),
            pos * 1e-3,
            mu,
            &settings(res),
        )
        .unwrap();
        println!(
            "| {res} | {pos} | {:.5} | {:.5e} | {:.1e} | {} | {:.0} |",
            s.drag_n_s_per_m,
            s.rotational_drag_n_m_s,
            s.flux_error().unwrap(),
            s.body_elements + s.wall_elements,
            1e3 * s.seconds
        );
    }
}

fn main() {
    let which = std::env::args().nth(1).unwrap_or_else(|| "all".into());
    if which == "free" || which == "all" {
        free();
    }
    if which == "tube" || which == "all" {
        tube();
    }
    if which == "cylinder" || which == "all" {
        cylinder();
    }
    if which == "paper" || which == "all" {
        paper();
    }
}
