//! Recovery rate of the hidden-effect study over many seeds (the README's
//! table): for each catalogue effect, synthetic data from base + effect
//! (2 % noise, 5 trials, the varied design), diagnosed from the base model.
//! Run: `cargo run --release -p swimbot --example recovery -- 10`.
use swimbot::effects::parse_effect_spec;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings, VerdictKind};
use swimbot::workbench::synth::{generate, varied_design, SynthSettings};

const TRUTHS: &[(&str, Option<&str>)] = &[
    ("base", None),
    ("backflow", Some("backflow")),
    (
        "body-correction:translation=8,rotation=1.5",
        Some("body-correction"),
    ),
    ("body-confinement", Some("body-confinement")),
    ("tail-confinement:gamma=1", Some("tail-confinement")),
    ("wall-contact:thrust=0.5", Some("wall-contact")),
    ("motor-frame", Some("motor-frame")),
    ("buoyancy:net_force_mn=0.3", Some("buoyancy")),
    ("coupler", Some("coupler")),
    ("nonlocal-tail", Some("nonlocal-tail")),
];

fn main() {
    let seeds: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10);
    let design = varied_design(&swimbot::data::paper());
    println!("| truth | recovered | verdicts |\n|---|---|---|");
    let mut total = (0, 0);
    for (truth, expected) in TRUTHS {
        let mut model = Model::base();
        if *truth != "base" {
            model
                .effects
                .push(parse_effect_spec(truth).expect("valid truth"));
        }
        let mut hits = 0;
        let mut other = Vec::new();
        for seed in 1..=seeds {
            let data = generate(
                &model,
                &design,
                SynthSettings {
                    seed: 1000 + seed,
                    ..Default::default()
                },
            )
            .expect("synth");
            let d =
                diagnose(&Model::base(), &data, &DiagnoseSettings::default()).expect("diagnose");
            let ok = match expected {
                Some(name) => d.verdict.effect.as_deref() == Some(*name),
                None => d.verdict.kind == VerdictKind::NoneNeeded,
            };
            if ok {
                hits += 1;
            } else {
                other.push(format!(
                    "{:?}",
                    d.verdict
                        .effect
                        .unwrap_or_else(|| format!("{:?}", d.verdict.kind))
                ));
            }
        }
        total = (total.0 + hits, total.1 + seeds);
        println!(
            "| `{truth}` | {hits}/{seeds} | {} |",
            if other.is_empty() {
                "all correct".to_string()
            } else {
                other.join(", ")
            }
        );
    }
    println!("\noverall: {}/{}", total.0, total.1);
}
