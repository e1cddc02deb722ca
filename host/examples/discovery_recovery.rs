//! Recovery table for discovery beyond the catalogue: synthetic data (2 %
//! noise per trial, five trials, `synth::rich_design`) from out-of-catalogue
//! truths (host/tests/fixtures/truths.rs), one catalogue effect combined
//! with one, and a null control, each over ten seeds (101..=110: different
//! from the tests' seeds), diagnosed from the base model. Three categories
//! drawn for the stagewise search and the robust guard, on forms and
//! designs not used while building them: two out-of-catalogue truths at
//! once (body and tail), a setup-field dependence (tail viscosity x
//! (mu/0.1)^-0.25 on a design with three oils), and a null with one case's
//! U moved by 6 standard errors (the case `seed mod cases`).
//!
//! `cargo run --release -p swimbot --example discovery_recovery [seeds]`
//!
//! Prints, per truth, how often the verdict kind, place and feature are
//! right, the median explained fraction and the median time per diagnosis;
//! the verdict kinds go to stderr. `ONLY=<text>` runs the truths whose
//! label contains it.

#[path = "../tests/fixtures/truths.rs"]
mod truths;

use std::time::Instant;
use swimbot::data::Dataset;
use swimbot::effects::parse_effect_spec;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, VerdictKind};
use swimbot::workbench::synth::{generate, rich_design, SynthSettings};

