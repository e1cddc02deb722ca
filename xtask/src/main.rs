//! Project automation. `cargo xtask test` is the README's test command: it runs
//! formatting and lint checks, every host test, the firmware build for
//! `thumbv6m-none-eabi` and the firmware size budget; `cargo xtask size`
//! prints the firmware's flash and static RAM use; `cargo xtask motor-wasm`
//! builds the emulator's motor model (WebAssembly); `cargo xtask uf2` builds
//! the firmware and writes its UF2 (`uf2`), and `cargo xtask flash` copies
//! that to a board in BOOTSEL mode (no debug probe needed).
//!
//! Written as a Rust program rather than a shell script so that the ELF size
//! check reads the section table itself (no cross binutils needed).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

mod background;
mod hil_check;
mod layout;
mod python;
mod size;
mod steps;
mod thermal;
mod uf2;

use background::Background;
use steps::Steps;

/// Flash budget for the firmware image: 128 KiB of the 2 MiB flash, room
/// for the ecosystem's USB stack (usb-device, usbd-serial) beside the run
/// log, pairing, the rate controller and the motor supervisor. The old
/// 32 KiB had no physical basis on a 2 MiB part (firmware/README.md,
/// "Flash and RAM").
const FLASH_BUDGET_BYTES: u64 = 128 * 1024;
/// Static RAM budget, defmt's RTT buffer included (the rest of the 264 KiB
/// is the stack).
const RAM_BUDGET_BYTES: u64 = 16 * 1024;
const FW_ELF: &str = "target/thumbv6m-none-eabi/fw/firmware";
const FW_UF2: &str = "target/thumbv6m-none-eabi/fw/firmware.uf2";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let root = workspace_root();
    let result = match args.first().map(String::as_str) {
        Some("test") => test_all(&root),
        Some("size") => firmware_size(&root, &mut Steps::new()),
        Some(cmd @ ("fw" | "uf2" | "flash")) => {
            // A bad `--thermal` file is bad input: exit 2, nothing built.
            let housing = thermal::file_arg(&args[1..])
                .and_then(|file| file.map(|f| thermal::read(&f)).transpose());
            let housing = match housing {
                Ok(h) => h,
                Err(e) => {
                    eprintln!("xtask: {e}");
                    return ExitCode::from(2);
                }
            };
            clippy_env().and_then(|mut env| {
                if let Some(h) = housing {
                    println!(
                        "thermal: housing {} mK/W, {} ms built in (SUPERVISOR.thermal.housing)",
                        h.r_th_mk_per_w, h.tau_ms
                    );
                    env.extend(h.env());
                }
                match cmd {
                    "fw" => build_firmware(&root, &mut Steps::new(), &env),
                    "uf2" => firmware_uf2(&root, &env).map(|_| ()),
                    _ => flash(&root, &env),
                }
            })
        }
        Some("motor-wasm") => {
            clippy_env().and_then(|lint| motor_wasm(&root, &mut Steps::new(), &lint))
        }
        Some("hil") => {
            #[path = "hil.rs"]
            mod hil;
            hil::run(&root)
        }
        _ => {
            eprintln!(
                "usage: cargo xtask <test|size|fw|uf2|flash|motor-wasm|hil> (fw, uf2, flash: [--thermal thermal.toml])"
            );
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

fn run(root: &Path, program: &str, args: &[&str]) -> Result<(), String> {
    run_with(root, program, args, &[])
}

/// [`run`] with extra environment variables.
fn run_with(
    root: &Path,
    program: &str,
    args: &[&str],
    env: &[(&str, std::ffi::OsString)],
) -> Result<(), String> {
    let status = Command::new(program)
        .args(args)
        .current_dir(root)
        .envs(env.iter().map(|(k, v)| (k, v)))
        .status()
        .map_err(|e| format!("cannot start `{program}`: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`{program} {}` failed ({status})", args.join(" ")))
    }
}

fn test_all(root: &Path) -> Result<(), String> {
    let mut steps = Steps::new();
    let result = test_steps(root, &mut steps);
    steps.summary();
    result
}

fn test_steps(root: &Path, steps: &mut Steps) -> Result<(), String> {
    let emulator = root.join("tests/emulator");
    let has_emulator = emulator.join("package.json").exists();
    let logs = root.join("target/xtask");
    std::fs::create_dir_all(&logs).map_err(|e| format!("{}: {e}", logs.display()))?;
    // Network waits, started now so they overlap the compile steps.
    let npm_ci = has_emulator.then(|| {
        Background::start(
            "npm ci (tests/emulator)",
            &emulator,
            "npm",
            &["ci", "--no-audit", "--no-fund"],
            logs.join("npm-ci.log"),
        )
    });
    let bootrom = has_emulator.then(|| {
        Background::start(
            "RP2040 bootrom download (tests/emulator/scripts/fetch_bootrom.py)",
            root,
            &std::env::var("PYTHON").unwrap_or_else(|_| "python3".into()),
            &[
                "tests/emulator/scripts/fetch_bootrom.py",
                "target/emu/bootrom",
            ],
            logs.join("bootrom.log"),
        )
    });

    let pyenv = python::start_venv(root, &logs);

    steps.begin("rustfmt");
    run(root, "cargo", &["fmt", "--all", "--", "--check"])?;
    let lint = host_clippy_and_tests(root, steps)?;
    python::test(root, steps, pyenv, &lint)?;
    // The RP2040 builds are linted as they compile, like the host's: the
    // firmware exists only for its target, so a host `cargo clippy` skips it.
    let fw_lint = clippy_env()?;
    steps.begin("shared crate builds for the RP2040 (no_std, thumbv6m, clippy)");
    // In the firmware's profile: the firmware build below then reuses this
    // very library and its dependencies instead of building them again.
    run_with(
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
            "--profile",
            "fw",
        ],
        &fw_lint,
    )?;
    build_firmware(root, steps, &fw_lint)?;
    firmware_size(root, steps)?;
    if let (Some(npm_ci), Some(bootrom)) = (npm_ci, bootrom) {
        steps.begin("emulator tests: fetched in the background");
        npm_ci.finish()?;
        bootrom.finish()?;
    }
    motor_wasm(root, steps, &fw_lint)?;
    // The emulator's images are the same build with features: same settings,
    // so they reuse the linted dependencies.
    emulator_tests(root, steps, &fw_lint)?;
    println!("\nall checks passed");
    Ok(())
}

