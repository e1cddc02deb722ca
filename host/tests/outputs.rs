//! Outputs through the real binary, on private nodes in a
//! temporary folder: a symbolic link is followed to its file, a FIFO is
//! written through, an output that is an input is refused, a full device is
//! exit 2 (`/dev/full`, only read... and written, never replaced), and
//! SIGINT / SIGTERM leave no temporary file and no new folder.

use crate::common::run_in;
use crate::common::stderr;
use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

const SMALL_SWEEP: [&str; 7] = [
    "sweep",
    "--wavelength-mm",
    "10:20:5",
    "--amplitude-mm",
    "2",
    "--tail-length-mm",
    "100",
];

fn sweep_to(dir: &Path, out: &str) -> Output {
    let mut args = SMALL_SWEEP.to_vec();
    args.extend(["-o", out]);
    run_in(dir, &args)
}

#[test]
fn a_symlink_is_followed_and_stays_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("real.csv"), "old").unwrap();
    std::os::unix::fs::symlink("real.csv", d.join("link.csv")).unwrap();
    let o = sweep_to(d, "link.csv");
    assert!(o.status.success(), "{}", stderr(&o));
    let meta = std::fs::symlink_metadata(d.join("link.csv")).unwrap();
    assert!(meta.file_type().is_symlink(), "the link was replaced");
    let text = std::fs::read_to_string(d.join("real.csv")).unwrap();
    let table: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
    assert!(
        table[0].starts_with("wavelength_mm,") && table.len() == 6,
        "{text}"
    );
    // A dangling link is refused, naming the output.
    std::os::unix::fs::symlink("nowhere/x.csv", d.join("dangling.csv")).unwrap();
    let o = sweep_to(d, "dangling.csv");
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("dangling.csv"), "{}", stderr(&o));
}

#[test]
fn a_fifo_is_written_through_not_replaced() {
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("pipe");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let o = sweep_to(dir.path(), "pipe");
    assert!(o.status.success(), "{}", stderr(&o));
    let text = reader.join().unwrap();
    // the provenance block, then the header and five rows
    let table = text.lines().filter(|l| !l.starts_with('#')).count();
    assert_eq!(table, 6, "{text}");
    use std::os::unix::fs::FileTypeExt;
    let t = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(t.is_fifo(), "the FIFO was replaced by a file");
}

#[test]
fn an_output_that_is_an_input_is_refused_before_the_work() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let paper = swimbot::data::to_toml(&swimbot::data::paper());
    std::fs::write(d.join("data.toml"), &paper).unwrap();
    std::os::unix::fs::symlink("data.toml", d.join("alias.toml")).unwrap();
    for out in ["data.toml", "./data.toml", "alias.toml"] {
        let o = run_in(
            d,
            &["diagnose", "--data", "data.toml", "--write-effect", out],
        );
        assert_eq!(o.status.code(), Some(2), "{out}: {}", stderr(&o));
        assert!(stderr(&o).contains("also an input"), "{}", stderr(&o));
        assert!(o.stdout.is_empty(), "work was done before the refusal");
    }
    assert_eq!(std::fs::read_to_string(d.join("data.toml")).unwrap(), paper);
}

#[test]
fn a_full_device_is_exit_2_on_every_path() {
    let dir = tempfile::tempdir().unwrap();
    let full = std::fs::File::options()
        .write(true)
        .open("/dev/full")
        .unwrap();
    let mut args = SMALL_SWEEP.to_vec();
    args.extend(["-o", "/dev/full"]);
    for (what, args, stdout) in [
        ("sweep -o /dev/full", args.clone(), Stdio::null()),
        (
            "sweep > /dev/full",
            SMALL_SWEEP.to_vec(),
            Stdio::from(full.try_clone().unwrap()),
        ),
        (
            "effects > /dev/full",
            vec!["effects"],
            Stdio::from(full.try_clone().unwrap()),
        ),
        (
            "compare --format csv > /dev/full",
            vec!["compare", "--no-report", "--format", "csv"],
            Stdio::from(full.try_clone().unwrap()),
        ),
    ] {
        let o = crate::common::command()
            .args(&args)
            .current_dir(dir.path())
            .stdout(stdout)
            .output()
            .unwrap();
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{what}: {err}");
        assert!(
            err.contains("No space left") && !err.contains("panicked"),
            "{what}: {err}"
        );
    }
    // /dev/full is still a character device (written through, never replaced).
    use std::os::unix::fs::FileTypeExt;
    assert!(std::fs::metadata("/dev/full")
        .unwrap()
        .file_type()
        .is_char_device());
}

