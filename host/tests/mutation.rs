//! Mutation test of the whole binary: random mutations of the built-in
//! dataset (its `[setup.uncertainty]` block and per-case `uncertainty`
//! tables included), of the built-in robot file and of an effects file of
//! formulas (deleted lines, duplicated keys, type swaps, extreme numbers,
//! truncations, odd ids, hostile formulas and uncertainties) are run
//! through `compare`, `fit`, `diagnose` and `sim`. Every run must end within a time
//! limit with exit 0 (and no NaN or inf in its output) or exit 2 with a
//! `swimbot: error:` message; never a panic, a signal, or exit 1.
//!
//! Seeded and reproducible: the seed and count are printed and can be set
//! with `SWIMBOT_MUTATION_SEED` and `SWIMBOT_MUTATIONS`; a failure prints
//! the seed, the mutation number, the mutations applied and the command.
//! Runs go through worker threads; each child is killed at its deadline.

use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::path::Path;
use std::process::Stdio;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

const PAPER: &str = include_str!("../data/paper.toml");
const ROBOT: &str = include_str!("../data/robot.toml");
const EFFECTS: &str = include_str!("fixtures/restated.toml");
const DEFAULT_SEED: u64 = 0x5eed_2026;
/// About 10 s on two cores with the test profile (opt-level 1).
const DEFAULT_COUNT: usize = 400;
/// A run that takes longer than this counts as a hang.
const RUN_LIMIT: Duration = Duration::from_secs(30);
const WORKERS: usize = 3;

/// Replacement values: extremes, zeros, non-numbers, wrong types.
const VALUES: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1e300",
    "-1e300",
    "5e-324",
    "1e-160",
    "1e-300",
    "nan",
    "inf",
    "-inf",
    "4294967296",
    "99999999999999999999",
    "1e8",
    "0.5",
    "\"text\"",
    "true",
    "[1, 2]",
    "[]",
    "{ a = 1 }",
    "\"\"",
    "2026-01-01",
];
/// Formulas for a place: out of range, deep, long, odd characters, escapes.
const FORMULAS: &[&str] = &[
    "\"1e300\"",
    "\"1e-300\"",
    "\"-1\"",
    "\"0\"",
    "\"translation / 0\"",
    "\"ln(0)\"",
    "\"sqrt(-translation)\"",
    "\"((((((((((translation))))))))))\"",
    "\"translation^translation^translation^translation\"",
    "\"\\t\u{3000}$\"",
    "\"\"\"\ntranslation\\\n  * 2\"\"\"",
    "'translation * shear_rate'",
    "\"exp(1000 * translation)\"",
    "\"min(translation)\"",
    "\"\"",
];
/// Uncertainty entries: huge, negative, relative, unknown keys, wrong types.
const UNCERTAINTIES: &[&str] = &[
    "amplitude_mm = 1e6",
    "amplitude_mm = \"300%\"",
    "wavelength_mm = -0.5",
    "viscosity_pa_s = \"nan%\"",
    "frequency_hz = \"2\"",
    "coupler_length_mm = 0.1",
    "no_such_field = 1",
    "body_length_mm = [1]",
    "tail_length_mm = \"49.9%\"",
];
const IDS: &[&str] = &[
    "\"\"",
    "\"a\\u0007b\"",
    "\"tail-2\"",
    "\"x,y\"",
    "\" \"",
    "\"\\u001b[2J\"",
];

