//! Inputs never fill the machine nor hang the run, through the binary:
//! every input is bounded by its kind's cap while it is read (an endless
//! device, a FIFO fed without end), a FIFO without a writer ends at once,
//! and messages that name what is wrong (`fit` at absurd bounds, an empty
//! term of `synth --truth`).

use crate::common::{mkfifo, stderr, swimbot};
use std::path::Path;
use std::process::Output;
use std::time::Duration;

/// The binary in the current directory, killed after `limit`.
fn within(args: &[&str], limit: Duration) -> Output {
    crate::common::within(Path::new("."), args, &[], limit)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn an_endless_device_is_refused_at_its_kinds_cap() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("d.csv");
    std::fs::write(
        &csv,
        "# setup_file = \"/dev/zero\"\nid,wavelength_mm\ntail-1,10\n",
    )
    .unwrap();
    for (args, needle) in [
        (
            vec!["compare", "--no-report", "--data", "/dev/zero"],
            "/dev/zero",
        ),
        (vec!["sim", "--robot", "/dev/zero"], "/dev/zero"),
        (vec!["sim", "--script-file", "/dev/zero"], "/dev/zero"),
        (
            vec!["compare", "--no-report", "--data", s(&csv)],
            "/dev/zero",
        ),
        (
            vec!["compare", "--no-report", "--effect-file", "/dev/zero"],
            "/dev/zero",
        ),
    ] {
        let o = within(&args, Duration::from_secs(20));
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        let e = stderr(&o);
        assert!(
            e.contains(needle) && e.contains("larger than"),
            "{args:?}: {e}"
        );
    }
    let o = within(&["log", "/dev/zero"], Duration::from_secs(20));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn a_fifo_fed_without_end_stops_at_the_logs_cap() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("fifo");
    mkfifo(&fifo);
    let path = fifo.clone();
    let writer = std::thread::spawn(move || {
        use std::io::Write;
        let mut f = std::fs::OpenOptions::new().write(true).open(&path).unwrap();
        let mut header = b"SWLG".to_vec();
        header.resize(32, 0);
        let _ = f.write_all(&header);
        let zeros = vec![0u8; 1 << 16];
        let mut sent = 0usize;
        // Until the reader stops (EPIPE), or far past the cap.
        while f.write_all(&zeros).is_ok() && sent < 64 << 20 {
            sent += zeros.len();
        }
        sent
    });
    let o = within(
        &["log", s(&fifo), "-o", s(&dir.path().join("L"))],
        Duration::from_secs(30),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("larger than"), "{}", stderr(&o));
    let sent = writer.join().unwrap();
    assert!(
        sent < 32 << 20,
        "the reader stopped near the 16 MiB cap: {sent}"
    );
}

#[test]
fn a_fifo_without_a_writer_does_not_hang() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("data.toml");
    mkfifo(&fifo);
    let o = within(
        &["compare", "--no-report", "--data", s(&fifo)],
        Duration::from_secs(20),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("data.toml"), "{}", stderr(&o));
    let o = within(&["log", s(&fifo)], Duration::from_secs(20));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    // A directory is refused by kind.
    let o = within(&["sim", "--robot", s(dir.path())], Duration::from_secs(20));
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("a directory"), "{}", stderr(&o));
}

#[test]
fn fit_at_bounds_too_wide_names_the_effect_and_parameter() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("wide.toml");
    std::fs::write(
        &file,
        "[[effect]]\nname = \"wide\"\nstatement = \"s\"\nreference = \"r\"\n\
         \n[[effect.param]]\nname = \"k\"\nunit = \"1\"\ndefault = 0.0\nmin = -1e308\nmax = 1e308\n\
         \n[effect.places]\n\"tail.c_n\" = \"1 + k\"\n",
    )
    .unwrap();
    let o = swimbot(&["fit", "--effect-file", s(&file), "--effect", "wide"]);
    assert_ne!(o.status.code(), Some(0), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("`wide`") && e.contains("`k`"), "{e}");
    assert!(!e.contains("panicked"), "{e}");
}

#[test]
fn an_empty_term_of_the_truth_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.toml");
    for truth in ["base ++ backflow", "base + backflow +", "+ backflow"] {
        let o = swimbot(&["synth", "--truth", truth, "-o", s(&out)]);
        assert_eq!(o.status.code(), Some(2), "{truth}: {}", stderr(&o));
        assert!(stderr(&o).contains("is empty"), "{}", stderr(&o));
        assert!(!out.exists());
    }
}