/// Start `args`, wait until `ready` holds, send `signal`, wait for the end.
fn interrupt(dir: &Path, args: &[&str], ready: impl Fn() -> bool, signal: i32) -> bool {
    let mut child = crate::common::command()
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !ready() {
        if child.try_wait().unwrap().is_some() || start.elapsed() > Duration::from_secs(60) {
            return false;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    // SAFETY: kill(2) on our own child's pid.
    unsafe { libc::kill(child.id() as i32, signal) };
    use std::os::unix::process::ExitStatusExt;
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(signal), "{status:?}");
    true
}

#[test]
fn sigint_and_sigterm_leave_no_temporary_file_and_no_new_folder() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path().to_path_buf();
    // A new folder, interrupted while the report is being computed.
    let seen = interrupt(
        &d,
        &["report", "-o", "new/deep/report"],
        || d.join("new/deep/report").exists(),
        libc::SIGINT,
    );
    assert!(seen, "the report ended before its folder was seen");
    assert!(!d.join("new").exists(), "the new folders were left behind");
    // A temporary file, interrupted while the CSV is written.
    let temp_seen = || {
        std::fs::read_dir(&d)
            .unwrap()
            .flatten()
            .any(|e| e.file_name().to_string_lossy().starts_with(".big.csv.tmp-"))
    };
    let args = [
        "sweep",
        "--wavelength-mm",
        "10:20:500",
        "--amplitude-mm",
        "2:3:300",
        "--tail-length-mm",
        "100",
        "-o",
        "big.csv",
    ];
    assert!(
        interrupt(&d, &args, temp_seen, libc::SIGTERM),
        "the sweep ended first"
    );
    let left: Vec<_> = std::fs::read_dir(&d)
        .unwrap()
        .flatten()
        .map(|e| e.file_name())
        .collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}

/// `diagnose --write-effect F | head -n 3`: the file the user asked for is
/// written before stdout is touched, so a reader that closed the pipe at
/// once (the process then ends quietly at its first line) still leaves F.
#[cfg(unix)]
#[test]
fn the_asked_for_file_is_written_before_a_closed_stdout_ends_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let found = dir.path().join("found.toml");
    let mut child = crate::common::command()
        .args(["diagnose", "--quiet", "--write-effect"])
        .arg(&found)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader is gone before the first line
    let out = child.wait_with_output().unwrap();
    let text = std::fs::read_to_string(&found).unwrap_or_else(|e| {
        panic!(
            "{} not written ({e}); stderr: {}",
            found.display(),
            String::from_utf8_lossy(&out.stderr)
        )
    });
    assert!(text.contains("[[effect]]"), "{text}");
}

/// A private character device (a null and a full device made with mknod
/// in the temporary folder; root only, where a replaced output would
/// destroy `/dev/null`): every kind of output names it, it stays a character
/// device, and the full one is exit 2 with nothing else left behind.
#[test]
fn private_character_devices_are_written_through_and_stay_devices() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let made = |name: &str, minor: &str| {
        Command::new("mknod")
            .args([d.join(name).to_str().unwrap(), "c", "1", minor])
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    };
    if !(made("null", "3") && made("full", "7")) {
        println!("mknod refused (not root, or no CAP_MKNOD): private devices not tested here");
        return;
    }
    let paper = swimbot::data::to_toml(&swimbot::data::paper());
    std::fs::write(d.join("data.toml"), &paper).unwrap();
    let runs: [&[&str]; 4] = [
        &[
            "sweep",
            "--wavelength-mm",
            "10:20:5",
            "--amplitude-mm",
            "2",
            "--tail-length-mm",
            "100",
            "-o",
            "DEV",
        ],
        &["synth", "--truth", "paper", "-o", "DEV"],
        &["convert", "data.toml", "-o", "DEV"],
        &[
            "diagnose",
            "--data",
            "data.toml",
            "--no-pairs",
            "--write-effect",
            "DEV",
        ],
    ];
    use std::os::unix::fs::FileTypeExt;
    for args in runs {
        for (dev, ok) in [("null", true), ("full", false)] {
            let args: Vec<&str> = args
                .iter()
                .map(|a| if *a == "DEV" { dev } else { a })
                .collect();
            let o = run_in(d, &args);
            let err = stderr(&o);
            if ok {
                assert!(o.status.success(), "{args:?}: {err}");
            } else {
                assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
                assert!(
                    err.contains("No space left") && err.contains(dev),
                    "{args:?}: {err}"
                );
            }
            let t = std::fs::symlink_metadata(d.join(dev)).unwrap().file_type();
            assert!(t.is_char_device(), "{args:?}: {dev} was replaced");
        }
    }
    let mut left: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(left, ["data.toml", "full", "null"], "files left behind");
    assert_eq!(std::fs::read_to_string(d.join("data.toml")).unwrap(), paper);
}

