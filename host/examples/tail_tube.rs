//! Studies of the leak-free tube solver (`swimbot::nonlocal::tube`), release
//! build: `cargo run --release -p swimbot --example tail_tube -- <study>`.
//!
//! - `wall [tail] [turns]`: convergence in the wall spacing (MFS and the old
//!   leaky wall, with their leak diagnostics), paper tail `tail` (1-6) cut
//!   to `turns` turns (0 = whole tail), closed 35 mm tube;
//! - `offset`, `margin`: convergence in the source offset and cap distance;
//! - `paper`: the six paper tails, closed 35 mm tube, against free space and
//!   the old leaky wall, with timings;
//! - `robot [tail]`: body-tail interaction in the tube, change of U and
//!   Omega_b (all six tails, or one);
//! - `layout`: the six paper tails with the default cap rings against the
//!   graded caps of the earlier wall (the same discretisation the dense
//!   solver used), and the ring solver against the dense one on a short
//!   tail, with timings.
//!
//! Each study asserts its own convergence claims (panics if they fail).
use std::time::Instant;
use swimbot::data::{paper, Case};
use swimbot::nonlocal::tube::{
    robot_resistance_in_tube, tail_resistance_in_tube, CapLayout, TubeSettings, WallModel,
    WallSolver,
};
use swimbot::nonlocal::{tail_resistance, NonlocalSettings};
use swimbot::physics::geometry::Helix;

fn case(tail: usize, turns: f64) -> Case {
    let mut c = paper().cases[tail - 1].clone();
    if turns > 0.0 {
        c.tail_length_mm = turns * c.wavelength_mm;
    }
    c
}

fn axial(m: &nalgebra::Matrix6<f64>) -> [f64; 3] {
    [m[(0, 0)], m[(0, 3)], m[(3, 3)]]
}

fn run(c: &Case, s: &TubeSettings) -> ([f64; 3], f64, f64, f64, usize) {
    let t0 = Instant::now();
    let r = tail_resistance_in_tube(&c.helix(), &c.channel(), c.viscosity_pa_s, s).unwrap();
    let d = &r.diagnostics;
    eprintln!(
        "  worst slip at x = {:.1} mm, r = {:.1} mm; wall x {:?}",
        d.wall_slip_at_x_r_m[0] * 1e3,
        d.wall_slip_at_x_r_m[1] * 1e3,
        d.sections_x_m
    );
    (
        axial(&r.matrix),
        d.max_flux(),
        d.max_slip(),
        t0.elapsed().as_secs_f64(),
        d.n_points,
    )
}

fn free(c: &Case) -> [f64; 3] {
    axial(&tail_resistance(&c.helix(), c.viscosity_pa_s, &NonlocalSettings::default()).unwrap())
}

fn row(label: &str, a: [f64; 3], f: [f64; 3], flux: f64, slip: f64, t: f64, n: usize) {
    println!(
        "{label:<22} {:>7.4} {:>7.4} {:>7.4}   {:>8.2e} {:>8.2e}  {:>6} {:>7.2} s",
        a[0] / f[0],
        a[1] / f[1],
        a[2] / f[2],
        flux,
        slip,
        3 * n,
        t
    );
}

fn header() {
    println!(
        "{:<22} {:>7} {:>7} {:>7}   {:>8} {:>8}  {:>6} {:>9}",
        "setting", "Bxx", "Bx,wx", "Bwx,wx", "max|Q|", "slip", "3N", "time"
    );
    println!("(entries over free space; Q over the piston flux; slip = wall speed between points / U or Omega r)");
}

fn wall_study(tail: usize, turns: f64) {
    let c = case(tail, turns);
    let f = free(&c);
    println!("tail #{tail}, {turns} turns (0 = whole), closed 35 mm tube");
    header();
    let mut mfs = vec![];
    for h_mm in [6.0, 4.5, 3.5, 3.0, 2.5] {
        let s = TubeSettings {
            wall_spacing_m: h_mm * 1e-3,
            ..TubeSettings::default()
        };
        let (a, q, sl, t, n) = run(&c, &s);
        row(&format!("MFS h = {h_mm} mm"), a, f, q, sl, t, n);
        mfs.push((a, q));
    }
    let mut leaky_flux = f64::INFINITY;
    for h_mm in [4.0, 3.0] {
        let s = TubeSettings {
            wall: WallModel::Leaky,
            wall_spacing_m: h_mm * 1e-3,
            cap_margin_over_radius: 2.0,
            ..TubeSettings::default()
        };
        let (a, q, sl, t, n) = run(&c, &s);
        row(&format!("leaky h = {h_mm} mm"), a, f, q, sl, t, n);
        leaky_flux = leaky_flux.min(q);
    }
    // the claims of the notes: 3 mm within 1 % of 2.5 mm, and 5x less leak
    let (a3, a25) = (mfs[3].0, mfs[4].0);
    for k in 0..3 {
        assert!(
            (a3[k] / a25[k] - 1.0).abs() < 0.01,
            "entry {k}: {a3:?} vs {a25:?}"
        );
    }
    assert!(mfs[4].1 < 0.2 * leaky_flux, "{} vs {leaky_flux}", mfs[4].1);
}