/// Clippy (warnings are errors) on every host target, then every host test,
/// compiled once. `cargo clippy` is `cargo check` with clippy's driver as the
/// compiler of the workspace's own crates; running `cargo test` with the
/// same driver lints exactly those crates while it builds them, so the
/// dependencies are compiled once (as the tests need them) instead of a
/// second time in check mode, and the workspace crates once, not twice.
///
/// Returns the settings that lint as these builds do, for the Python
/// extension's build (python/ is left out here: maturin builds it, once).
fn host_clippy_and_tests(root: &Path, steps: &mut Steps) -> Result<python::Lint, String> {
    let clippy = clippy_env()?;
    let cold = cold_build(root);
    if cold {
        println!("cold host build: no incremental cache, workspace crates in 4 codegen units");
    }
    let with_clippy = |args: &[&str]| -> Result<(), String> {
        let mut cargo = Command::new("cargo");
        if cold {
            cargo.env("CARGO_INCREMENTAL", "0");
            for setting in COLD_CODEGEN_UNITS {
                cargo.args(["--config", setting]);
            }
        }
        let status = cargo
            .args(args)
            .current_dir(root)
            .envs(clippy.iter().map(|(k, v)| (k, v)))
            .status()
            .map_err(|e| format!("cannot start `cargo`: {e}"))?;
        if status.success() {
            Ok(())
        } else {
            Err(format!("`cargo {}` failed ({status})", args.join(" ")))
        }
    };
    steps.begin("clippy on every host target (warnings are errors), building the tests");
    // --all-targets: the benches too, which `cargo test` alone never builds.
    with_clippy(&[
        "test",
        "--workspace",
        "--exclude",
        "firmware",
        "--exclude",
        "swimbot-python",
        "--all-targets",
        "--no-run",
    ])?;
    steps.begin("host tests (unit, integration, doc tests; examples compile)");
    with_clippy(&[
        "test",
        "--workspace",
        "--exclude",
        "firmware",
        "--exclude",
        "swimbot-python",
    ])?;
    let mut lint = clippy.clone();
    let mut configs = Vec::new();
    if cold {
        lint.push(("CARGO_INCREMENTAL", "0".into()));
        configs.extend(COLD_CODEGEN_UNITS.iter().map(|c| c.to_string()));
    }
    Ok(python::Lint { env: lint, configs })
}

