//! The held-out catalogue of physical effects (docs/held-out.md): twelve
//! kinds of effect a lab with this robot may meet, none of them a kind the
//! development sets hold, drawn as truths on 32 designs and frozen before
//! the search is changed. The truths are fixture effects of this file
//! only; the search sees none of them.
//!
//! `MODE=freeze cargo run --release -p swimbot --example
//! discovery_held_out` draws every design, writes it to
//! `$OUT/<id>.toml` (`/tmp/held_out` unless given) and prints its row of
//! the frozen table (seed, kinds, truth, expected verdict, SHA-256 of the
//! written data). `MODE=check` draws them again and compares each hash
//! with the table in docs/held-out.md (exit 1 on a difference).
//! `MODE=measure` diagnoses each design once from the base
//! model and prints the scored table (`ONLY=H03,H10` those designs alone).
//!
//! Scored from the verdict alone, each stated member read at every place
//! the verdict states as its equivalent (`discovery::interpret::
//! equivalents`): **right** (strict) is a `located` or `identified`
//! verdict whose one set reads as exactly the true places, or
//! `none-needed` where the truth is unobservable; **stated with rivals**
//! an `indistinguishable` verdict with the truth in a stated set; **wrong
//! alone** a `located`/`identified` set with a member that reads as no
//! true place; **at the floor** the found set (or the base) at the floor.

#[path = "held_out/mod.rs"]
mod held_out;

use held_out::{
    expected, load_scale_mn, onset, rng, score, stability, stated, vary, Law, Tally, Truth,
};
use nalgebra::Matrix6;
use rand::{rngs::StdRng, Rng};
use std::f64::consts::PI;
use std::sync::Arc;
use std::time::Instant;
use swimbot::data::{Case, Dataset};
use swimbot::effects::EffectInstance;
use swimbot::model::Model;
use swimbot::physics::coefficients::LocalDrag;
use swimbot::physics::solve::ForceBalance;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings};
use swimbot::workbench::synth::{generate, SynthSettings};

/// The helix's outer radius over the wall gap, `R_h / (R_ch - R_h)`.
fn wall_ratio(c: &Case) -> f64 {
    let r_h = c.amplitude_mm + 0.5 * c.wire_diameter_mm;
    r_h / (0.5 * c.channel_diameter_mm - r_h)
}

/// One drawn truth: which kind, and its constants.
#[derive(Clone, Copy, Debug)]
enum Kind {
    /// K1 tail drag rising only once the helix nears the wall:
    /// `B_t[x,x] (1 + k max(0, w/w0 - 1)^p)`, w = R_h/gap.
    WallOnset { k: f64, w0: f64, p: f64 },
    /// K2 the tail's rotational drag rising near the wall:
    /// `B_t[omega,omega] (1 + a w^q)`.
    WallTorque { a: f64, q: f64 },
    /// K3/K4 the oil's viscosity set by its recorded temperature (Andrade):
    /// `mu(T) = mu exp(-b (T - 25 C))` on body and tail alike.
    Temperature { b: f64 },
    /// K5 the body's Oseen drag: `D_x (1 + 3/16 Re)`, Re = rho 2 pi f R_h D_b / mu.
    Oseen,
    /// K6 a motor at its current limit: the tail's rate
    /// `f (1 - k max(0, f/f_c - 1))`.
    CurrentLimit { k: f64, f_c: f64 },
    /// K7 a viscoelastic oil: thrust coupling `(1 + beta De^2)/(1 + De^2)`,
    /// De = lambda 2 pi f.
    Viscoelastic { lambda_s: f64, beta: f64 },
    /// K8 the coupler's seal as a Petroff journal: body rotation
    /// resistance `E_x (1 + a g0/g)`, g the coupler gap.
    SealGap { a: f64, g0: f64 },
    /// K9 the body shielding the tail: thrust `(1 - a D_b/L_t)`.
    BodyShield { a: f64 },
    /// K10 two robots of different trim: axial load `dW robot_id` (mN).
    RobotTrim { dw_mn: f64 },
    /// K11 Lighthill's slender-body normal coefficient:
    /// `c_n (ln(2 lambda/d)/ln(2 lambda0/d0))^e`.
    SlenderNormal { e: f64, l0: f64 },
    /// K12 the motor heating the oil at the body: body rotation
    /// resistance `E_x / (1 + a mu f^2 / (mu f^2)_0)`.
    MotorHeating { a: f64, s0: f64 },
    /// K13 a coupling that slips past a breakaway torque:
    /// `f (1 - k max(0, mu f L / (mu f L)_0 - 1))`.
    Breakaway { k: f64, t0: f64 },
}

