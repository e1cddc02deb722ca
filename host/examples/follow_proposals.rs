//! A user who does only what the study proposes: on drawn truths with
//! several effects, `init` a study and add, step after step, the first
//! thing its last diagnosis proposes (a catalogue effect by name, a law
//! from the file `diagnose --write-effect` writes, by the `#NAME` the
//! study printed), until nothing is proposed, the model is at the noise
//! floor, or twice the truth's size of steps is spent. Prints one row per
//! design: the steps taken against the truth's number of effects, whether
//! the floor was reached, and what each step added.
//!
//! The loop reaches the floor "in time" when it takes at most one step
//! more than the truth has effects (a step may hold an effect's share that
//! a later step completes). It knows the truth only to count its effects:
//! this is a measurement of the advice, not a check `diagnose` runs.
//!
//! `cargo run --release -p swimbot --example follow_proposals`
//! (`FIRST_SEED`, `SEEDS`: the three-effect designs of the recovery study,
//! docs/discovery.md, default 1701 and 10).

#[path = "../tests/fixtures/drawn.rs"]
mod drawn;

use std::path::Path;
use std::time::Instant;
use swimbot::model::Model;
use swimbot::provenance::Inputs;
use swimbot::study::{AddOptions, Definition, InitOptions, Study};
use swimbot::workbench::diagnose::{diagnose, DiagnoseSettings};
use swimbot::workbench::discovery::write::to_toml_steps;

/// How one design's loop ended.
struct Walk {
    added: Vec<String>,
    at_floor: bool,
    stopped: &'static str,
}

/// The definition of what `name` names: a catalogue effect, else the law
/// of that name in the file `diagnose --write-effect` writes now.
fn definition_of(study: &Study, name: &str, dir: &Path) -> Definition {
    if let Some(e) = swimbot::effects::by_name(name) {
        return Definition::of_catalogue(e);
    }
    let model = study.model().expect("the study's model");
    let d = diagnose(&model, study.dataset(), &DiagnoseSettings::default()).expect("diagnose");
    let file = dir.join("found.toml");
    std::fs::write(&file, to_toml_steps(&d.laws_to_write(), "drawn")).expect("write");
    Definition::of_file(&file, Some(name), &Inputs::new()).unwrap_or_else(|e| {
        panic!("the proposed #{name} is not in the written file: {e}");
    })
}

fn walk(data: &swimbot::data::Dataset, limit: usize) -> Walk {
    let dir = tempfile::tempdir().expect("a temporary directory");
    let data_path = dir.path().join("data.toml");
    std::fs::write(&data_path, swimbot::data::to_toml(data)).expect("write");
    let path = dir.path().join("swimbot-study.toml");
    let mut study = Study::init(&path, &data_path, &InitOptions::default()).expect("init");
    let mut added = Vec::new();
    loop {
        if study.current().stats.at_noise_floor {
            return Walk {
                added,
                at_floor: true,
                stopped: "at the floor",
            };
        }
        if added.len() >= limit {
            return Walk {
                added,
                at_floor: false,
                stopped: "step limit",
            };
        }
        let Some(p) = study
            .last_diagnosis()
            .and_then(|d| d.proposals.first())
            .cloned()
        else {
            return Walk {
                added,
                at_floor: false,
                stopped: "nothing proposed",
            };
        };
        // A proposed set of catalogue effects is added one at a time.
        let name = p.name.split(" + ").next().unwrap_or(&p.name).to_string();
        let def = definition_of(&study, &name, dir.path());
        match study.add(def, &AddOptions::default()) {
            Ok(_) => added.push(p.law.clone().unwrap_or(name)),
            Err(e) => {
                added.push(format!("{name} (refused: {e})"));
                return Walk {
                    added,
                    at_floor: false,
                    stopped: "the proposal was refused",
                };
            }
        }
    }
}

fn main() {
    let paper = swimbot::data::paper();
    let seeds = drawn::seeds_from_env(1701);
    println!(
        "| seed | truth's effects | steps | at the floor | in time | ended | s | steps added |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let (mut floor, mut in_time, mut n) = (0, 0, 0);
    for seed in seeds {
        let (_, data) = drawn::three_effect_data(&Model::base(), &paper, seed);
        let truth_size = 3;
        let t = Instant::now();
        let w = walk(&data, 2 * truth_size);
        let on_time = w.at_floor && w.added.len() <= truth_size + 1;
        n += 1;
        floor += w.at_floor as u32;
        in_time += on_time as u32;
        println!(
            "| {seed} | {truth_size} | {} | {} | {} | {} | {:.0} | {} |",
            w.added.len(),
            if w.at_floor { "yes" } else { "no" },
            if on_time { "yes" } else { "no" },
            w.stopped,
            t.elapsed().as_secs_f64(),
            w.added.join("; ")
        );
    }
    println!("\nat the floor {floor}/{n}, in at most one step more than the truth {in_time}/{n}");
}