fn mutate(text: &str, rng: &mut StdRng, log: &mut Vec<String>) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let n_mut = rng.gen_range(1..=3);
    for _ in 0..n_mut {
        let i = rng.gen_range(0..lines.len());
        let is_kv = lines[i].contains('=') && !lines[i].trim_start().starts_with('#');
        let key = lines[i].split('=').next().unwrap_or("").trim().to_string();
        match rng.gen_range(0..13) {
            11 if key.starts_with('"') && key.contains('.') => {
                // A place's formula (an effects file).
                let f = FORMULAS[rng.gen_range(0..FORMULAS.len())];
                log.push(format!("line {}: {key} = {f}", i + 1));
                lines[i] = format!("{key} = {f}");
            }
            12 if text.contains("[setup.uncertainty]") => {
                let u = UNCERTAINTIES[rng.gen_range(0..UNCERTAINTIES.len())];
                let at = lines
                    .iter()
                    .position(|l| l.trim() == "[setup.uncertainty]")
                    .map_or(i, |p| p + 1);
                log.push(format!("insert at line {}: {u}", at + 1));
                lines.insert(at.min(lines.len()), u.to_string());
            }
            8..=10 if is_kv => {
                // A plausible value: a number scaled by 1/20..20, so that
                // many runs get through validation to the numerics.
                let (key, value) = lines[i].split_once('=').unwrap();
                let (key, value) = (key.trim().to_string(), value.trim());
                if let Ok(x) = value.parse::<f64>() {
                    let f = 20f64.powf(rng.gen_range(-1.0..1.0));
                    log.push(format!("line {}: {key} = {x} * {f:.3}", i + 1));
                    lines[i] = format!("{key} = {:e}", x * f);
                }
            }
            0 => {
                log.push(format!("delete line {}: {}", i + 1, lines[i]));
                lines.remove(i);
            }
            1 => {
                log.push(format!("duplicate line {}: {}", i + 1, lines[i]));
                let l = lines[i].clone();
                lines.insert(i, l);
            }
            2..=4 if is_kv => {
                let key = lines[i].split('=').next().unwrap_or("").trim().to_string();
                let v = if key == "id" && rng.gen_bool(0.5) {
                    IDS[rng.gen_range(0..IDS.len())]
                } else {
                    VALUES[rng.gen_range(0..VALUES.len())]
                };
                log.push(format!("line {}: {key} = {v}", i + 1));
                lines[i] = format!("{key} = {v}");
            }
            5 if is_kv => {
                let key = lines[i].split('=').next().unwrap_or("").trim().to_string();
                let v = VALUES[rng.gen_range(0..VALUES.len())];
                let k = if key.ends_with("_mm_s") {
                    "u_trials_mm_s"
                } else {
                    "omega_body_trials_hz"
                };
                let same = rng.gen_bool(0.5);
                let line = if same {
                    format!("{k} = [{v}, {v}, {v}]")
                } else {
                    format!("{k} = [0.2, {v}]")
                };
                log.push(format!("insert after line {}: {line}", i + 1));
                lines.insert(i + 1, line);
            }
            6 => {
                log.push(format!("swap lines {} and its successor", i + 1));
                if i + 1 < lines.len() {
                    lines.swap(i, i + 1);
                }
            }
            _ => {
                let joined = lines.join("\n");
                let cut = rng.gen_range(0..=joined.len());
                let cut = (0..=cut)
                    .rev()
                    .find(|&c| joined.is_char_boundary(c))
                    .unwrap_or(0);
                log.push(format!("truncate at byte {cut}"));
                lines = joined[..cut].lines().map(str::to_string).collect();
                if lines.is_empty() {
                    lines.push(String::new());
                }
            }
        }
        if lines.is_empty() {
            lines.push(String::new());
        }
    }
    lines.join("\n") + "\n"
}

struct Outcome {
    code: Option<i32>,
    stdout: String,
    stderr: String,
    timed_out: bool,
}

fn run(args: &[String], dir: &Path) -> Outcome {
    let mut child = crate::common::command()
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts");
    // Drain the pipes in threads so that a chatty child cannot block.
    let mut out = child.stdout.take().unwrap();
    let mut err = child.stderr.take().unwrap();
    let t_out = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut out, &mut s);
        s
    });
    let t_err = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::Read::read_to_string(&mut err, &mut s);
        s
    });
    let start = Instant::now();
    let mut timed_out = false;
    let status = loop {
        if let Some(s) = child.try_wait().expect("wait") {
            break Some(s);
        }
        if start.elapsed() > RUN_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            timed_out = true;
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Outcome {
        code: status.and_then(|s| s.code()),
        stdout: t_out.join().unwrap_or_default(),
        stderr: t_err.join().unwrap_or_default(),
        timed_out,
    }
}

/// A NaN or infinity as any of our formats prints it.
fn has_non_finite(text: &str) -> bool {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .any(|w| matches!(w, "NaN" | "nan" | "inf" | "Inf" | "infinity" | "Infinity"))
}

