//! The wall-resolved confinement effects (`tail-confinement-stokeslets`,
//! `body-confinement-exact`) on the paper data, and the resolution
//! study behind their settings. Release build:
//!
//! `cargo run --release -p swimbot --example tube_effects` compares the base
//! model plus both effects with the paper data twice, each in a fresh
//! process sharing a new, empty disk cache: the first run is cold (every
//! solve), the second warm (every matrix read from disk);
//! `... --example tube_effects -- resolution` measures cost and wall
//! convergence on tail #6 (MFS wall spacings 2.5-5 mm) and on the body
//! (axisymmetric resolution 4-16 elements per gap), and the cost of all six
//! tails at the chosen spacing.
use std::process::Command;
use std::time::Instant;
use swimbot::data::paper;
use swimbot::effects::parse_effect_spec;
use swimbot::model::Model;
use swimbot::nonlocal::axisym::{solve_body, AxisymSettings, Confinement};
use swimbot::nonlocal::tube::{tail_resistance_in_tube, TubeSettings};
use swimbot::nonlocal::{tail_resistance, NonlocalSettings};
use swimbot::physics::profile::BodyProfile;
use swimbot::workbench::compare::compare;

const EFFECTS: [&str; 2] = ["body-confinement-exact", "tail-confinement-stokeslets"];

fn compare_once() {
    let mut model = Model::base();
    for e in EFFECTS {
        model = model.with_effect(parse_effect_spec(e).unwrap());
    }
    let data = paper();
    let t0 = Instant::now();
    let c = compare(&model, &data, 0).unwrap();
    println!("model: {}", c.model);
    println!("case     U pred  U obs   U err    Ω pred   Ω obs    Ω err");
    for k in &c.cases {
        println!(
            "{:<8} {:6.3} {:6.3} {:+7.1} % {:7.4} {:7.4} {:+7.1} %",
            k.id,
            k.u().pred,
            k.u().obs.unwrap_or(f64::NAN),
            100.0 * k.u().rel_err.unwrap_or(f64::NAN),
            k.omega().pred,
            k.omega().obs.unwrap_or(f64::NAN),
            100.0 * k.omega().rel_err.unwrap_or(f64::NAN),
        );
    }
    let base = compare(&Model::base(), &data, 0).unwrap();
    println!(
        "MARE {:.1} % (base model {:.1} %), max |rel err| {:.1} %; in-process time {:.1} s",
        100.0 * c.summary.mare,
        100.0 * base.summary.mare,
        100.0 * c.summary.max_abs_rel_err,
        t0.elapsed().as_secs_f64()
    );
}

fn resolution() {
    let data = paper();
    let tube = |wall_mm: f64| TubeSettings {
        wall_spacing_m: wall_mm * 1e-3,
        ..TubeSettings::default()
    };
    let spacings = [2.5, 3.0, 4.0, 5.0];
    let case6 = &data.cases[5];
    let (h, ch, mu) = (case6.helix(), case6.channel(), case6.viscosity_pa_s);
    let free = tail_resistance(&h, mu, &NonlocalSettings::default()).unwrap();
    println!("tail #6 in tube (MFS wall) / free, by wall spacing:");
    for w in spacings {
        let t0 = Instant::now();
        let r = tail_resistance_in_tube(&h, &ch, mu, &tube(w)).unwrap();
        let m = r.matrix;
        println!(
            "  wall {w} mm: xx {:.4} x,wx {:.4} wx,wx {:.4}, flux {:.1e}  ({:.2} s)",
            m[(0, 0)] / free[(0, 0)],
            m[(0, 3)] / free[(0, 3)],
            m[(3, 3)] / free[(3, 3)],
            r.diagnostics.max_flux(),
            t0.elapsed().as_secs_f64()
        );
    }
    let body = case6.body();
    let profile = BodyProfile::spheroid(body.length_m * 1e3, body.diameter_m * 1e3);
    let confined = Confinement::of_channel(&ch);
    let free_b = solve_body(
        &profile,
        &Confinement::Free,
        0.0,
        mu,
        &AxisymSettings::default(),
    )
    .unwrap();
    println!(
        "body free: xx {:.4e} wx,wx {:.4e}; in the tube (axisymmetric, exact), by resolution:",
        free_b.drag_n_s_per_m, free_b.rotational_drag_n_m_s
    );
    for resolution in [4.0, 8.0, 16.0] {
        let s = AxisymSettings {
            resolution,
            ..AxisymSettings::default()
        };
        let m = solve_body(&profile, &confined, 0.0, mu, &s).unwrap();
        println!(
            "  {resolution} per gap: xx {:.4e} ({:.3}x free) wx,wx {:.4e} ({:.3}x free), flux {:.1e} ({:.3} s)",
            m.drag_n_s_per_m,
            m.drag_n_s_per_m / free_b.drag_n_s_per_m,
            m.rotational_drag_n_m_s,
            m.rotational_drag_n_m_s / free_b.rotational_drag_n_m_s,
            m.flux_error().unwrap_or(f64::NAN),
            m.seconds
        );
    }
    let w: f64 = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(3.0);
    let t_all = Instant::now();
    for c in &data.cases {
        let t0 = Instant::now();
        let r = tail_resistance_in_tube(&c.helix(), &ch, mu, &tube(w)).unwrap();
        let (m, f) = (
            r.matrix,
            tail_resistance(&c.helix(), mu, &NonlocalSettings::default()).unwrap(),
        );
        println!(
            "  {} at wall {w} mm: xx {:.4} x,wx {:.4} wx,wx {:.4} x free ({:.2} s)",
            c.id,
            m[(0, 0)] / f[(0, 0)],
            m[(0, 3)] / f[(0, 3)],
            m[(3, 3)] / f[(3, 3)],
            t0.elapsed().as_secs_f64()
        );
    }
    println!(
        "six tails at wall {w} mm: {:.1} s",
        t_all.elapsed().as_secs_f64()
    );
}

fn main() {
    match std::env::args().nth(1).as_deref() {
        Some("resolution") => resolution(),
        Some("compare-once") => compare_once(),
        _ => {
            let dir =
                std::env::temp_dir().join(format!("swimbot-cache-example-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            for run in ["cold", "warm"] {
                let t0 = Instant::now();
                let status = Command::new(std::env::current_exe().unwrap())
                    .arg("compare-once")
                    .env(swimbot::nonlocal::cache::CACHE_DIR_ENV, &dir)
                    .status()
                    .unwrap();
                assert!(status.success());
                println!(
                    "{run} run (new process): {:.3} s wall time\n",
                    t0.elapsed().as_secs_f64()
                );
            }
            let _ = std::fs::remove_dir_all(&dir);
        }
    }
}
