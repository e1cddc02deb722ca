//! Where one exact body solve spends its time (paper spheroid and profile in
//! the closed paper tube, default resolution), single- and multi-threaded:
//! `cargo run --release -p swimbot --example axisym_cost`.
use swimbot::nonlocal::axisym::{solve_body, AxisymSettings, Confinement};
use swimbot::physics::profile::BodyProfile;

fn main() {
    let tube = Confinement::Closed {
        diameter_m: 0.035,
        length_m: 0.35,
    };
    for p in [
        BodyProfile::spheroid(50.0, 20.0),
        BodyProfile::parse_sections("10:20,30:18,10:20", 0.0).unwrap(),
    ] {
        let mut best = (f64::INFINITY, 0.0);
        for _ in 0..10 {
            let s = solve_body(&p, &tube, 0.0, 3.5, &AxisymSettings::default()).unwrap();
            if s.seconds < best.0 {
                best = (s.seconds, s.flux_seconds);
            }
        }
        println!(
            "{}: best of 10: {:.1} ms, of which flux diagnostic {:.1} ms",
            p.describe(),
            1e3 * best.0,
            1e3 * best.1
        );
    }
}
