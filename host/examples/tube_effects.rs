//! The wall-resolved confinement effects (`tail-confinement-stokeslets`,
//! `body-confinement-exact`) on the paper data, and the resolution
//! study behind their settings. Release build:
//!
//! `cargo run --release -p swimbot --example tube_effects` compares the base
//! model plus both effects with the paper data twice, each in a fresh
//! process sharing a new, empty disk cache: the first run is cold (every
//! solve), the second warm (every matrix read from disk);
//! `... --example tube_effects -- resolution` measures cost and wall
//! convergence (wall spacings 2.5-5 mm) on tail #6 and on the body, and the
//! cost of all six tails at the chosen spacing.
use std::process::Command;
use std::time::Instant;
use swimbot::data::paper;
use swimbot::effects::parse_effect_spec;
use swimbot::model::Model;
use swimbot::nonlocal::{
    body_resistance, tail_resistance, tail_resistance_in_channel, NonlocalSettings,
};
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
            k.u_pred_mm_s,
            k.u_obs_mm_s.unwrap_or(f64::NAN),
            100.0 * k.u_rel_err.unwrap_or(f64::NAN),
            k.omega_pred_hz,
            k.omega_obs_hz.unwrap_or(f64::NAN),
            100.0 * k.omega_rel_err.unwrap_or(f64::NAN),
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
    let settings = |wall_mm: f64| NonlocalSettings {
        wall_spacing_m: wall_mm * 1e-3,
        ..NonlocalSettings::default()
    };
    let spacings = [2.5, 3.0, 4.0, 5.0];
    let case6 = &data.cases[5];
    let (h, ch, mu) = (case6.helix(), case6.channel(), case6.viscosity_pa_s);
    let free = tail_resistance(&h, mu, &settings(3.0)).unwrap();
    println!("tail #6 in tube / free, by wall spacing:");
    for w in spacings {
        let t0 = Instant::now();
        let m = tail_resistance_in_channel(&h, &ch, mu, &settings(w)).unwrap();
        println!(
            "  wall {w} mm: xx {:.4} x,wx {:.4} wx,wx {:.4}  ({:.1} s)",
            m[(0, 0)] / free[(0, 0)],
            m[(0, 3)] / free[(0, 3)],
            m[(3, 3)] / free[(3, 3)],
            t0.elapsed().as_secs_f64()
        );
    }
    let body = case6.body();
    let free_b = body_resistance(&body, None, mu, &settings(3.0)).unwrap();
    println!(
        "body free: xx {:.4e} wx,wx {:.4e}; in tube, by wall spacing:",
        free_b[(0, 0)],
        free_b[(3, 3)]
    );
    for w in spacings {
        let t0 = Instant::now();
        let m = body_resistance(&body, Some(&ch), mu, &settings(w)).unwrap();
        println!(
            "  wall {w} mm: xx {:.4e} ({:.3}x free) wx,wx {:.4e} ({:.3}x free)  ({:.1} s)",
            m[(0, 0)],
            m[(0, 0)] / free_b[(0, 0)],
            m[(3, 3)],
            m[(3, 3)] / free_b[(3, 3)],
            t0.elapsed().as_secs_f64()
        );
    }
    let w: f64 = std::env::args()
        .nth(2)
        .and_then(|a| a.parse().ok())
        .unwrap_or(4.0);
    let t_all = Instant::now();
    for c in &data.cases {
        let t0 = Instant::now();
        let m = tail_resistance_in_channel(&c.helix(), &ch, mu, &settings(w)).unwrap();
        let f = tail_resistance(&c.helix(), mu, &settings(w)).unwrap();
        println!(
            "  {} at wall {w} mm: xx {:.4} x,wx {:.4} wx,wx {:.4} x free ({:.1} s)",
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
