//! Faults the scripted attack on the answer-first commands found
//! (scripts/attack_screens.py, attack_outputs.py), through the binary: a
//! negative count is refused naming its flag; every usage mistake has the
//! `swimbot: error:` prefix; an output FIFO with no reader is refused
//! instead of waited on for ever; a failed run into `new/../D` keeps the
//! user's folder D.

use crate::common::{mkfifo, stderr, stdout, within};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// A study on the paper's CSV in a fresh folder, made by the binary.
fn study() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv"),
        dir.path().join("paper.csv"),
    )
    .unwrap();
    let o = within(
        dir.path(),
        &["init", "--data", "paper.csv"],
        &[],
        Duration::from_secs(120),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    dir
}

fn refused(o: &std::process::Output, needles: &[&str]) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    // Notes may come first (`note: the study ...`); the refusal is a line of its own.
    assert!(e.lines().any(|l| l.starts_with("swimbot: error: ")), "{e}");
    assert!(!e.contains("panicked"), "{e}");
    for n in needles {
        assert!(e.contains(n), "no `{n}` in: {e}");
    }
}

#[test]
fn a_negative_count_is_refused_naming_its_flag() {
    let dir = tempfile::tempdir().unwrap();
    let limit = Duration::from_secs(60);
    // `-1` read as an unknown flag `-1` before: no flag named.
    for (args, flag) in [
        (&["plan", "--runs", "-1"][..], "--runs"),
        (&["plan", "--runs=-3"], "--runs"),
        (
            &["compare", "--no-report", "--mc-draws", "-1"],
            "--mc-draws",
        ),
        (&["audit", "--family-samples", "-2"], "--family-samples"),
        (&["audit", "--seed", "-1"], "--seed"),
        (
            &["compare", "--no-report", "--nodes-per-wavelength", "-100"],
            "--nodes-per-wavelength",
        ),
    ] {
        let o = within(dir.path(), args, &[], limit);
        refused(&o, &[flag, "negative"]);
    }
    // A fraction and an exponent get their own reason.
    let o = within(dir.path(), &["plan", "--runs", "2.5"], &[], limit);
    refused(&o, &["--runs", "not a whole number"]);
    let o = within(dir.path(), &["plan", "--runs", "1e3"], &[], limit);
    refused(&o, &["--runs", "exponent"]);
}

#[test]
fn a_usage_mistake_has_the_prefix_of_every_refusal_and_help_still_prints() {
    let dir = tempfile::tempdir().unwrap();
    let limit = Duration::from_secs(60);
    let o = within(dir.path(), &["plan", "-o"], &[], limit);
    refused(&o, &["--output"]);
    let o = within(dir.path(), &["diagnose", "--no-such-flag"], &[], limit);
    refused(&o, &["--no-such-flag"]);
    let o = within(dir.path(), &["plan", "--help"], &[], limit);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).contains("--runs"), "{}", stdout(&o));
    let o = within(dir.path(), &["--version"], &[], limit);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(stdout(&o).starts_with("swimbot "), "{}", stdout(&o));
}

#[test]
fn an_output_fifo_without_a_reader_is_refused_and_with_one_it_is_written() {
    let dir = study();
    let fifo = dir.path().join("sheet");
    mkfifo(&fifo);
    // Was a hang: opening a FIFO for writing waits for a reader.
    let o = within(
        dir.path(),
        &["plan", "--runs", "2", "-o", "sheet"],
        &[],
        Duration::from_secs(60),
    );
    refused(&o, &["sheet", "no reader"]);
    let o = within(
        dir.path(),
        &["diagnose", "--write-effect", "sheet"],
        &[],
        Duration::from_secs(60),
    );
    refused(&o, &["sheet", "no reader"]);
    // A reader that comes a moment later still gets the whole sheet.
    let path = fifo.clone();
    let reader = std::thread::spawn(move || {
        std::thread::sleep(Duration::from_millis(300));
        std::fs::read_to_string(path).unwrap()
    });
    let o = within(
        dir.path(),
        &["plan", "--runs", "2", "-o", "sheet"],
        &[],
        Duration::from_secs(60),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let sheet = reader.join().unwrap();
    assert!(
        sheet.contains("wavelength_mm") && sheet.lines().count() > 3,
        "{sheet}"
    );
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "the full disk is simulated in debug builds only (atomic_dir::fault_injection)"
)]
fn a_failed_run_into_new_dotdot_d_keeps_the_users_folder_d() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().join("D");
    std::fs::create_dir(&d).unwrap();
    let through: PathBuf = ["new", "..", "D"].iter().collect();
    let o = crate::common::command()
        .args(["compare", "-o"])
        .arg(&through)
        .current_dir(dir.path())
        .env("SWIMBOT_FAULT_DISK_FULL_AFTER_BYTES", "60000")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("No space left"), "{}", stderr(&o));
    // D was the user's (it existed): kept; `new/` was the run's: removed.
    assert!(d.is_dir(), "the user's folder D was removed");
    assert!(
        !dir.path().join("new").exists(),
        "the run's folder new/ was kept"
    );
    assert_eq!(listing(&d), Vec::<String>::new());
}

