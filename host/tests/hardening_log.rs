//! CRC-valid run logs that would print a lie, through the binary: a rate
//! of 0 in every record gives no "inf %", and a time that runs backwards
//! (two logs joined) or jumps by weeks is refused naming the record.

use crate::common::{stderr, stdout, swimbot, write_simulated_log};
use std::path::Path;
use swimbot_shared::run_log::Record;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// The records of a short simulated run (rate-controlled 0.6 Hz).
fn simulated_records(dir: &Path) -> Vec<Record> {
    let log = dir.join("base.swlog");
    write_simulated_log(&log, &dir.join("sim"));
    swimbot::runlog::decode::decode_bytes(&std::fs::read(&log).unwrap())
        .unwrap()
        .records
}

fn write(dir: &Path, name: &str, records: &[Record]) -> String {
    let path = dir.join(name);
    std::fs::write(&path, swimbot::sim::replay::log_image(records).unwrap()).unwrap();
    path.display().to_string()
}

#[test]
fn a_log_rate_of_zero_prints_no_infinite_percentage() {
    let dir = tempfile::tempdir().unwrap();
    let mut records = simulated_records(dir.path());
    for r in &mut records {
        if r.rate_mhz.is_some() {
            r.rate_mhz = Some(0);
        }
    }
    let log = write(dir.path(), "zero.swlog", &records);
    let out = dir.path().join("replay");
    let o = swimbot(&[
        "sim",
        "--tail",
        "3",
        "--set-points-from",
        &log,
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(!text.contains("inf"), "{text}");
    assert!(text.contains("no relative difference"), "{text}");
    let svg = std::fs::read_to_string(out.join("log-vs-sim.svg")).unwrap();
    assert!(
        !svg.contains("inf %") && !svg.contains("NaN"),
        "the figure's note"
    );
}

#[test]
fn time_that_runs_backwards_or_jumps_is_refused_naming_the_record() {
    let dir = tempfile::tempdir().unwrap();
    let records = simulated_records(dir.path());
    let n = records.len();
    let doubled = [records.clone(), records.clone()].concat();
    let mut jumped = records.clone();
    for r in &mut jumped[n / 2..] {
        r.t_ms = r.t_ms.wrapping_add(0xFFF0_0000);
    }
    for (name, recs, says) in [
        ("doubled", doubled, format!("record {} ", n + 1)),
        ("jumped", jumped, format!("record {} ", n / 2 + 1)),
    ] {
        let log = write(dir.path(), &format!("{name}.swlog"), &recs);
        let out = dir.path().join(format!("out-{name}"));
        for args in [
            vec!["log", log.as_str(), "-o", s(&out)],
            vec![
                "sim",
                "--tail",
                "3",
                "--set-points-from",
                log.as_str(),
                "-o",
                s(&out),
            ],
        ] {
            let o = swimbot(&args);
            let e = stderr(&o);
            assert_eq!(o.status.code(), Some(2), "{name}: {e}");
            assert!(e.contains(&log) && e.contains(&says), "{name}: {e}");
            assert!(!out.exists(), "{name}: nothing written");
        }
    }
    // Two runs of one power-up, minutes apart, are one real log.
    let mut two_runs = records.clone();
    let end = records.last().unwrap().t_ms;
    two_runs.extend(records.iter().map(|r| Record {
        t_ms: r.t_ms + end + 600_000,
        ..*r
    }));
    let log = write(dir.path(), "two.swlog", &two_runs);
    let o = swimbot(&["log", &log, "-o", s(&dir.path().join("two"))]);
    assert!(o.status.success(), "{}", stderr(&o));
}