fn offset_study(tail: usize, turns: f64) {
    let c = case(tail, turns);
    let f = free(&c);
    println!("tail #{tail}, {turns} turns, closed 35 mm tube, default h");
    header();
    for off in [1.0, 1.5, 2.0] {
        let s = TubeSettings {
            source_offset_over_spacing: off,
            ..TubeSettings::default()
        };
        let (a, q, sl, t, n) = run(&c, &s);
        row(&format!("offset {off} h"), a, f, q, sl, t, n);
    }
}

fn margin_study(tail: usize, turns: f64) {
    let c = case(tail, turns);
    let f = free(&c);
    println!("tail #{tail}, {turns} turns, closed 35 mm tube, default h");
    header();
    for m in [1.0, 1.5, 2.0] {
        let s = TubeSettings {
            cap_margin_over_radius: m,
            ..TubeSettings::default()
        };
        let (a, q, sl, t, n) = run(&c, &s);
        row(&format!("caps {m} R beyond"), a, f, q, sl, t, n);
    }
}

fn paper_study() {
    println!("six paper tails, closed 35 mm tube: in tube / free space (MFS default; old leaky wall 4 mm)");
    header();
    for tail in 1..=6 {
        let c = case(tail, 0.0);
        let f = free(&c);
        let (a, q, sl, t, n) = run(&c, &TubeSettings::default());
        row(&format!("#{tail} MFS"), a, f, q, sl, t, n);
        let leaky = TubeSettings {
            wall: WallModel::Leaky,
            wall_spacing_m: 4e-3,
            cap_margin_over_radius: 2.0,
            ..TubeSettings::default()
        };
        let (al, ql, sl, t, n) = run(&c, &leaky);
        row(&format!("#{tail} leaky 4 mm"), al, f, ql, sl, t, n);
        assert!(q < 0.3 * ql, "#{tail}: MFS flux {q} vs old wall {ql}");
        assert!(a[0] > al[0] && (a[2] / al[2] - 1.0).abs() < 0.02);
        println!(
            "#{tail} free: Bxx {:.5e} N s/m, Bx,wx {:.5e} N s, Bwx,wx {:.5e} N m s",
            f[0], f[1], f[2]
        );
    }
}

/// Swimming speed and body rate of the robot from a 12x12 grand matrix,
/// axial motions only (the paper's model restricted to x): the body moves
/// at `(U, Omega_b)`, the tail at `(U, Omega_b + omega)`, zero net force
/// and zero net torque.
fn swim(g: &nalgebra::SMatrix<f64, 12, 12>, omega: f64) -> (f64, f64) {
    // unknowns U, Ob; tail rate omega relative to body
    let idx = |obj: usize, k: usize| 6 * obj + k;
    let mut a = nalgebra::Matrix2::zeros();
    let mut b = nalgebra::Vector2::zeros();
    for (row, k) in [(0, 0), (1, 3)] {
        // net load component k = -sum_p sum_q G[p k, q m] V_q m
        for p in 0..2 {
            a[(row, 0)] += g[(idx(p, k), idx(0, 0))] + g[(idx(p, k), idx(1, 0))];
            a[(row, 1)] += g[(idx(p, k), idx(0, 3))] + g[(idx(p, k), idx(1, 3))];
            b[row] -= g[(idx(p, k), idx(1, 3))] * omega;
        }
    }
    let x = a.lu().solve(&b).unwrap();
    (x[0], x[1])
}

