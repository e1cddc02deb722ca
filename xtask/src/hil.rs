//! `cargo xtask hil`: the on-target checks (`firmware/src/hil.rs`) on a
//! board attached through a debug probe. With no probe (or no probe-rs)
//! it says it skipped and succeeds, so CI without hardware passes; with
//! one it builds the `hil` image, runs it with `probe-rs run` (which
//! prints the checks' defmt lines and returns the image's semihosting exit
//! code) and fails if a check failed. The plain image is rebuilt after, so
//! `cargo fw`'s path never keeps the test image.

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
        .map_err(|e| format!("on-target checks failed: {e}"))
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