impl Kind {
    fn place(self) -> Option<&'static str> {
        Some(match self {
            Kind::WallOnset { .. } => "tail.drag",
            Kind::WallTorque { .. } => "tail.torque",
            Kind::Temperature { .. } => "load.force",
            Kind::Oseen => "body.D_x",
            Kind::CurrentLimit { .. } | Kind::Breakaway { .. } => "drive.rate",
            Kind::Viscoelastic { .. } | Kind::BodyShield { .. } => "tail.thrust",
            Kind::SealGap { .. } | Kind::MotorHeating { .. } => "body.E_x",
            Kind::RobotTrim { .. } => "load.force",
            Kind::SlenderNormal { .. } => "tail.c_n",
        })
    }
}

impl Law for Kind {
    fn local_drag(&self, c: &Case, drag: &mut LocalDrag) {
        match *self {
            Kind::Temperature { b } => *drag = drag.scaled(temperature_factor(c, b)),
            Kind::SlenderNormal { e, l0 } => {
                let l = (2.0 * c.wavelength_mm / c.wire_diameter_mm).ln();
                drag.normal *= (l / l0).powf(e);
            }
            _ => {}
        }
    }
    fn tail(&self, c: &Case, t: &mut Matrix6<f64>) {
        match *self {
            Kind::WallOnset { k, w0, p } => t[(0, 0)] *= 1.0 + k * onset(wall_ratio(c), w0, p),
            Kind::WallTorque { a, q } => t[(3, 3)] *= 1.0 + a * wall_ratio(c).powf(q),
            Kind::Viscoelastic { lambda_s, beta } => {
                let de = lambda_s * c.tail_rate_rad_s();
                let s = (1.0 + beta * de * de) / (1.0 + de * de);
                t[(0, 3)] *= s;
                t[(3, 0)] *= s;
            }
            Kind::BodyShield { a } => {
                let s = 1.0 - a * c.body_diameter_mm / c.tail_length_mm;
                t[(0, 3)] *= s;
                t[(3, 0)] *= s;
            }
            _ => {}
        }
    }
    fn body(&self, c: &Case, b: &mut Matrix6<f64>) {
        match *self {
            Kind::Temperature { b: beta } => *b *= temperature_factor(c, beta),
            Kind::Oseen => {
                let r_h = c.amplitude_mm + 0.5 * c.wire_diameter_mm;
                let re = c.density_kg_m3
                    * 2.0
                    * PI
                    * c.frequency_hz
                    * r_h
                    * 1e-3
                    * c.body_diameter_mm
                    * 1e-3
                    / c.viscosity_pa_s;
                b[(0, 0)] *= 1.0 + 3.0 / 16.0 * re;
            }
            Kind::SealGap { a, g0 } => b[(3, 3)] *= 1.0 + a * g0 / c.coupler_gap_mm,
            Kind::MotorHeating { a, s0 } => {
                b[(3, 3)] /= 1.0 + a * c.viscosity_pa_s * c.frequency_hz.powi(2) / s0
            }
            _ => {}
        }
    }
    fn balance(&self, c: &Case, fb: &mut ForceBalance) {
        match *self {
            Kind::CurrentLimit { k, f_c } => {
                fb.tail_rate_rad_s *= 1.0 - k * onset(c.frequency_hz, f_c, 1.0)
            }
            Kind::Breakaway { k, t0 } => {
                let t = c.viscosity_pa_s * c.frequency_hz * c.tail_length_mm;
                fb.tail_rate_rad_s *= 1.0 - k * onset(t, t0, 1.0);
            }
            Kind::RobotTrim { dw_mn } => {
                fb.load[0] += dw_mn * c.recorded.value("robot_id").unwrap_or(0.0) * 1e-3
            }
            _ => {}
        }
    }
}

fn temperature_factor(c: &Case, b: f64) -> f64 {
    (-b * (c.recorded.value("temperature_c").unwrap_or(25.0) - 25.0)).exp()
}

