//! The coupler's spin torque by the axisymmetric solver
//! (`nonlocal::axisym::spin`): convergence with resolution, the gap sweep,
//! the analytic limits and the composite estimate, as tabled in
//! docs/physics.md section 4. `cargo run --release --example coupler_spin`.

use std::f64::consts::PI;
use swimbot::nonlocal::axisym::spin::{solve_spin, SpinSolve, Stack};
use swimbot::nonlocal::axisym::{AxisymSettings, Confinement};
use swimbot::physics::profile::BodyProfile;

const MU: f64 = 3.5;

fn robot(gap_mm: f64) -> Stack {
    Stack {
        rotor: BodyProfile::cylinder(10.0, 6.0, 0.0),
        stator: Some(BodyProfile::parse_sections("10:20,30:18,10:20", 0.0).unwrap()),
        gap_m: gap_mm * 1e-3,
    }
}

fn tube() -> Confinement {
    Confinement::Closed {
        diameter_m: 0.035,
        length_m: 0.35,
    }
}

fn at(stack: &Stack, c: &Confinement, resolution: f64) -> SpinSolve {
    let s = AxisymSettings {
        resolution,
        ..AxisymSettings::default()
    };
    solve_spin(stack, c, 0.0, MU, &s).expect("solve")
}

fn main() {
    println!("## convergence, gap 1 mm, paper's tube (closed 35 x 350 mm), mu 3.5 Pa s");
    println!("| resolution | elements (rotor/stator/wall) | T_c (N m s) | T on body | T on wall | balance | s |");
    for r in [2.0, 4.0, 8.0, 16.0, 32.0] {
        if std::env::args().any(|a| a == "--skip-table") {
            break;
        }
        let x = at(&robot(1.0), &tube(), r);
        println!(
            "| {r} | {}/{}/{} | {:.5e} | {:.4e} | {:.4e} | {:.1e} | {:.2} |",
            x.rotor_elements,
            x.stator_elements,
            x.wall_elements,
            x.rotational_drag_n_m_s,
            x.stator_torque_n_m_s,
            x.wall_torque_n_m_s,
            x.torque_balance(),
            x.seconds
        );
    }
    println!("## gap sweep (resolution 8 and 16)");
    for g in [0.15, 0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 30.0] {
        let a = at(&robot(g), &tube(), 8.0);
        let b = at(&robot(g), &tube(), 16.0);
        println!(
            "| {g} | {:.5e} | {:.5e} | {:+.2} % |",
            a.rotational_drag_n_m_s,
            b.rotational_drag_n_m_s,
            100.0 * (a.rotational_drag_n_m_s / b.rotational_drag_n_m_s - 1.0)
        );
    }
    let free = Stack {
        stator: None,
        ..robot(1.0)
    };
    for r in [4.0, 8.0, 16.0, 32.0] {
        let x = at(&free, &Confinement::Free, r);
        println!(
            "free coupler res {r}: {:.5e}  ({} el)",
            x.rotational_drag_n_m_s, x.rotor_elements
        );
    }
    for r in [8.0, 16.0] {
        let x = at(&free, &tube(), r);
        println!(
            "coupler in tube, no body res {r}: {:.5e}",
            x.rotational_drag_n_m_s
        );
    }
    for g in [10.0, 30.0, 100.0] {
        let x = at(&robot(g), &Confinement::Free, 8.0);
        println!("free space gap {g} mm: {:.5e}", x.rotational_drag_n_m_s);
    }
    let a = 3e-3;
    let side = 4.0 * PI * MU * a * a * 0.01;
    println!("side 4 pi mu a^2 L = {side:.5e}");
    // Composite estimate: Couette side in the tube, one free disc face
    // (half of 32/3 mu a^3) below, the lubrication film pi mu a^4 / (2 g)
    // above; it ignores the flow round the rims.
    let b = 17.5e-3;
    let couette = side * b * b / (b * b - a * a);
    let disc = 16.0 / 3.0 * MU * a.powi(3);
    let film = PI * MU * a.powi(4) / (2.0 * 1e-3);
    println!(
        "composite: Couette side {couette:.4e} + free face {disc:.4e} + film {film:.4e} = {:.4e}",
        couette + disc + film
    );
    // Jeffery (1915): a sphere spinning about the normal to a plane wall.
    for gap in [0.1, 0.5] {
        let stack = Stack {
            rotor: BodyProfile::spheroid(2.0, 2.0),
            stator: Some(BodyProfile::cylinder(10.0, 40.0, 0.0)),
            gap_m: gap * 1e-3,
        };
        let al = (1.0_f64 + gap).acosh();
        let exact: f64 = (1..200)
            .map(|n| (al.sinh() / (n as f64 * al).sinh()).powi(3))
            .sum();
        for r in [8.0, 16.0] {
            let t =
                at(&stack, &Confinement::Free, r).rotational_drag_n_m_s / (8.0 * PI * MU * 1e-9);
            println!(
                "Jeffery gap {gap} a, res {r}: {t:.5} vs {exact:.5} ({:+.3} %)",
                100.0 * (t / exact - 1.0)
            );
        }
    }
}
