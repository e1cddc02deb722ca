//! `cargo xtask hil`: the on-target checks (`firmware/src/hil.rs`) on a
//! board attached through a debug probe. With no probe (or no probe-rs)
//! it says it skipped and succeeds, so CI without hardware passes; with
//! one it builds the `hil` image, runs it with `probe-rs run` (which
//! prints the checks' defmt lines and returns the image's semihosting exit
//! code) and fails if a check failed. The plain image is rebuilt after, so
//! `cargo fw`'s path never keeps the test image.
//!
//! Then the plain image is flashed (`probe-rs download`, `probe-rs reset`)
//! and checked from the host's side of its USB cable (Linux: sysfs finds
//! the port, the `serialport` crate talks to it): the port enumerates
//! within 5 s with the serial number's domain prefix
//! (`board::USB_SERIAL_DOMAIN`), and `INFO` answers one line with the log's
//! and the robot's fields. The board's USB cable must be in the host
//! running this.
//!
//! Last, the fail-safe timing on the jig (firmware/README.md, "Fail-safe
//! timing on the jig": motor disconnected, GPIO16 wired to GPIO17): the
//! `hil-faults` image is flashed, and for a panic, a hang and a stack
//! overflow in turn `FAULT <KIND>` is sent, the board resets, re-enumerates
//! and answers `FAULT RESULT` with the time from the injection to the
//! gate's last fall, which `hil_check::judge` holds to its bound (1 ms for
//! the panic; the 80 ms watchdog, one pass and one PWM period for the
//! others). The plain image is flashed back whatever the outcome.

use std::path::Path;
use std::process::Command;

const CHIP: &str = "RP2040";
const ELF: &str = "target/thumbv6m-none-eabi/fw/firmware";
const HIL_ELF: &str = "target/hil/firmware-hil.elf";
const FAULTS_ELF: &str = "target/hil/firmware-hil-faults.elf";

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
    let built = build_image(root, "hil", HIL_ELF).and(build_image(root, "hil-faults", FAULTS_ELF));
    // The plain image back in place whatever happened above.
    super::run(root, "cargo", &["fw"])?;
    built?;
    println!("hil: running {HIL_ELF} on the {CHIP} (motor disconnected!)");
    super::run(root, "probe-rs", &["run", "--chip", CHIP, HIL_ELF])
        .map_err(|e| format!("on-target checks failed: {e}"))?;
    println!("hil: flashing the plain image for the USB checks");
    super::run(root, "probe-rs", &["download", "--chip", CHIP, ELF])?;
    super::run(root, "probe-rs", &["reset", "--chip", CHIP])?;
    usb_checks()?;
    println!("hil: flashing the hil-faults image (jig: motor disconnected, GPIO16 wired to GPIO17)");
    super::run(root, "probe-rs", &["download", "--chip", CHIP, FAULTS_ELF])?;
    super::run(root, "probe-rs", &["reset", "--chip", CHIP])?;
    let timed = fault_checks();
    println!("hil: flashing the plain image back");
    super::run(root, "probe-rs", &["download", "--chip", CHIP, ELF])?;
    super::run(root, "probe-rs", &["reset", "--chip", CHIP])?;
    timed
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

/// The board's port, waited for up to 5 s.
fn wait_for_port() -> Result<(String, String, f64), String> {
    let start = std::time::Instant::now();
    loop {
        if let Some((port, serial)) = find_port() {
            return Ok((port, serial, start.elapsed().as_secs_f64()));
        }
        if start.elapsed() > std::time::Duration::from_secs(5) {
            return Err(format!(
                "hil: no ttyACM port with serial {SERIAL_DOMAIN}:... within 5 s (is the USB cable in this host?)"
            ));
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
}

/// Send `request` on `port` and read one answer line (3 s of silence ends it).
fn ask(port: &str, request: &str) -> Result<String, String> {
    use std::io::{Read, Write};
    let mut tty = serialport::new(port, 115_200)
        .timeout(std::time::Duration::from_secs(3))
        .open()
        .map_err(|e| format!("{port}: {e}"))?;
    tty.write_all(request.as_bytes())
        .map_err(|e| format!("{port}: {e}"))?;
    let mut line = Vec::new();
    let mut byte = [0u8; 1];
    while !line.ends_with(b"\n") {
        match tty.read(&mut byte) {
            Ok(1) => line.push(byte[0]),
            Ok(_) => return Err(format!("{port}: {:?} not answered", request.trim_end())),
            Err(e) => return Err(format!("{port}: {:?}: {e}", request.trim_end())),
        }
    }
    Ok(String::from_utf8_lossy(&line).into_owned())
}

/// The port enumerates and answers `INFO` with every field.
fn usb_checks() -> Result<(), String> {
    let (port, serial, secs) = wait_for_port()?;
    println!("hil: USB enumerated in {secs:.1} s: {port} serial {serial}");
    let text = ask(&port, "INFO\n")?;
    println!("hil: INFO: {}", text.trim_end());
    crate::hil_check::check_info(&text).map_err(|e| format!("{port}: {e}"))
}

/// Each fault injected in turn; the gate's fall after it, judged.
fn fault_checks() -> Result<(), String> {
    use crate::hil_check::{judge, parse_result, Fault};
    let mut failed = Vec::new();
    for fault in Fault::ALL {
        let (port, _, _) = wait_for_port()?;
        let answer = ask(&port, fault.request())?;
        if answer.trim_end() != "OK FAULT" {
            return Err(format!("{port}: {:?} answered {answer:?}", fault.request().trim_end()));
        }
        // The image injects 120 ms after its answer, then resets; the port
        // goes and comes back.
        std::thread::sleep(std::time::Duration::from_millis(1_500));
        let (port, _, secs) = wait_for_port()?;
        let result = ask(&port, "FAULT RESULT\n")?;
        match parse_result(&result).and_then(|r| judge(fault, &r)) {
            Ok(us) => println!(
                "hil: ok   {fault:?}: gate low {us} us after the injection (bound {} us; back on USB in {secs:.1} s)",
                fault.bound_us()
            ),
            Err(e) => {
                println!("hil: FAIL {fault:?}: {e}");
                failed.push(fault);
            }
        }
    }
    if failed.is_empty() {
        Ok(())
    } else {
        Err(format!("fail-safe timing failed for {failed:?}"))
    }
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

/// The firmware built with `feature`, copied to `to` (`cargo fw`'s path is
/// restored by the caller).
fn build_image(root: &Path, feature: &str, to: &str) -> Result<(), String> {
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
            feature,
        ],
    )?;
    let dir = root.join("target/hil");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    std::fs::copy(root.join(ELF), root.join(to))
        .map(|_| ())
        .map_err(|e| format!("{ELF} -> {to}: {e}"))
}