fn robot_study(only: Option<usize>) {
    println!("body-tail interaction in the closed 35 mm tube (MFS, axial motions, zero net force and torque)");
    println!("case  U coupled   U uncoupled   dU      Ob coupled  Ob uncoupled  dOb   3N   time");
    for tail in (1..=6).filter(|t| only.is_none_or(|o| o == *t)) {
        let c = case(tail, 0.0);
        let helix: Helix = c.helix();
        let t0 = Instant::now();
        let s = TubeSettings {
            tail: NonlocalSettings {
                body_spacing_m: 2.0e-3,
                ..NonlocalSettings::default()
            },
            ..TubeSettings::default()
        };
        let (r, d) =
            robot_resistance_in_tube(&c.body(), &helix, &c.channel(), c.viscosity_pa_s, &s)
                .unwrap();
        let g = r.grand();
        let mut g0 = g;
        for i in 0..6 {
            for j in 0..6 {
                g0[(i, 6 + j)] = 0.0;
                g0[(6 + i, j)] = 0.0;
            }
        }
        let omega = -c.tail_rate_rad_s();
        let (u1, o1) = swim(&g, omega);
        let (u0, o0) = swim(&g0, omega);
        println!(
            "#{tail}  {:9.4} {:12.4} {:+7.1} %  {:9.4} {:12.4} {:+6.1} %  {} {:.1} s",
            u1 * 1e3,
            u0 * 1e3,
            100.0 * (u1 / u0 - 1.0),
            o1 / (2.0 * std::f64::consts::PI),
            o0 / (2.0 * std::f64::consts::PI),
            100.0 * (o1 / o0 - 1.0),
            3 * d.n_points,
            t0.elapsed().as_secs_f64()
        );
    }
}

fn layout_study() {
    println!("six paper tails, closed 35 mm tube, default wall: cap rings / graded caps - 1");
    println!("tail  Bxx        Bx,wx      Bwx,wx     max|6x6|   flux(rings) flux(graded)  t rings  t graded");
    let mut worst: f64 = 0.0;
    for tail in 1..=6 {
        let c = case(tail, 0.0);
        let solve = |caps| {
            let s = TubeSettings {
                caps,
                ..TubeSettings::default()
            };
            let t0 = Instant::now();
            let r =
                tail_resistance_in_tube(&c.helix(), &c.channel(), c.viscosity_pa_s, &s).unwrap();
            (r, t0.elapsed().as_secs_f64())
        };
        let (a, ta) = solve(CapLayout::Rings);
        let (b, tb) = solve(CapLayout::Graded);
        let (x, y) = (axial(&a.matrix), axial(&b.matrix));
        let d: Vec<f64> = (0..3).map(|k| x[k] / y[k] - 1.0).collect();
        let all = (a.matrix - b.matrix).abs().max() / b.matrix.abs().max();
        worst = d.iter().fold(worst, |m, v| m.max(v.abs()));
        println!(
            "#{tail}   {:+.2e}  {:+.2e}  {:+.2e}  {:.2e}   {:.2e}    {:.2e}     {:.2} s   {:.2} s  (solve {:.2} s, diagnostics {:.2} s, {} points)",
            d[0],
            d[1],
            d[2],
            all,
            a.diagnostics.max_flux(),
            b.diagnostics.max_flux(),
            ta,
            tb,
            a.diagnostics.solve_seconds,
            a.diagnostics.diagnostics_seconds,
            a.diagnostics.n_points
        );
    }
    assert!(worst < 1e-3, "cap layouts differ by {worst}");
    let c = case(6, 2.0);
    let s = TubeSettings {
        wall_spacing_m: 4.5e-3,
        ..TubeSettings::default()
    };
    for solver in [WallSolver::Rings, WallSolver::Dense] {
        let t0 = Instant::now();
        let r = tail_resistance_in_tube(
            &c.helix(),
            &c.channel(),
            c.viscosity_pa_s,
            &TubeSettings { solver, ..s },
        )
        .unwrap();
        println!(
            "tail #6, two turns, 4.5 mm wall, {solver:?}: Bxx {:.9e}, {:.2} s, {} points",
            r.matrix[(0, 0)],
            t0.elapsed().as_secs_f64(),
            r.diagnostics.n_points
        );
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let tail = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(6);
    let turns = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(2.0);
    match args.first().map(String::as_str) {
        Some("wall") => wall_study(tail, turns),
        Some("offset") => offset_study(tail, turns),
        Some("margin") => margin_study(tail, turns),
        Some("paper") => paper_study(),
        Some("layout") => layout_study(),
        Some("robot") => robot_study(args.get(1).and_then(|s| s.parse().ok())),
        _ => {
            eprintln!("usage: tail_tube wall|offset|margin [tail] [turns] | paper | robot | layout")
        }
    }
}