/// Codegen units of the workspace crates in a cold build (see `cold_build`).
const COLD_CODEGEN_UNITS: [&str; 3] = [
    "profile.dev.package.swimbot.codegen-units=4",
    "profile.dev.package.swimbot-integration.codegen-units=4",
    "profile.dev.package.swimbot-shared.codegen-units=4",
];

/// Whether the host build is cold: no incremental cache of the `swimbot`
/// library under `target/debug` yet (a fresh clone, CI; xtask's own cache,
/// made by `cargo xtask` itself, does not count), and the caller has not
/// chosen `CARGO_INCREMENTAL`. A cold build is made for throughput, not for
/// the next edit: no incremental cache (writing it is pure overhead when
/// nothing is reused) and 4 codegen units for the workspace crates instead
/// of 256 (fewer copies of the same nalgebra instances to optimise). On this
/// 2-core machine the workspace crates' test build took 246 and 257 s of CPU
/// with cargo's defaults, 242 s without the cache, 151 s with both changes
/// (wall 82 s; runs with next to no steal). Both
/// settings are part of cargo's fingerprint, so once a developer's
/// incremental `cargo test` has made the cache the checks use the
/// developer's settings too, and the two never rebuild each other's crates.
fn cold_build(root: &Path) -> bool {
    if std::env::var_os("CARGO_INCREMENTAL").is_some() {
        return false;
    }
    let warm = std::fs::read_dir(root.join("target/debug/incremental"))
        .map(|entries| {
            entries
                .flatten()
                .any(|e| e.file_name().to_string_lossy().starts_with("swimbot-"))
        })
        .unwrap_or(false);
    !warm
}

/// The toolchain's `clippy-driver`, next to its `rustc`.
fn clippy_driver() -> Result<PathBuf, String> {
    let out = Command::new("rustc")
        .args(["--print", "sysroot"])
        .output()
        .map_err(|e| format!("cannot start `rustc`: {e}"))?;
    let sysroot = String::from_utf8_lossy(&out.stdout).trim().to_string();
    let driver = Path::new(&sysroot)
        .join("bin")
        .join(format!("clippy-driver{}", std::env::consts::EXE_SUFFIX));
    if driver.is_file() {
        Ok(driver)
    } else {
        Err(format!(
            "{} not found: install clippy (`rustup component add clippy`)",
            driver.display()
        ))
    }
}

fn build_firmware(
    root: &Path,
    steps: &mut Steps,
    lint: &[(&str, std::ffi::OsString)],
) -> Result<(), String> {
    steps.begin("firmware release build (thumbv6m-none-eabi, profile fw, clippy)");
    run_with(root, "cargo", &["fw"], lint)
}

/// Clippy's driver as the compiler of the workspace's own crates, warnings
/// as errors: what `cargo clippy -- -D warnings` hands its driver, set on a
/// build so that it lints what it compiles.
fn clippy_env() -> Result<Vec<(&'static str, std::ffi::OsString)>, String> {
    Ok(vec![
        ("RUSTC_WORKSPACE_WRAPPER", clippy_driver()?.into_os_string()),
        (
            "CLIPPY_ARGS",
            "-D__CLIPPY_HACKERY__warnings__CLIPPY_HACKERY__".into(),
        ),
    ])
}