/// Scales fixed from the paper's design (f median 1.2 Hz, mu 3.5 Pa s,
/// L_t about 75 mm): the onsets sit inside the drawn design's range.
/// The drawn design (the paper's six tails, six conditions each: channel
/// 28-50 mm, rate x0.8-1.6, tail length x0.9-1.3; 36 cases), with what a
/// kind needs varied or recorded.
fn design(seed: u64, kinds: &[Kind], trimmed: bool) -> Dataset {
    let paper = swimbot::data::paper();
    let mut r = rng(seed, 1);
    let mut out = paper.clone();
    out.name = format!("{} (held-out design, seed {seed})", paper.name);
    out.cases.clear();
    let load = load_scale_mn();
    for c in &paper.cases {
        for i in 0..6 {
            let mut v = vary(c, i, &mut r);
            for k in kinds {
                match k {
                    Kind::Temperature { .. } => {
                        v.recorded
                            .values
                            .push(("temperature_c".into(), r.gen_range(18.0..34.0)));
                    }
                    Kind::Oseen => {
                        v.viscosity_pa_s *= r.gen_range(0.002f64.ln()..0.2f64.ln()).exp()
                    }
                    Kind::SealGap { .. } => v.coupler_gap_mm = r.gen_range(0.3..2.0),
                    Kind::MotorHeating { .. } | Kind::Breakaway { .. } => {
                        v.viscosity_pa_s *= r.gen_range(0.5..1.5)
                    }
                    Kind::RobotTrim { .. } => {
                        v.recorded.values.push(("robot_id".into(), (i % 2) as f64))
                    }
                    _ => {}
                }
            }
            if trimmed {
                // a net weight of about one load scale (mN as grams-force)
                v.net_weight_g = load / 9.81;
            }
            v.recorded.values.sort_by(|a, b| a.0.cmp(&b.0));
            out.cases.push(v);
        }
    }
    out
}

fn draw_kind(k: usize, r: &mut StdRng, load: f64) -> Kind {
    match k {
        1 => Kind::WallOnset {
            k: r.gen_range(0.3..0.8),
            w0: r.gen_range(0.25..0.4),
            p: r.gen_range(1.0..2.0),
        },
        2 => Kind::WallTorque {
            a: r.gen_range(0.2..0.5),
            q: r.gen_range(1.0..2.0),
        },
        3 | 4 => Kind::Temperature {
            b: r.gen_range(0.015..0.025),
        },
        5 => Kind::Oseen,
        6 => Kind::CurrentLimit {
            k: r.gen_range(0.2..0.5),
            f_c: r.gen_range(1.1..1.4) * 1.2,
        },
        7 => Kind::Viscoelastic {
            lambda_s: r.gen_range(0.02..0.06),
            beta: r.gen_range(0.3..0.6),
        },
        8 => Kind::SealGap {
            a: r.gen_range(0.1..0.3),
            g0: 1.0,
        },
        9 => Kind::BodyShield {
            a: r.gen_range(0.15..0.35),
        },
        10 => Kind::RobotTrim {
            dw_mn: load * r.gen_range(0.5..1.5) * if r.gen_bool(0.5) { 1.0 } else { -1.0 },
        },
        11 => Kind::SlenderNormal {
            e: r.gen_range(0.5..1.0),
            l0: 3.0,
        },
        12 => Kind::MotorHeating {
            a: r.gen_range(0.2..0.5),
            s0: 5.0,
        },
        _ => Kind::Breakaway {
            k: r.gen_range(0.2..0.4),
            t0: 300.0 * r.gen_range(0.9..1.2),
        },
    }
}

/// The 32 frozen designs: (id, seed, kind numbers). K4 is K3 at neutral
/// trim, where a viscosity common to body and tail cancels.
const DESIGNS: [(&str, u64, &[usize]); 32] = [
    ("H01", 5101, &[1]),
    ("H02", 5102, &[2]),
    ("H03", 5103, &[3]),
    ("H04", 5104, &[4]),
    ("H05", 5105, &[5]),
    ("H06", 5106, &[6]),
    ("H07", 5107, &[7]),
    ("H08", 5108, &[8]),
    ("H09", 5109, &[9]),
    ("H10", 5110, &[10]),
    ("H11", 5111, &[11]),
    ("H12", 5112, &[12]),
    ("H13", 5113, &[13]),
    ("H14", 5114, &[1]),
    ("H15", 5115, &[2]),
    ("H16", 5116, &[3]),
    ("H17", 5117, &[5]),
    ("H18", 5118, &[6]),
    ("H19", 5119, &[7]),
    ("H20", 5120, &[8]),
    ("H21", 5121, &[10]),
    ("H22", 5122, &[11]),
    ("H23", 5123, &[12]),
    ("H24", 5124, &[13]),
    ("H25", 5125, &[1, 6]),
    ("H26", 5126, &[2, 10]),
    ("H27", 5127, &[5, 8]),
    ("H28", 5128, &[3, 9]),
    ("H29", 5129, &[7, 12]),
    ("H30", 5130, &[11, 13]),
    ("H31", 5131, &[1, 6, 8, 10]),
    ("H32", 5132, &[2, 5, 9, 13]),
];