/// One mutation: its exit code, or what went wrong.
fn one(k: usize, seed: u64, root: &Path) -> Result<i32, String> {
    let mut rng = StdRng::seed_from_u64(seed ^ (k as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
    let dir = root.join(format!("m{k}"));
    std::fs::create_dir_all(&dir).unwrap();
    let mut log = Vec::new();
    let pick = rng.gen_range(0..100);
    let args: Vec<String> = if pick < 15 {
        let text = mutate(EFFECTS, &mut rng, &mut log);
        std::fs::write(dir.join("effects.toml"), text).unwrap();
        let effect = if pick < 10 {
            "body-factors:translation=4,rotation=2"
        } else {
            "wall-log"
        };
        [
            "compare",
            "--no-report",
            "--effect-file",
            "effects.toml",
            "--effect",
            effect,
        ]
        .map(String::from)
        .to_vec()
    } else if pick < 35 {
        let text = mutate(ROBOT, &mut rng, &mut log);
        std::fs::write(dir.join("robot.toml"), text).unwrap();
        [
            "sim",
            "--robot",
            "robot.toml",
            "--max-time-s",
            "30",
            "-o",
            "out",
        ]
        .map(String::from)
        .to_vec()
    } else {
        let text = mutate(PAPER, &mut rng, &mut log);
        std::fs::write(dir.join("data.toml"), text).unwrap();
        let cmd: &[&str] = match pick {
            30..=64 => &["compare", "--no-report"],
            65..=69 => &["compare", "-o", "rep", "--format", "csv"],
            70..=94 => &["fit", "--effect", "body-correction"],
            _ => &["diagnose", "--no-pairs"],
        };
        cmd.iter()
            .map(|s| s.to_string())
            .chain(["--data".into(), "data.toml".into()])
            .collect()
    };
    let o = run(&args, &dir);
    let what = || {
        format!(
            "seed {seed:#x}, mutation {k}: `swimbot {}` after [{}]",
            args.join(" "),
            log.join("; ")
        )
    };
    if o.timed_out {
        return Err(format!("{}: no answer within {RUN_LIMIT:?}", what()));
    }
    match o.code {
        Some(0) => {
            let csv = std::fs::read_to_string(dir.join("out/sim.csv")).unwrap_or_default();
            if has_non_finite(&o.stdout) || has_non_finite(&csv) {
                return Err(format!(
                    "{}: exit 0 with a non-finite number:\n{}",
                    what(),
                    o.stdout
                ));
            }
        }
        Some(2) => {
            // Progress lines (a run past 2 s) may come before the message.
            let msg = o.stderr.trim();
            let said = |l: &str| l.starts_with("swimbot: error:") || l.starts_with("error:");
            if !msg.lines().any(said) {
                return Err(format!("{}: exit 2 without a message: {msg}", what()));
            }
        }
        c => {
            return Err(format!(
                "{}: exit {c:?} (expected 0 or 2)\nstderr: {}",
                what(),
                o.stderr
            ))
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(o.code.unwrap_or(-1))
}

#[test]
fn random_mutations_never_panic_hang_or_print_nan() {
    let seed = std::env::var("SWIMBOT_MUTATION_SEED")
        .ok()
        .and_then(|s| u64::from_str_radix(s.trim_start_matches("0x"), 16).ok())
        .unwrap_or(DEFAULT_SEED);
    let count = std::env::var("SWIMBOT_MUTATIONS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(DEFAULT_COUNT);
    eprintln!("mutation test: seed {seed:#x} (SWIMBOT_MUTATION_SEED), {count} mutations (SWIMBOT_MUTATIONS)");
    let root = tempfile::tempdir().unwrap();
    let next = AtomicUsize::new(0);
    let failures = Mutex::new(Vec::new());
    let (ok, refused) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let start = Instant::now();
    std::thread::scope(|s| {
        for _ in 0..WORKERS {
            s.spawn(|| loop {
                let k = next.fetch_add(1, Ordering::Relaxed);
                if k >= count {
                    break;
                }
                match one(k, seed, root.path()) {
                    Ok(0) => _ = ok.fetch_add(1, Ordering::Relaxed),
                    Ok(_) => _ = refused.fetch_add(1, Ordering::Relaxed),
                    Err(e) => failures.lock().unwrap().push(e),
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    eprintln!(
        "mutation test: {count} runs in {:.1} s: {} exit 0, {} refused with exit 2, {} failures",
        start.elapsed().as_secs_f64(),
        ok.into_inner(),
        refused.into_inner(),
        failures.len()
    );
    assert!(
        failures.is_empty(),
        "{} of {count} mutations failed:\n{}",
        failures.len(),
        failures.join("\n\n")
    );
}

#[test]
fn the_mutator_is_reproducible_and_changes_the_text() {
    let a = mutate(PAPER, &mut StdRng::seed_from_u64(7), &mut Vec::new());
    let b = mutate(PAPER, &mut StdRng::seed_from_u64(7), &mut Vec::new());
    assert_eq!(a, b);
    let changed = (0..50)
        .filter(|&s| mutate(PAPER, &mut StdRng::seed_from_u64(s), &mut Vec::new()) != PAPER)
        .count();
    assert!(
        changed >= 45,
        "only {changed} of 50 mutations changed the text"
    );
    assert!(has_non_finite("U NaN mm/s") && has_non_finite("x,inf,") && !has_non_finite("info"));
}
