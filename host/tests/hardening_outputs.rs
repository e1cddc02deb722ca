//! Outputs never destroy or mix the user's data, through the binary: an
//! input inside an output folder is refused; the report's bundle is
//! replaced all-or-none (a full disk, a kill at any moment); an output
//! folder another command wrote is refused; a closed stdout is an error;
//! SIGHUP and killed runs leave no temporary file behind the next run.

use crate::common::{stderr, stdout, swimbot, write_simulated_log};
use std::path::Path;
use std::process::Command;

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

#[test]
fn an_input_inside_the_output_folder_is_refused_naming_both() {
    let dir = tempfile::tempdir().unwrap();
    let log = dir.path().join("base.swlog");
    write_simulated_log(&log, &dir.path().join("sim"));
    let l = dir.path().join("L");
    let o = swimbot(&["log", s(&log), "--case", "tail-3", "-o", s(&l)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let trials = l.join("trials.toml");
    let before = std::fs::read(&trials).unwrap();
    // The dataset it just wrote, read back as --data into the same folder.
    let o = swimbot(&[
        "log",
        s(&log),
        "--case",
        "tail-3@0.600Hz",
        "--data",
        s(&trials),
        "-o",
        s(&l),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains(s(&l)) && e.contains("trials.toml"), "{e}");
    assert_eq!(
        std::fs::read(&trials).unwrap(),
        before,
        "the input is intact"
    );
    // Through a symbolic link to the folder, and for `sim`'s inputs alike.
    let link = dir.path().join("link");
    std::os::unix::fs::symlink(&l, &link).unwrap();
    let moved = l.join("run.swlog");
    std::fs::copy(&log, &moved).unwrap();
    for args in [
        vec![
            "sim",
            "--tail",
            "3",
            "--set-points-from",
            s(&moved),
            "-o",
            s(&link),
        ],
        vec!["log", s(&moved), "-o", s(&l)],
    ] {
        let o = swimbot(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains("run.swlog"), "{}", stderr(&o));
    }
    assert_eq!(std::fs::read(&trials).unwrap(), before);
    // An output file named beside the folder is no input: allowed.
    let sim = dir.path().join("S");
    let again = sim.join("run.swlog");
    write_simulated_log(&again, &sim);
    write_simulated_log(&again, &sim);
}

/// Each file the manifest lists has the SHA-256 it records.
fn bundle_is_whole(dir: &Path) -> Result<usize, String> {
    let text = std::fs::read_to_string(dir.join("manifest.json")).map_err(|e| e.to_string())?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| e.to_string())?;
    let files = v["files"].as_array().ok_or("no files")?;
    for f in files {
        let rel = f["file"].as_str().ok_or("no name")?;
        let bytes = std::fs::read(dir.join(rel)).map_err(|e| format!("{rel}: {e}"))?;
        if swimbot::provenance::sha256_hex(&bytes) != f["sha256"].as_str().unwrap_or("") {
            return Err(format!("{rel}: not the file the manifest lists"));
        }
    }
    Ok(files.len())
}

fn leftovers(parent: &Path) -> Vec<String> {
    walk(parent)
        .into_iter()
        .filter(|n| {
            n.contains(".tmp-") || n.contains(".swimbot-staging") || n.contains(".swimbot-old")
        })
        .collect()
}

fn walk(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        out.push(e.path().display().to_string());
        if e.file_type().unwrap().is_dir() {
            out.extend(walk(&e.path()));
        }
    }
    out
}

#[test]
fn the_manifest_records_each_written_files_sha256() {
    let dir = tempfile::tempdir().unwrap();
    let r = dir.path().join("R");
    let o = swimbot(&["compare", "-o", s(&r)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let n = bundle_is_whole(&r).unwrap();
    assert!(n > 5, "the page, figures and tables: {n}");
}

#[test]
#[cfg_attr(
    not(debug_assertions),
    ignore = "the full disk is simulated in debug builds only (atomic_dir::fault_injection)"
)]
fn a_full_disk_leaves_the_old_bundle_whole() {
    let dir = tempfile::tempdir().unwrap();
    let r = dir.path().join("R");
    let o = swimbot(&["compare", "-o", s(&r)]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(r.join("notes.txt"), "mine").unwrap();
    let before = std::fs::read(r.join("manifest.json")).unwrap();
    // A different page (another model), on a disk that fills mid-bundle.
    let o = crate::common::command()
        .args(["compare", "--preset", "paper", "-o", s(&r)])
        .env("SWIMBOT_FAULT_DISK_FULL_AFTER_BYTES", "60000")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("No space left"), "{}", stderr(&o));
    assert_eq!(std::fs::read(r.join("manifest.json")).unwrap(), before);
    bundle_is_whole(&r).unwrap();
    assert_eq!(
        std::fs::read_to_string(r.join("notes.txt")).unwrap(),
        "mine"
    );
    assert!(
        leftovers(dir.path()).is_empty(),
        "{:?}",
        leftovers(dir.path())
    );
    // With room, the new bundle replaces it whole, the user's file kept.
    let o = swimbot(&["compare", "--preset", "paper", "-o", s(&r)]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(std::fs::read(r.join("manifest.json")).unwrap(), before);
    bundle_is_whole(&r).unwrap();
    assert_eq!(
        std::fs::read_to_string(r.join("notes.txt")).unwrap(),
        "mine"
    );
}

/// A run killed outright (SIGKILL) between creating and removing its
/// folder probe or its marker's temporary file leaves them; the next run
/// into the folder removes them (those of a live process stay).
#[test]
fn the_next_run_sweeps_what_a_killed_run_left_in_the_folder() {
    let dir = tempfile::tempdir().unwrap();
    let r = dir.path().join("R");
    let o = swimbot(&["compare", "-o", s(&r)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let mut gone = Command::new("true").spawn().unwrap();
    gone.wait().unwrap();
    let dead = gone.id();
    let alive = std::process::id();
    for name in [".probe.tmp-", "..swimbot-output.tmp-"] {
        std::fs::write(r.join(format!("{name}{dead}")), "").unwrap();
    }
    std::fs::write(r.join(format!(".probe.tmp-{alive}")), "").unwrap();
    let o = swimbot(&["compare", "-o", s(&r)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let left = leftovers(dir.path());
    assert_eq!(left.len(), 1, "{left:?}");
    assert!(
        left[0].ends_with(&format!(".probe.tmp-{alive}")),
        "{left:?}"
    );
}

#[test]
fn a_killed_report_leaves_the_old_bundle_or_the_new_one() {
    let dir = tempfile::tempdir().unwrap();
    let r = dir.path().join("R");
    let o = swimbot(&["compare", "-o", s(&r)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let start = std::time::Instant::now();
    let mut run = crate::common::command()
        .args(["compare", "--preset", "paper", "-o", s(&r)])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    run.wait().unwrap();
    let full = start.elapsed();
    // Kills spread over the run's length, by SIGTERM and SIGKILL.
    let mut killed = Vec::new();
    for k in 0..8u32 {
        let at = full.mul_f64(f64::from(k) / 8.0 + 0.05);
        let mut run = crate::common::command()
            .args([
                "compare",
                "--preset",
                if k % 2 == 0 { "base" } else { "paper" },
                "-o",
                s(&r),
            ])
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(at);
        let sig = if k % 3 == 0 {
            libc::SIGKILL
        } else {
            libc::SIGTERM
        };
        // SAFETY: signalling our own child.
        unsafe { libc::kill(run.id() as i32, sig) };
        if sig == libc::SIGKILL {
            killed.push(format!("-{}", run.id()));
        }
        run.wait().unwrap();
        bundle_is_whole(&r).unwrap_or_else(|e| panic!("kill {k} at {at:?}: {e}"));
        // A SIGTERM cleans up; only a SIGKILLed run may leave its staging
        // folder, until a later run reaches the bundle.
        let left = leftovers(dir.path());
        assert!(
            left.iter()
                .all(|l| killed.iter().any(|pid| l.contains(pid.as_str()))),
            "{left:?}"
        );
    }
    // The next run removes what a SIGKILL left.
    let o = swimbot(&["compare", "-o", s(&r)]);
    assert!(o.status.success(), "{}", stderr(&o));
    bundle_is_whole(&r).unwrap();
    assert!(
        leftovers(dir.path()).is_empty(),
        "{:?}",
        leftovers(dir.path())
    );
}

#[test]
fn a_folder_another_command_wrote_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let sim = dir.path().join("sim");
    let o = swimbot(&["sim", "--max-time-s", "5", "-o", s(&sim)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = swimbot(&["compare", "-o", s(&sim)]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("swimbot sim"), "{}", stderr(&o));
    let r = dir.path().join("R");
    let o = swimbot(&["compare", "-o", s(&r)]);
    assert!(o.status.success(), "{}", stderr(&o));
    let log = dir.path().join("run.swlog");
    write_simulated_log(&log, &dir.path().join("sim2"));
    for (args, who) in [
        (vec!["log", s(&log), "-o", s(&r)], "swimbot compare"),
        (
            vec!["sim", "--max-time-s", "5", "-o", s(&r)],
            "swimbot compare",
        ),
        (vec!["log", s(&log), "-o", s(&sim)], "swimbot sim"),
    ] {
        let o = swimbot(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(who), "{}", stderr(&o));
    }
    // The same command again is fine.
    let o = swimbot(&["sim", "--max-time-s", "5", "-o", s(&sim)]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn a_closed_stdout_is_an_error_and_a_closed_pipe_a_quiet_success() {
    let bin = env!("CARGO_BIN_EXE_swimbot");
    for cmd in [
        "effects",
        "compare --no-report --format json",
        "sweep --wavelength-mm 10 --amplitude-mm 2 --tail-length-mm 20",
    ] {
        let o = Command::new("sh")
            .arg("-c")
            .arg(format!("exec {bin} {cmd} >&-"))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{cmd}: {}", stderr(&o));
        assert!(
            stderr(&o).contains("standard output is closed"),
            "{}",
            stderr(&o)
        );
    }
    // `>/dev/null` is no closed stdout.
    let o = Command::new("sh")
        .arg("-c")
        .arg(format!("exec {bin} effects >/dev/null"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // A reader that stops early (`| head`): a quiet success.
    let mut run = Command::new(bin)
        .args([
            "sweep",
            "-q",
            "--wavelength-mm",
            "5:20:300",
            "--amplitude-mm",
            "1:3:300",
            "--tail-length-mm",
            "20",
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut head = [0u8; 64];
    std::io::Read::read_exact(run.stdout.as_mut().unwrap(), &mut head).unwrap();
    drop(run.stdout.take());
    let o = run.wait_with_output().unwrap();
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).is_empty(), "{}", stderr(&o));
}

#[test]
fn sighup_and_killed_runs_leave_no_temporary_file_behind() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sw.csv");
    // A leftover of a run killed outright (its process is gone).
    let stale = dir.path().join(format!(".sw.csv.tmp-{}", 1 << 23));
    std::fs::write(&stale, "half").unwrap();
    let mut run = crate::common::command()
        .args([
            "sweep",
            "--wavelength-mm",
            "5:20:2000",
            "--amplitude-mm",
            "1:3:2000",
            "--tail-length-mm",
            "20",
            "-o",
            s(&out),
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Signalled while it writes, not after a fixed sleep: a faster sweep
    // had finished 160 000 geometries before a 300 ms sleep ended. Four
    // million take seconds once the temporary file is there.
    let mine = dir.path().join(format!(".sw.csv.tmp-{}", run.id()));
    let start = std::time::Instant::now();
    while !mine.exists() {
        assert!(
            run.try_wait().unwrap().is_none(),
            "the sweep ended before it wrote"
        );
        assert!(
            start.elapsed().as_secs() < 60,
            "no temporary file after 60 s"
        );
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    // SAFETY: signalling our own child.
    unsafe { libc::kill(run.id() as i32, libc::SIGHUP) };
    let status = run.wait().unwrap();
    assert!(!status.success());
    let left: Vec<String> = walk(dir.path())
        .into_iter()
        .filter(|n| n.contains(".tmp-") && !n.ends_with(&format!("{}", 1 << 23)))
        .collect();
    assert!(left.is_empty(), "{left:?}");
    let o = swimbot(&[
        "sweep",
        "--wavelength-mm",
        "5:20:3",
        "--amplitude-mm",
        "2",
        "--tail-length-mm",
        "20",
        "-o",
        s(&out),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stale.exists(), "the dead run's temporary file is removed");
    let _ = stdout(&o);
}
