//! The run log through the binary: `swimbot sim
//! --write-log` writes a log image with the firmware's own recorder and
//! encoder, `swimbot log` reads it back into steady windows, a dataset and
//! the trace figure, and `swimbot sim --set-points-from` replays it; bad
//! logs are input errors naming the file and what is wrong, with nothing
//! written.

use crate::common::{stderr, stdout, swimbot};
use std::path::Path;

/// A rate-controlled run of tail 3: 0.6 Hz, 0.9 Hz from 15 s, Off at 30 s.
fn simulated_log(dir: &Path) -> String {
    let log = dir.join("run.swlog").display().to_string();
    let out = dir.join("sim").display().to_string();
    let o = swimbot(&[
        "sim",
        "--tail",
        "3",
        "--rate-hz",
        "0.6@0s,0.9@15s",
        "--script",
        "on@0s,off@30s",
        "--write-log",
        &log,
        "-o",
        &out,
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    log
}

#[test]
fn a_simulated_log_round_trips_into_trials_and_a_replay() {
    let dir = tempfile::tempdir().unwrap();
    let log = simulated_log(dir.path());
    let out = dir.path().join("log");
    let o = swimbot(&["log", &log, "--case", "tail-3", "-o", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("set-point 0.900 Hz"), "{}", stdout(&o));

    // The dataset loads; one case per set-point, the log's rate near it,
    // its uncertainty the standard error of a few turns' means.
    let data = swimbot::data::load_file(&out.join("trials.toml")).expect("a valid dataset");
    let ids: Vec<&str> = data.cases.iter().map(|c| c.id.as_str()).collect();
    assert_eq!(ids, ["tail-3@0.600Hz", "tail-3@0.900Hz"]);
    for (c, set) in data.cases.iter().zip([0.6, 0.9]) {
        assert!(
            (c.frequency_hz / set - 1.0).abs() < 0.01,
            "{}",
            c.frequency_hz
        );
        let u = c.inputs.standard(c, "frequency_hz");
        assert!(u > 0.0 && u < 0.01 * set, "{}: {u}", c.id);
        assert!(c.u_mm_s.is_none(), "the log cannot know the speed");
    }
    let svg = std::fs::read_to_string(out.join("log.svg")).unwrap();
    assert!(svg.contains("set 0.9 Hz") && svg.contains("Off"));
    let csv = std::fs::read_to_string(out.join("log.csv")).unwrap();
    assert!(csv.lines().count() > 300, "10 Hz for 30 s");

    // Replayed with the same tail and model, the simulation predicts its
    // own log: the set-points and commands were reconstructed in time.
    let replay = dir.path().join("replay");
    let o = swimbot(&[
        "sim",
        "--tail",
        "3",
        "--set-points-from",
        &log,
        "-o",
        replay.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let line = stdout(&o)
        .lines()
        .find(|l| l.starts_with("log vs sim, in the log's steady windows"))
        .expect("the difference is stated")
        .to_string();
    let pct: f64 = line
        .split('(')
        .nth(2)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!(pct.abs() < 0.1, "{line}");
    assert!(replay.join("log-vs-sim.svg").exists());
}

/// Each damaged log: exit 2, the file named, what is wrong said, and no
/// output written.
#[test]
fn bad_logs_are_input_errors_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read(simulated_log(dir.path())).unwrap();
    let mut bad_crc = good.clone();
    let last = bad_crc.len() - 1;
    bad_crc[last] ^= 0x01;
    let mut magic = good.clone();
    magic[..4].copy_from_slice(b"PNG\x89");
    // A valid image of no record: the robot's answer before any run.
    let empty = swimbot::sim::replay::log_image(&[]).unwrap();
    let cases: [(&str, Vec<u8>, &str); 5] = [
        ("truncated", good[..good.len() - 7].to_vec(), "truncated"),
        ("crc", bad_crc, "bad CRC"),
        ("magic", magic, "not a swimbot run log"),
        ("empty", empty, "the log is empty"),
        ("short", good[..10].to_vec(), "too short"),
    ];
    for (name, bytes, says) in cases {
        let path = dir.path().join(format!("{name}.swlog"));
        std::fs::write(&path, bytes).unwrap();
        let out = dir.path().join(format!("out-{name}"));
        let o = swimbot(&["log", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.contains(path.to_str().unwrap()) && err.contains(says),
            "{name}: {err}"
        );
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(!out.exists() || std::fs::read_dir(&out).unwrap().next().is_none());
    }
    let missing = dir.path().join("none.swlog");
    let o = swimbot(&["log", missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("none.swlog"), "{}", stderr(&o));
}

/// The log's steady rate against the simulated motor's true rate over the
/// same windows, on a tail and noise draw nothing was tuned to: the
/// interval written covers the truth.
#[test]
fn the_logged_rate_and_its_interval_cover_the_true_rate() {
    use swimbot::robot::hall::SensorNoise;
    use swimbot::sim::{default_robot, replay, simulate_with, Options, RateRun, Script};
    let mut robot = default_robot();
    let t = &mut robot.tails[0];
    (t.id, t.wavelength_mm, t.amplitude_mm, t.length_mm) = ("fresh".into(), 11.0, 3.5, 100.0);
    t.observed_f_hz = None;
    let mut run = RateRun::new(vec![(0, 0.7), (20_000_000, 1.1)]);
    run.noise = SensorNoise {
        pitch_error_deg: 3.0,
        seed: 4_242,
        ..SensorNoise::TYPICAL
    };
    let opts = Options {
        tail: 0,
        max_time_s: 40.0,
        stop_at_top: false,
        ..Options::default()
    };
    let o = simulate_with(&robot, &Script::on_at_zero(), &opts, Some(&run)).unwrap();
    let windows = swimbot::runlog::steady_windows(&replay::log_trace(&o.log_records));
    assert_eq!(windows.len(), 2, "{windows:?}");
    for w in &windows {
        // The first turn mean covers the turn before the window's start.
        let from = w.from_s - 1.0 / w.set_hz;
        let truth: Vec<f64> = o
            .rate_trace
            .iter()
            .filter(|p| p.t_s > from && p.t_s <= w.to_s)
            .map(|p| p.motor_rate_hz)
            .collect();
        let true_mean = truth.iter().sum::<f64>() / truth.len() as f64;
        eprintln!(
            "{:.1}-{:.1} s: log {:.5} +- {:.5} Hz, true {:.5} Hz",
            w.from_s, w.to_s, w.mean_hz, w.ci_hz, true_mean
        );
        assert!(
            (w.mean_hz - true_mean).abs() <= w.ci_hz,
            "{w:?}: {true_mean}"
        );
        assert!(w.ci_hz < 0.01 * w.set_hz, "{w:?}");
    }
}