struct Drawn {
    id: &'static str,
    seed: u64,
    kinds: Vec<Kind>,
    data: Dataset,
    want: Vec<&'static str>,
}

fn draw(id: &'static str, seed: u64, ks: &[usize]) -> Drawn {
    let load = load_scale_mn();
    let mut r = rng(seed, 2);
    let kinds: Vec<Kind> = ks.iter().map(|k| draw_kind(*k, &mut r, load)).collect();
    let trimmed = ks.contains(&3);
    let d = design(seed, &kinds, trimmed);
    let truth = kinds.iter().fold(Model::base(), |m, k| {
        m.with_effect(EffectInstance::default_of(Arc::new(Truth(*k))))
    });
    let settings = SynthSettings {
        seed,
        ..Default::default()
    };
    let data = generate(&truth, &d, settings).expect("the held-out truth predicts its design");
    let mut want: Vec<&'static str> = if ks == [4] {
        Vec::new()
    } else {
        kinds.iter().filter_map(|k| k.place()).collect()
    };
    want.sort();
    want.dedup();
    Drawn {
        id,
        seed,
        kinds,
        data,
        want,
    }
}

fn main() {
    let mode = std::env::var("MODE").unwrap_or_else(|_| "freeze".into());
    let out = std::env::var("OUT").unwrap_or_else(|_| "/tmp/held_out".into());
    std::fs::create_dir_all(&out).expect("the output folder");
    if mode == "freeze" {
        println!(
            "| design | seed | kinds | truth | expected verdict | SHA-256 of the drawn data |"
        );
        println!("|---|---|---|---|---|---|");
    } else if mode == "measure" {
        println!("| design | kinds | expected | verdict | stated sets | right | with rivals | wrong alone | floor | stability | s |");
        println!("|---|---|---|---|---|---|---|---|---|---|---|");
    }
    let frozen = if mode == "check" {
        held_out::frozen_hashes("held-out.md")
    } else {
        Vec::new()
    };
    // `ONLY=H03,H10` measures those designs alone (batch 1 is development
    // data now: docs/held-out-2.md).
    let only = std::env::var("ONLY").ok();
    let (mut tally, mut differ) = (Tally::default(), 0);
    for (id, seed, ks) in DESIGNS {
        if only
            .as_ref()
            .is_some_and(|o| !o.split(',').any(|x| x == id))
        {
            continue;
        }
        let d = draw(id, seed, ks);
        let kinds: Vec<String> = ks.iter().map(|k| format!("K{k}")).collect();
        let expected = expected(&d.want);
        if mode == "freeze" {
            let hex = held_out::freeze(&out, id, &d.data);
            println!(
                "| {} | {} | {} | {:?} | {} | `{}` |",
                d.id,
                d.seed,
                kinds.join(" + "),
                d.kinds,
                expected,
                hex
            );
            continue;
        }
        if mode == "check" {
            differ +=
                !held_out::same_hash(&frozen, id, &held_out::freeze(&out, id, &d.data)) as u32;
            continue;
        }
        let t = Instant::now();
        let g = diagnose(&Model::base(), &d.data, &DiagnoseSettings::default()).expect("diagnose");
        let secs = t.elapsed().as_secs_f64();
        let v = &g.verdict;
        let s = score(v, &d.want);
        tally.add(&s);
        println!(
            "| {id} | {} | {expected} | {} | {} | {} | {} | {} | {} | {} | {secs:.1} |",
            kinds.join(" + "),
            v.kind.name(),
            stated(&s),
            s.right,
            s.with_rivals,
            s.wrong_alone,
            s.at_floor,
            stability(v)
        );
    }
    match mode.as_str() {
        "freeze" => {}
        "check" if differ > 0 => {
            eprintln!("{differ} designs differ from docs/held-out.md");
            std::process::exit(1);
        }
        "check" => {}
        _ => println!("\n{}", tally.line()),
    }
}
