//! `cargo xtask hil`: the on-target checks (`firmware/src/hil.rs`) on a
//! board attached through a debug probe. With no probe (or no probe-rs)
//! it says it skipped and succeeds, so CI without hardware passes; with
//! one it builds the `hil` image, runs it with `probe-rs run` (which
//! prints the checks' defmt lines and returns the image's semihosting exit
//! code) and fails if a check failed. The plain image is rebuilt after, so
//! `cargo fw`'s path never keeps the test image.
//!
//! Then the plain image is flashed (`probe-rs download`, `probe-rs reset`)
//! and checked from the host's side of its USB cable (Linux: sysfs and
//! `stty`): the port enumerates within 5 s with the serial number's domain
//! prefix (`board::USB_SERIAL_DOMAIN`), and `INFO` answers one line with
//! the log's and the robot's fields. The board's USB cable must be in the
//! host running this. Not yet checked here: the gate-low time after an
//! injected panic, hang and stack overflow, which needs the jig of
//! firmware/README.md's bring-up checklist (GPIO16 looped back to a spare
//! input, GPIO17) and the `fault-test` image; the emulator measures it
//! (scenario 6).

use std::path::Path;
use std::process::Command;

const CHIP: &str = "RP2040";
const ELF: &str = "target/thumbv6m-none-eabi/fw/firmware";
const HIL_ELF: &str = "target/hil/firmware-hil.elf";

pub fn run(root: &Path) -> Result<(), String> {
    match probes() {
        Probes::NoTool(why) => {
            println!("hil: skipped: no probe ({why})");
            return Ok(());
        }
        Probes::None => {
            println!("hil: skipped: no probe (`probe-rs list` found none)");
            return Ok(());
        }
        Probes::Some(list) => println!("hil: probes:\n{list}"),
    }
    let built = build_hil_image(root);
    // The plain image back in place whatever happened above.
    super::run(root, "cargo", &["fw"])?;
    built?;
    println!("hil: running {HIL_ELF} on the {CHIP} (motor disconnected!)");
    super::run(root, "probe-rs", &["run", "--chip", CHIP, HIL_ELF])
        .map_err(|e| format!("on-target checks failed: {e}"))?;
    println!("hil: flashing the plain image for the USB checks");
    super::run(root, "probe-rs", &["download", "--chip", CHIP, ELF])?;
    super::run(root, "probe-rs", &["reset", "--chip", CHIP])?;
    usb_checks()
}

/// The domain the firmware's serial number starts with.
const SERIAL_DOMAIN: &str = swimbot_shared::board::USB_SERIAL_DOMAIN;

/// The board's port: a ttyACM whose USB serial starts with the domain.
fn find_port() -> Option<(String, String)> {
    let entries = std::fs::read_dir("/sys/class/tty").ok()?;
    for e in entries.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if !name.starts_with("ttyACM") {
            continue;
        }
        // ttyACMn/device is the interface; its parent the USB device.
        let serial = e.path().join("device/../serial");
        if let Ok(s) = std::fs::read_to_string(serial) {
            let s = s.trim().to_string();
            if s.starts_with(&format!("{SERIAL_DOMAIN}:")) {
                return Some((format!("/dev/{name}"), s));
            }
        }
    }
    None
}

/// The port enumerates and answers `INFO` with every field.
fn usb_checks() -> Result<(), String> {
    let start = std::time::Instant::now();
    let (port, serial) = loop {
        if let Some(found) = find_port() {
            break found;
        }
        if start.elapsed() > std::time::Duration::from_secs(5) {
            return Err(format!(
                "hil: no ttyACM port with serial {SERIAL_DOMAIN}:... within 5 s (is the USB cable in this host?)"
            ));
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    };
    println!(
        "hil: USB enumerated in {:.1} s: {port} serial {serial}",
        start.elapsed().as_secs_f64()
    );
    // Raw, no echo, reads return after 3 s of silence.
    super::run(
        std::path::Path::new("/"),
        "stty",
        &["-F", &port, "raw", "-echo", "min", "0", "time", "30"],
    )?;
    use std::io::{Read, Write};
    let mut tty = std::fs::OpenOptions::new()
        .read(true)
        .write(true)
        .open(&port)
        .map_err(|e| format!("{port}: {e}"))?;
    tty.write_all(b"INFO\n").map_err(|e| format!("{port}: {e}"))?;
    let mut line = Vec::new();
    let mut byte = [0u8; 1];
    while !line.ends_with(b"\n") {
        match tty.read(&mut byte) {
            Ok(1) => line.push(byte[0]),
            Ok(_) => return Err(format!("{port}: INFO not answered within 3 s")),
            Err(e) => return Err(format!("{port}: {e}")),
        }
    }
    let text = String::from_utf8_lossy(&line);
    println!("hil: INFO: {}", text.trim_end());
    let missing: Vec<&str> = ["fw=", "commit=", "battery_mv=", "fault=", "pairing="]
        .into_iter()
        .filter(|f| !text.contains(f))
        .collect();
    if !text.starts_with("swimbot-log v2 ") || !missing.is_empty() {
        return Err(format!("{port}: INFO line malformed (missing {missing:?})"));
    }
    Ok(())
}

enum Probes {
    NoTool(String),
    None,
    Some(String),
}

/// What `probe-rs list` sees: a line per probe, `[0]: ...`.
fn probes() -> Probes {
    let out = match Command::new("probe-rs").arg("list").output() {
        Ok(out) => out,
        Err(e) => return Probes::NoTool(format!("`probe-rs` not runnable: {e}")),
    };
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let found: Vec<&str> = text
        .lines()
        .filter(|l| l.trim_start().starts_with('['))
        .collect();
    if !out.status.success() && found.is_empty() {
        return Probes::NoTool(format!(
            "`probe-rs list` failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    if found.is_empty() {
        Probes::None
    } else {
        Probes::Some(found.join("\n"))
    }
}

fn build_hil_image(root: &Path) -> Result<(), String> {
    super::run(
        root,
        "cargo",
        &[
            "build",
            "-p",
            "firmware",
            "--target",
            "thumbv6m-none-eabi",
            "--profile",
            "fw",
            "--features",
            "hil",
        ],
    )?;
    let dir = root.join("target/hil");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    std::fs::copy(root.join(ELF), root.join(HIL_ELF))
        .map(|_| ())
        .map_err(|e| format!("{ELF} -> {HIL_ELF}: {e}"))
}
