//! A run the robot could not log, through the binary: when a power-up
//! dropped its whole run (no erased slot), the robot answers `LOG` with an
//! earlier power-up's records and says so (image version 2); `swimbot log`
//! refuses that as this run (exit 2, the file named, nothing written)
//! unless `--earlier`, and warns about every log that is not plainly this
//! power-up's whole run. The images are made by the firmware's encoder.

use crate::common::{stderr, stdout, swimbot};
use std::path::Path;
use swimbot_shared::run_log::image::{FLAG_CLOSED, FLAG_RECOVERED};
use swimbot_shared::run_log::{encode, Events, Header, Record, HEADER_LEN, RECORD_LEN};

/// Four seconds at 0.8 Hz, one record every 100 ms.
fn image(flags: u16, dropped: u32, n: u32) -> Vec<u8> {
    let records: Vec<Record> = (0..n)
        .map(|i| Record {
            t_ms: 1_000 + 100 * i,
            set_point_mhz: Some(800),
            rate_mhz: Some(799 + (i % 3) as u16),
            duty_per_10k: 3_000,
            cell_mv: 3_900,
            events: if i == 0 { Events::ON } else { Events::NONE },
            fault: None,
            foreign_frames: 0,
        })
        .collect();
    let header = Header {
        sample_period_ms: 100,
        record_count: 0,
        dropped_records: dropped,
        foreign_frames: 0,
        paired_address: Some(0x5a),
        flags,
    };
    let mut out = vec![0u8; HEADER_LEN + RECORD_LEN * records.len()];
    encode(&header, &records, &mut out).unwrap();
    out
}

/// `swimbot log` on `bytes` saved as `name`: the output and the output dir.
fn log(dir: &Path, name: &str, bytes: &[u8], extra: &[&str]) -> (std::process::Output, String) {
    let path = dir.join(format!("{name}.swlog"));
    std::fs::write(&path, bytes).unwrap();
    let out = dir.join(format!("out-{name}"));
    let mut args = vec!["log", path.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    (swimbot(&args), path.display().to_string())
}

fn is_empty_dir(dir: &Path, name: &str) -> bool {
    let out = dir.join(format!("out-{name}"));
    !out.exists() || std::fs::read_dir(&out).unwrap().next().is_none()
}

#[test]
fn a_dropped_run_is_refused_not_read_as_the_earlier_one() {
    let dir = tempfile::tempdir().unwrap();
    // The robot's answer after a power-up with no erased slot ran 4.2 s:
    // 42 records dropped, the 40 records sent are an earlier power-up's.
    let lost = image(FLAG_CLOSED | FLAG_RECOVERED, 42, 40);
    let (o, path) = log(dir.path(), "lost", &lost, &[]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for says in [
        path.as_str(),
        "NOT logged",
        "42 records",
        "EARLIER",
        "--earlier",
    ] {
        assert!(err.contains(says), "no `{says}` in: {err}");
    }
    assert!(is_empty_dir(dir.path(), "lost"), "written though refused");

    // Asked for: read, with the loss and whose run it is said.
    let (o, path) = log(dir.path(), "lost", &lost, &["--earlier"]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains(&format!(
        "warning: {path}: this power-up's run was NOT logged"
    )));
    assert!(
        stdout(&o).contains("an EARLIER power-up's run; 42 dropped"),
        "{}",
        stdout(&o)
    );
    let csv = std::fs::read_to_string(dir.path().join("out-lost/log.csv")).unwrap();
    assert!(
        csv.contains("# warning: this power-up's run was NOT logged"),
        "{csv}"
    );

    // Dropped with no earlier log to fall back to: refused, --earlier or not.
    let nothing = image(FLAG_CLOSED, 7, 0);
    let (o, path) = log(dir.path(), "nothing", &nothing, &["--earlier"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&path) && err.contains("holds no other log"),
        "{err}"
    );
}

#[test]
fn logs_that_are_not_this_power_ups_whole_run_are_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let mut v1 = image(FLAG_CLOSED | FLAG_RECOVERED, 0, 40);
    v1[4..6].copy_from_slice(&1u16.to_le_bytes());
    let crc = crc32(&[&v1[..28], &v1[HEADER_LEN..]].concat());
    v1[28..32].copy_from_slice(&crc.to_le_bytes());
    let cases: [(&str, Vec<u8>, Option<&str>); 4] = [
        ("own", image(FLAG_CLOSED, 0, 40), None),
        (
            "gaps",
            image(FLAG_CLOSED, 12, 40),
            Some("misses 12 records (1.2 s"),
        ),
        (
            "earlier",
            image(FLAG_CLOSED | FLAG_RECOVERED, 0, 40),
            Some("an EARLIER power-up's run: the robot was powered off and on since"),
        ),
        ("v1", v1, Some("version-1 log: whether the run")),
    ];
    for (name, bytes, warns) in cases {
        let (o, path) = log(dir.path(), name, &bytes, &[]);
        let err = stderr(&o);
        assert!(o.status.success(), "{name}: {err}");
        match warns {
            None => assert!(!err.contains("warning"), "{name}: {err}"),
            Some(w) => assert!(
                err.contains(&format!("warning: {path}: ")) && err.contains(w),
                "{name}: {err}"
            ),
        }
    }
}

/// zlib's CRC-32, bit by bit, to write a version-1 file: the host has no
/// CRC crate (the firmware's `crc` is the shared crate's), and `decode`
/// refusing a wrong sum checks this one.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 != 0 {
                (c >> 1) ^ 0xEDB8_8320
            } else {
                c >> 1
            };
        }
    }
    !c
}