fn firmware_size(root: &Path, steps: &mut Steps) -> Result<(), String> {
    steps.begin("firmware size budget");
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
    // flip-link (the linker in .cargo/config.toml) puts the stack below the
    // statics, so an overflow faults instead of overwriting them; a build
    // linked without it has its statics at the RAM's origin.
    match usage.lowest_static_ram {
        Some(a) if a > size::RAM_START => println!(
            "stack below the statics (flip-link): statics from {a:#010x}, stack grows down to {:#010x}",
            size::RAM_START
        ),
        Some(a) => {
            return Err(format!(
                "statics start at the RAM's origin ({a:#010x}): the firmware was not linked by \
                 flip-link, so a stack overflow would overwrite them (install it: `cargo install flip-link`)"
            ))
        }
        None => {}
    }
    println!("{}", layout::check(&root.join(FW_ELF))?);
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

/// The emulator board's motor: the host's motor model (`swimbot-motor`)
/// compiled to WebAssembly (`motor/wasm`), which `tests/emulator/lib/rotor.js`
/// loads. The target is installed as `scripts/test` installs thumbv6m's
/// (a no-op once present).
fn motor_wasm(
    root: &Path,
    steps: &mut Steps,
    lint: &[(&str, std::ffi::OsString)],
) -> Result<(), String> {
    if !root.join("tests/emulator/package.json").exists() {
        return Ok(());
    }
    steps.begin("emulator's motor model (swimbot-motor-wasm, wasm32-unknown-unknown, clippy)");
    run(root, "rustup", &["target", "add", WASM_TARGET])?;
    run_with(
        root,
        "cargo",
        &[
            "build",
            "-p",
            "swimbot-motor-wasm",
            "--target",
            WASM_TARGET,
            "--profile",
            "wasm",
        ],
        lint,
    )
}

const WASM_TARGET: &str = "wasm32-unknown-unknown";

/// The RP2040 emulator tests (`tests/emulator`, rp2040js): `npm test`, whose
/// `scripts/prepare.mjs` builds the images it runs in this target directory
/// (the plain one is the firmware just built and measured, so it is only
/// copied; the `hang-test` one is moved away from the flashed path at once),
/// and runs the scenarios in simulated time. `npm ci` and the bootrom
/// download ran in the background (`test_all`).
fn emulator_tests(
    root: &Path,
    steps: &mut Steps,
    lint: &[(&str, std::ffi::OsString)],
) -> Result<(), String> {
    let dir = root.join("tests/emulator");
    if !dir.join("package.json").exists() {
        steps.begin("emulator tests: not present in this tree (tests/emulator/package.json)");
        return Ok(());
    }
    steps.begin("emulator tests (rp2040js: IR in, PWM out, battery ADC, watchdog)");
    run_with(&dir, "npm", &["test"], lint)
}

/// The firmware built (as `cargo fw`) and written as a UF2 next to its ELF.
fn firmware_uf2(root: &Path, lint: &[(&str, std::ffi::OsString)]) -> Result<PathBuf, String> {
    build_firmware(root, &mut Steps::new(), lint)?;
    let out = root.join(FW_UF2);
    let blocks = uf2::write(&root.join(FW_ELF), &out)?;
    println!(
        "{}: {blocks} blocks ({} KiB of flash), family RP2040 ({:#010x}), from {:#010x}",
        out.display(),
        blocks * uf2::PAGE_BYTES / 1024,
        uf2::RP2040_FAMILY_ID,
        uf2::FLASH_START
    );
    Ok(out)
}

/// The UF2 copied onto a board's BOOTSEL drive; the bootrom flashes it and
/// starts the firmware when the copy closes.
fn flash(root: &Path, lint: &[(&str, std::ffi::OsString)]) -> Result<(), String> {
    let file = firmware_uf2(root, lint)?;
    let Some(drive) = uf2::find_drive() else {
        return Err(format!(
            "no RPI-RP2 drive mounted: hold BOOTSEL while plugging the Pico in (or send \
             `BOOTSEL` on its serial port), then run this again, or copy {} to the drive \
             yourself (SWIMBOT_UF2_DRIVE names a drive mounted elsewhere)",
            file.display()
        ));
    };
    let to = drive.join("firmware.uf2");
    std::fs::copy(&file, &to)
        .map_err(|e| format!("{} -> {}: {e}", file.display(), to.display()))?;
    println!(
        "copied to {}: the board restarts into the new firmware",
        to.display()
    );
    Ok(())
}
