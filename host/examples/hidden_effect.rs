//! The hidden-effect study: synthetic data from the base model plus one
//! catalogue effect, diagnosed from the base model.
use swimbot::effects::parse_effect_spec;
use swimbot::model::Model;
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings};
use swimbot::workbench::synth::{generate, varied_design, SynthSettings};

fn main() {
    let design = varied_design(&swimbot::data::paper());
    let truths = std::env::args().skip(1).collect::<Vec<_>>();
    for truth in truths {
        for seed in 1..=3 {
            let mut m = Model::base();
            for t in truth
                .split('+')
                .filter(|s| !s.trim().is_empty() && s.trim() != "base")
            {
                m.effects.push(parse_effect_spec(t.trim()).unwrap());
            }
            let data = generate(
                &m,
                &design,
                SynthSettings {
                    seed,
                    ..Default::default()
                },
            )
            .unwrap();
            let t0 = std::time::Instant::now();
            let d = diagnose(&Model::base(), &data, &DiagnoseSettings::default()).unwrap();
            println!(
                "truth {truth} seed {seed}: {:?} [{:.2}s]\n  {}",
                d.verdict.effect,
                t0.elapsed().as_secs_f64(),
                d.verdict.note
            );
            for c in d.ranking.iter().take(3) {
                println!(
                    "    {:<18} aicc {:>10.1} chi2r {:?} cv {:.4} floor {}",
                    c.effect,
                    c.score.aicc.unwrap_or(f64::NAN),
                    c.score.chi2_reduced.map(|x| (x * 100.0).round() / 100.0),
                    c.score.cv_mare,
                    c.score.at_noise_floor
                );
            }
        }
    }
}