fn listing(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_bad_value_on_a_setup_line_is_refused_naming_its_key() {
    let dir = tempfile::tempdir().unwrap();
    let paper =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv")).unwrap();
    // The message named only the line, and called it no `# key = value` line.
    for (key, bad) in [
        ("viscosity_pa_s", "1e999"),
        ("trials", ""),
        ("wire_diameter_mm", "µm"),
    ] {
        let text = paper
            .lines()
            .map(|l| {
                if l.starts_with(&format!("# {key} = ")) {
                    format!("# {key} = {bad}")
                } else {
                    l.to_string()
                }
            })
            .collect::<Vec<_>>()
            .join("\n");
        std::fs::write(dir.path().join("lab.csv"), text).unwrap();
        let o = within(
            dir.path(),
            &["diagnose", "--data", "lab.csv"],
            &[],
            Duration::from_secs(60),
        );
        refused(&o, &["lab.csv", &format!("`{key}`")]);
    }
}

#[test]
fn a_file_name_prints_as_spelled_not_as_the_papers_symbols() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv"),
        dir.path().join("lambda pi.csv"),
    )
    .unwrap();
    // `lambda pi.csv` printed as `λ π.csv`, a file that does not exist.
    for args in [&["init", "--data", "lambda pi.csv"][..], &["steps"]] {
        let o = within(dir.path(), args, &[], Duration::from_secs(120));
        assert!(o.status.success(), "{}", stderr(&o));
        let out = stdout(&o);
        assert!(out.contains("lambda pi.csv"), "{args:?}: {out}");
        assert!(!out.contains("λ π.csv"), "{args:?}: {out}");
    }
}

#[test]
fn inits_first_line_is_wrapped_at_a_narrow_terminal() {
    let dir = tempfile::tempdir().unwrap();
    let name = format!("{}.csv", "long-name-".repeat(5));
    std::fs::copy(
        concat!(env!("CARGO_MANIFEST_DIR"), "/data/paper.csv"),
        dir.path().join(&name),
    )
    .unwrap();
    let out = on_terminal(dir.path(), &["init", "--data", &name], 40);
    let first: Vec<&str> = out.lines().take(2).collect();
    assert!(first[0].starts_with("started the study"), "{out}");
    // Wrapped at the terminal's 40 columns (the name breaks onto the next line).
    for l in out.lines().take_while(|l| !l.starts_with("data:")) {
        assert!(l.chars().count() <= 40, "{l:?} in\n{out}");
    }
    assert!(
        out.replace(char::is_whitespace, "").contains(&name),
        "{out}"
    );
}

/// The binary's stdout on a pseudo-terminal `cols` columns wide.
fn on_terminal(dir: &Path, args: &[&str], cols: u16) -> String {
    use std::io::Read;
    use std::os::fd::FromRawFd;
    let (mut master, mut slave) = (0, 0);
    let size = libc::winsize {
        ws_row: 50,
        ws_col: cols,
        ws_xpixel: 0,
        ws_ypixel: 0,
    };
    // SAFETY: out-pointers to two descriptors and a valid winsize.
    let r = unsafe {
        libc::openpty(
            &mut master,
            &mut slave,
            std::ptr::null_mut(),
            std::ptr::null(),
            &size,
        )
    };
    assert_eq!(r, 0);
    // SAFETY: openpty returned two open descriptors this function owns.
    let (master, slave) = unsafe {
        (
            std::fs::File::from_raw_fd(master),
            std::fs::File::from_raw_fd(slave),
        )
    };
    let mut child = crate::common::command()
        .args(args)
        .current_dir(dir)
        .env("NO_COLOR", "1")
        .stdout(slave)
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let mut out = Vec::new();
    let mut buf = [0u8; 4096];
    let mut master = master;
    // The slave closes when the child exits: the read then fails (EIO).
    while let Ok(n) = master.read(&mut buf) {
        if n == 0 {
            break;
        }
        out.extend_from_slice(&buf[..n]);
    }
    assert!(child.wait().unwrap().success());
    String::from_utf8_lossy(&out).replace("\r\n", "\n")
}

#[test]
fn a_tube_outside_the_data_limits_is_refused_naming_tubes_mm() {
    let dir = study();
    // Named the field `rate` before: every run failed the tube's limit.
    let o = within(
        dir.path(),
        &["plan", "--tubes-mm=1e308", "-o", "p.csv"],
        &[],
        Duration::from_secs(120),
    );
    refused(&o, &["--tubes-mm", "data limits"]);
    assert!(!dir.path().join("p.csv").exists());
}