/// A report re-run into its own folder removes the figures and tables the
/// previous run's manifest lists, and nothing else: a user's files in
/// `figures/` and `tables/` stay (the whole folders were deleted before),
/// and a manifest entry pointing out of them (`../`) removes nothing.
#[test]
fn a_report_rerun_removes_only_what_its_manifest_lists() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let report = || run_in(d, &["report", "-q", "--no-physics", "-o", "rep"]);
    let o = report();
    assert!(o.status.success(), "{}", stderr(&o));
    let rep = d.join("rep");
    std::fs::write(rep.join("tables/mine.txt"), "notes").unwrap();
    std::fs::write(rep.join("figures/drawing.svg"), "<svg/>").unwrap();
    std::fs::write(rep.join("tables/stale.csv"), "old").unwrap();
    std::fs::write(d.join("victim.txt"), "keep").unwrap();
    let manifest = std::fs::read_to_string(rep.join("manifest.json")).unwrap();
    let manifest = manifest.replacen(
        "\"files\": [",
        "\"files\": [{\"file\": \"tables/stale.csv\"}, {\"file\": \"tables/../../victim.txt\"}, {\"file\": \"../victim.txt\"},",
        1,
    );
    std::fs::write(rep.join("manifest.json"), manifest).unwrap();
    let o = report();
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        rep.join("tables/mine.txt").exists(),
        "a user's table was deleted"
    );
    assert!(
        rep.join("figures/drawing.svg").exists(),
        "a user's figure was deleted"
    );
    assert!(
        !rep.join("tables/stale.csv").exists(),
        "a stale table stayed"
    );
    assert_eq!(
        std::fs::read_to_string(d.join("victim.txt")).unwrap(),
        "keep"
    );
    assert!(rep.join("index.html").exists());
}

/// Every way a command prints (`println!`, the CSV writer, `compare`'s CSV,
/// the final flush) ends with exit 0 and nothing on stderr when the reader
/// is gone before the first line, as `sweep | head` does (`cli.rs`), rather
/// than a death by SIGPIPE, met only by commands printing more than a
/// pipe buffer holds.
#[cfg(unix)]
#[test]
fn a_closed_stdout_ends_every_kind_of_printing_with_exit_0() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["compare", "--no-report"][..],
        &["compare", "--no-report", "--format", "csv"],
        &["diagnose", "--format", "csv"],
        &["effects"],
        &SMALL_SWEEP,
    ] {
        let mut child = crate::common::command()
            .args(args)
            .arg("--quiet")
            .current_dir(dir.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        assert_eq!(out.status.code(), Some(0), "{args:?}: {:?}", out.status);
        assert!(out.stderr.is_empty(), "{args:?}: {}", stderr(&out));
    }
}

/// A dataset kept in the report's folder under a name the bundle writes
/// (`tables/paper-1.csv`) is an input: the report refuses it (exit 2)
/// before writing or removing any file, fresh or over its own earlier page.
#[test]
fn a_report_refuses_to_overwrite_an_input_in_its_bundle() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let data = swimbot::data::paper();
    std::fs::create_dir_all(d.join("rep/tables")).unwrap();
    let input = d.join("rep/tables/paper-1.csv");
    std::fs::write(d.join("paper.toml"), swimbot::data::to_toml(&data)).unwrap();
    let o = run_in(
        d,
        &[
            "convert",
            "-q",
            "paper.toml",
            "-o",
            "rep/tables/paper-1.csv",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let before = std::fs::read(&input).unwrap();
    let report = || {
        run_in(
            d,
            &[
                "report",
                "-q",
                "--no-physics",
                "-o",
                "rep",
                "--data",
                "rep/tables/paper-1.csv",
            ],
        )
    };
    let o = report();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("paper-1.csv") && stderr(&o).contains("is also an input"),
        "{}",
        stderr(&o)
    );
    assert_eq!(std::fs::read(&input).unwrap(), before);
    assert!(!d.join("rep/index.html").exists(), "a page was written");
    // Over an earlier page whose manifest lists that table (to be removed).
    let o = run_in(d, &["report", "-q", "--no-physics", "-o", "rep2"]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::copy(&input, d.join("rep2/tables/paper-1.csv")).unwrap();
    let o = run_in(
        d,
        &[
            "report",
            "-q",
            "--no-physics",
            "-o",
            "rep2",
            "--data",
            "rep2/tables/paper-1.csv",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert_eq!(
        std::fs::read(d.join("rep2/tables/paper-1.csv")).unwrap(),
        before
    );
}

/// A closed stderr (a note printed after the work, `report`'s "wrote ...")
/// is exit 2, never a panic (exit 101) nor a death by SIGPIPE.
#[cfg(unix)]
#[test]
fn a_closed_stderr_is_exit_2_not_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut child = crate::common::command()
        .args(["report", "--no-physics", "-o", "rep"])
        .current_dir(dir.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stderr.take());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(2), "{status:?}");
}