struct Truth {
    label: &'static str,
    model: Model,
    kind: VerdictKind,
    place: Option<&'static str>,
    features: &'static [&'static str],
    effect: Option<&'static str>,
    /// A second place that must be located too, with its features.
    second: Option<(&'static str, &'static [&'static str])>,
    /// The design (default: the rich design).
    design: Option<Dataset>,
    /// Move one case's U by 6 standard errors.
    spoil: bool,
}

fn main() {
    let n_seeds: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10);
    let design = rich_design(&swimbot::data::paper());
    let base = Model::base();
    let truths = vec![
        Truth {
            label: "c_n x (1 + 5 ((D_t/2)/gap)^1.3)",
            model: base.clone().with_effect(truths::instance(&truths::WALL)),
            kind: VerdictKind::Located,
            place: Some("tail.c_n"),
            features: &["wire_over_gap", "tail_clearance", "tail_gap_ratio"],
            effect: None,
            second: None,
            design: None,
            spoil: false,
        },
        Truth {
            label: "mu_tail x (1 + shear/20)^-0.3",
            model: base.clone().with_effect(truths::instance(&truths::SHEAR)),
            kind: VerdictKind::Located,
            place: Some("tail.viscosity"),
            features: &["shear_rate"],
            effect: None,
            second: None,
            design: None,
            spoil: false,
        },
        Truth {
            label: "omega x 0.85 (drive slip)",
            model: base.clone().with_effect(truths::instance(&truths::SLIP)),
            kind: VerdictKind::Located,
            place: Some("drive.rate"),
            features: &[],
            effect: None,
            second: None,
            design: None,
            spoil: false,
        },
        Truth {
            label: "D_x x (1 + 3 (D_b/D_ch)^4)",
            model: base.clone().with_effect(truths::instance(&truths::BODY)),
            kind: VerdictKind::Located,
            place: Some("body.D_x"),
            features: &["body_ratio", "body_gap_ratio", "body_over_gap"],
            effect: None,
            second: None,
            design: None,
            spoil: false,
        },
        Truth {
            label: "body-confinement + drive slip",
            model: base
                .clone()
                .with_effect(parse_effect_spec("body-confinement").unwrap())
                .with_effect(truths::instance(&truths::SLIP)),
            kind: VerdictKind::Identified,
            place: Some("drive.rate"),
            features: &[],
            effect: Some("body-confinement"),
            second: None,
            design: None,
            spoil: false,
        },
        Truth {
            label: "null (base only)",
            model: base.clone(),
            kind: VerdictKind::NoneNeeded,
            place: None,
            features: &[],
            effect: None,
            second: None,
            design: None,
            spoil: false,
        },
        Truth {
            label: "D_x x (1 + 3 (D_b/D_ch)^4) and mu_tail x (1 + shear/20)^-0.3 at once",
            model: base
                .clone()
                .with_effect(truths::instance(&truths::BODY))
                .with_effect(truths::instance(&truths::SHEAR)),
            kind: VerdictKind::Located,
            place: Some("body.D_x"),
            features: &["body_ratio", "body_gap_ratio", "body_over_gap"],
            effect: None,
            second: Some(("tail.viscosity", &["shear_rate"])),
            design: None,
            spoil: false,
        },
        Truth {
            label: "mu_tail x (mu/0.1)^-0.25, three oils",
            model: base.clone().with_effect(truths::instance(&truths::OIL)),
            kind: VerdictKind::Located,
            place: Some("tail.viscosity"),
            features: &["viscosity_pa_s"],
            effect: None,
            second: None,
            design: Some(truths::oil_design(&swimbot::data::paper())),
            spoil: false,
        },
        Truth {
            label: "null, one case's U off by 6 standard errors",
            model: base.clone(),
            kind: VerdictKind::NoneNeeded,
            place: None,
            features: &[],
            effect: None,
            second: None,
            design: None,
            spoil: true,
        },
    ];
    println!("| truth | kind right | place right | feature right | catalogue effect right | median explained fraction | median time per diagnosis |");
    println!("|---|---|---|---|---|---|---|");
    let only = std::env::var("ONLY").ok();
    for t in &truths {
        if only.as_deref().is_some_and(|o| !t.label.contains(o)) {
            continue;
        }
        let mut kinds = std::collections::BTreeMap::<String, u32>::new();
        let (mut kind_ok, mut place_ok, mut feat_ok, mut eff_ok) = (0, 0, 0, 0);
        let mut fractions = Vec::new();
        let mut times = Vec::new();
        let mut named = 0;
        for seed in 101..101 + n_seeds {
            let mut data = generate(
                &t.model,
                t.design.as_ref().unwrap_or(&design),
                SynthSettings {
                    seed,
                    ..Default::default()
                },
            )
            .expect("synth");
            let n_cases = data.cases.len();
            let spoiled = t
                .spoil
                .then(|| truths::spoil_one(&mut data, seed as usize % n_cases, 6.0));
            let t0 = Instant::now();
            let d = diagnose(&base, &data, &DiagnoseSettings::default()).expect("diagnose");
            times.push(t0.elapsed().as_secs_f64());
            let v = &d.verdict;
            kind_ok += (v.kind == t.kind) as u32;
            *kinds.entry(format!("{:?}", v.kind)).or_default() += 1;
            eff_ok += (v.effect.as_deref() == t.effect) as u32;
            let first = v.located.first();
            let place_right = first.map(|l| l.place) == t.place;
            let feat_right = match (first, t.place) {
                (Some(l), Some(_)) => match l.feature {
                    None => t.features.is_empty(),
                    Some(f) => t.features.contains(&f),
                },
                (None, None) => true,
                _ => false,
            };
            let second_right = t.second.is_none_or(|(place, feats)| {
                v.located.iter().any(|l| {
                    l.place == place
                        && match l.feature {
                            None => feats.is_empty(),
                            Some(f) => feats.contains(&f),
                        }
                })
            });
            let in_set = |p: &str| v.located.iter().any(|l| l.place == p);
            let place_right = match t.second {
                Some((p2, _)) => t.place.is_some_and(in_set) && in_set(p2),
                None => place_right,
            };
            let feat_right = match t.second {
                Some(_) => {
                    let first_ok = v.located.iter().any(|l| {
                        Some(l.place) == t.place
                            && l.feature.is_some_and(|f| t.features.contains(&f))
                    });
                    first_ok && second_right
                }
                None => feat_right,
            };
            place_ok += place_right as u32;
            feat_ok += feat_right as u32;
            if let Some(id) = &spoiled {
                named += d.lone_case.as_ref().is_some_and(|l| &l.case == id) as u32;
            }
            if let Some(l) = first {
                fractions.push(l.explained_fraction.unwrap_or(f64::NAN));
            }
            if std::env::var("VERBOSE").is_ok() {
                eprintln!("{} seed {seed}: {}", t.label, v.note);
            }
        }
        let med = |v: &mut Vec<f64>| {
            if v.is_empty() {
                return f64::NAN;
            }
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        println!(
            "| {} | {kind_ok}/{n_seeds} | {place_ok}/{n_seeds} | {feat_ok}/{n_seeds} | {eff_ok}/{n_seeds} | {:.3} | {:.2} s |",
            t.label,
            med(&mut fractions),
            med(&mut times)
        );
        eprintln!("{}: verdict kinds {kinds:?}", t.label);
        if t.spoil {
            eprintln!(
                "{}: the spoiled case named as standing out {named}/{n_seeds}",
                t.label
            );
        }
    }
}
