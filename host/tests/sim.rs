//! Physics of `swimbot sim`: the coupled run against the direct model
//! solve, the energy ledger, the battery's life, the remote's on/off, the
//! one-motor fit and the robot file's errors through the binary.

use std::f64::consts::TAU;
use swimbot::data::paper;
use swimbot::effects::parse_effect_spec;
use swimbot::physics::solve::TailDrive;
use swimbot::sim::calibrate::{fit_motor, rms_f_error};
use swimbot::sim::{default_robot, simulate, End, Options, Robot, Script};
use swimbot_shared::{Command, MotorState as State, StopReason};

fn long_channel() -> Options {
    Options {
        stop_at_top: false,
        ..Options::default()
    }
}

#[test]
fn steady_state_equals_the_direct_model_solve_at_the_simulated_rate() {
    let robot = default_robot();
    for tail in [0, 4] {
        let opts = Options {
            tail,
            max_time_s: 5.0,
            ..long_channel()
        };
        let o = simulate(&robot, &Script::on_at_zero(), &opts).unwrap();
        assert_eq!(o.end, End::TimeLimit);
        let s = o.last;
        assert_eq!(s.state, State::Running);
        let w = s.motor_rate_hz * TAU;
        // Direct solve of eq. 11 with the motor between body and tail.
        let case = robot.case(tail, s.motor_rate_hz);
        let mut fb = robot.model.force_balance(&case).unwrap();
        fb.drive = TailDrive::RelativeToBody;
        fb.tail_rate_rad_s = w;
        let v = fb.solve().unwrap();
        let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
        eprintln!(
            "tail {tail}: f {:.4} Hz, U rel err {:.1e}, Omega_b rel err {:.1e}",
            s.tail_rate_hz,
            rel(s.u_mm_s, v[0] * 1e3),
            rel(s.body_rate_hz, v[3] / TAU)
        );
        assert!(
            rel(s.u_mm_s, v[0] * 1e3) < 1e-9,
            "{} vs {}",
            s.u_mm_s,
            v[0] * 1e3
        );
        assert!(rel(s.body_rate_hz, v[3] / TAU) < 1e-9);
        // The same through the public predict() with the motor-frame effect.
        let p = robot
            .model
            .clone()
            .with_effect(parse_effect_spec("motor-frame").unwrap())
            .predict(&case)
            .unwrap();
        assert!(rel(s.u_mm_s, p.u_mm_s) < 1e-9 && rel(-s.body_rate_hz, p.omega_body_hz) < 1e-9);
        // The motor is at its steady state: k i = friction + the tail's torque.
        let m = robot.motor;
        let tail_torque = {
            let mut vt = v;
            vt[3] += w;
            (fb.tail * vt)[3]
        };
        let friction = m.viscous_friction_n_m_s * w + m.coulomb_friction_n_m;
        let torque = m.torque_constant_n_m_per_a * s.motor_current_a;
        assert!(
            rel(friction + tail_torque, torque) < 1e-6,
            "{torque} vs {}",
            friction + tail_torque
        );
    }
}

#[test]
fn energy_from_the_cell_equals_losses_plus_dissipation_plus_storage() {
    let mut robot = default_robot();
    for buoyancy in [None, Some("buoyancy:net_force_mn=-0.5")] {
        if let Some(b) = buoyancy {
            robot.model.effects.push(parse_effect_spec(b).unwrap());
        }
        let script = Script::parse("on@0s,off@30s,on@31s,off@60s").unwrap();
        let opts = Options {
            max_time_s: 62.0,
            ..long_channel()
        };
        let o = simulate(&robot, &script, &opts).unwrap();
        let e = o.energy;
        // Tolerance 1e-5 of the cell's energy: the implicit motor step's
        // numerical damping in the start and stop transients is the only
        // term outside the ledger.
        assert!(
            e.cell_j > 20.0 && e.hydro_j > 0.0 && e.friction_j > 0.0,
            "{e:?}"
        );
        eprintln!(
            "energy {buoyancy:?}: {e:?}, relative residual {:.2e}",
            e.residual_j() / e.cell_j
        );
        assert!(
            e.residual_j().abs() < 1e-5 * e.cell_j,
            "{buoyancy:?}: {e:?}, residual {}",
            e.residual_j()
        );
        if buoyancy.is_some() {
            assert!(
                e.external_j < 0.0,
                "a heavy robot does work against its weight: {e:?}"
            );
        }
    }
}

#[test]
fn the_battery_lasts_about_the_papers_ten_minutes() {
    // The board's 10-minute limit stops the default robot first, with the
    // cell nearly empty; without the limit the under-voltage cut-off trips
    // shortly after.
    let robot = default_robot();
    let o = simulate(&robot, &Script::on_at_zero(), &long_channel()).unwrap();
    assert_eq!(o.end, End::Stopped(StopReason::MaxRunTime));
    assert!((599.0..602.0).contains(&o.last.t_s), "{}", o.last.t_s);
    assert!(o.last.soc < 0.2, "soc {}", o.last.soc);

    let mut unlimited = robot.clone();
    unlimited.controller.max_run_us = 3_600_000_000;
    let o = simulate(&unlimited, &Script::on_at_zero(), &long_channel()).unwrap();
    assert_eq!(o.end, End::Stopped(StopReason::LowBattery));
    let minutes = o.last.t_s / 60.0;
    eprintln!(
        "cut-off after {minutes:.2} min, soc {:.3}, {:.3} V",
        o.last.soc, o.last.battery_v
    );
    assert!((9.0..13.0).contains(&minutes), "{minutes} min");
    assert!(o.last.soc < 0.1, "soc {}", o.last.soc);
}

#[test]
fn on_climbs_off_stops() {
    let robot = default_robot();
    let script = Script::parse("on@0s,off@20s").unwrap();
    let opts = Options {
        max_time_s: 60.0,
        sample_every_s: 0.01,
        ..long_channel()
    };
    let o = simulate(&robot, &script, &opts).unwrap();
    assert_eq!(o.end, End::Idle);
    let cmds: Vec<Command> = o.commands.iter().map(|c| c.1).collect();
    assert_eq!(cmds, vec![Command::On, Command::Off]);
    let off_at = o.commands[1].0;
    assert!((20.0..20.1).contains(&off_at), "{off_at}");
    let on: Vec<_> = o.samples.iter().filter(|s| s.t_s < off_at).collect();
    assert!(
        on.windows(2).all(|w| w[1].height_mm >= w[0].height_mm),
        "height monotonic while on"
    );
    let climbed = on.last().unwrap().height_mm - o.start_height_mm;
    assert!(
        climbed > 0.5 * o.mean_u_mm_s * 20.0 && climbed > 1.0,
        "{climbed} mm"
    );
    // Within a second of Off the tail is still; the robot stays put.
    let after: Vec<_> = o.samples.iter().filter(|s| s.t_s > off_at + 1.0).collect();
    assert!(!after.is_empty());
    for s in &after {
        assert_eq!(s.state, State::Off);
        assert!(
            s.motor_rate_hz.abs() < 1e-3 && s.u_mm_s.abs() < 1e-6,
            "{s:?}"
        );
        assert!((s.height_mm - after[0].height_mm).abs() < 1e-6);
    }
}

#[test]
fn the_default_run_reaches_the_top() {
    let o = simulate(&default_robot(), &Script::on_at_zero(), &Options::default()).unwrap();
    assert_eq!(o.end, End::TopReached);
    let t = o.top_reached_s.unwrap();
    let climb = o.channel_length_mm - o.start_height_mm;
    // The soft start costs a fraction of a second of climbing.
    assert!(
        (t - climb / o.mean_u_mm_s).abs() < 1.0,
        "{t} s vs {climb} / {}",
        o.mean_u_mm_s
    );
}

#[test]
fn fit_motor_gives_finite_constants_and_per_case_errors() {
    let robot = default_robot();
    let data = paper();
    let fit = fit_motor(&robot, &data).unwrap();
    assert_eq!(fit.cases.len(), 6);
    for v in [
        fit.stall_torque_n_m,
        fit.slope_n_m_s,
        fit.constant_torque_n_m,
        fit.k_from_stall_n_m_per_a,
    ] {
        assert!(v.is_finite() && v > 0.0, "{fit:?}");
    }
    for c in &fit.cases {
        assert!(
            c.line.f_hz.is_finite() && c.line.f_hz > 0.0 && c.line.omega_b_hz.is_finite(),
            "{c:?}"
        );
    }
    let (line, constant, plausible) = (
        rms_f_error(&fit, |c| c.line),
        rms_f_error(&fit, |c| c.constant),
        rms_f_error(&fit, |c| c.robot_motor),
    );
    // A torque-speed line beats a constant torque; the robot file's motor
    // is the calibrated one, so it does as well as the line (within the
    // rounding of its constants to three figures).
    assert!(line < constant, "{line} {constant}");
    assert!(plausible < line * 1.1, "{plausible} {line}");
    let cal = fit.calibration.as_ref().expect("six cases calibrate");
    let (k, b) = (&cal.k_n_m_per_a, &cal.b_n_m_s);
    assert!(cal.rms_f <= plausible + 1e-9, "{cal:?}");
    assert!(k.lo < k.best && k.hi.is_some_and(|h| h > k.best), "{cal:?}");
    assert!(!b.lo_at_bound && b.lo < b.best, "{cal:?}");
    // The robot file carries the fit (to three figures).
    let m = &robot.motor;
    assert!(
        (m.torque_constant_n_m_per_a / k.best - 1.0).abs() < 5e-3,
        "{cal:?}"
    );
    assert!(
        (m.viscous_friction_n_m_s / b.best - 1.0).abs() < 5e-3,
        "{cal:?}"
    );
}

fn run_bin(args: &[&str]) -> std::process::Output {
    crate::common::command().args(args).output().unwrap()
}

#[test]
fn bad_robot_files_are_input_errors_naming_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let good = swimbot::sim::robot::DEFAULT_ROBOT_TOML;
    let cases = [
        (
            good.replace("resistance_ohm = 7.0", "resistance_ohm = -7.0"),
            "motor.resistance_ohm",
        ),
        (
            good.replace("capacity_mah = 70.0", "capacity_mah = 70.0\nvoltage = 3.7"),
            "voltage",
        ),
        (
            good.replace("\"backflow\",", "\"backflw\","),
            "model.effects[0]",
        ),
        (
            good.replace("amplitude_mm = 7.5", "amplitude_mm = 17.5"),
            "amplitude_mm",
        ),
    ];
    for (i, (text, field)) in cases.iter().enumerate() {
        assert!(Robot::from_toml(text, "x.toml").is_err(), "{field}");
        let path = dir.path().join(format!("bad{i}.toml"));
        std::fs::write(&path, text).unwrap();
        let out = run_bin(&[
            "sim",
            "--robot",
            path.to_str().unwrap(),
            "-o",
            dir.path().to_str().unwrap(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(
            err.contains(&format!("bad{i}.toml")) && err.contains(field),
            "{field}: {err}"
        );
    }
    let out = run_bin(&[
        "sim",
        "--script",
        "on@soon",
        "-o",
        dir.path().to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let out = run_bin(&["sim", "--tail", "7", "-o", dir.path().to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn the_binary_writes_csv_and_svg() {
    let dir = tempfile::tempdir().unwrap();
    let out = run_bin(&[
        "sim",
        "--tail",
        "tail-5",
        "--script",
        "on@0s,off@5s",
        "-o",
        dir.path().to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let file = std::fs::read_to_string(dir.path().join("sim.csv")).unwrap();
    // The provenance comes first, as `#` lines.
    assert!(file.starts_with("# swimbot "), "{file}");
    let csv: String = file
        .lines()
        .filter(|l| !l.starts_with('#'))
        .map(|l| format!("{l}\n"))
        .collect();
    assert!(csv.starts_with("time_s,duty,battery_v") && csv.lines().count() > 50);
    // Omega_b is the counter-rotation, positive while the motor runs (as
    // in the summary and the paper's Table IV); numbers in plain decimals.
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (omega, state) = (col("omega_body_counter_hz"), col("state"));
    let running: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect::<Vec<_>>())
        .filter(|r| r[state] == "running")
        .map(|r| r[omega].parse().unwrap())
        .collect();
    assert!(
        !running.is_empty() && running.iter().all(|w| *w > 0.0),
        "{running:?}"
    );
    assert!(
        !csv.contains("e-") && !csv.contains("e0"),
        "scientific notation in the CSV"
    );
    let svg = std::fs::read_to_string(dir.path().join("sim.svg")).unwrap();
    assert!(svg.contains("<svg"));
    swimbot::chart::legend_clear(&svg).unwrap();
    assert!(String::from_utf8_lossy(&out.stdout).contains("battery left"));
}

#[test]
fn rate_set_points_write_the_step_responses_and_bad_ones_are_input_errors() {
    let dir = tempfile::tempdir().unwrap();
    let out_dir = dir.path().to_str().unwrap();
    let out = run_bin(&[
        "sim",
        "--tail",
        "tail-3",
        "--script",
        "on@0s,off@10s",
        "--rate-hz",
        "0.7@0s,1.0@5s",
        "-o",
        out_dir,
    ]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(
        stdout.matches("settled within 2 % in").count(),
        2,
        "{stdout}"
    );
    let csv = std::fs::read_to_string(dir.path().join("rate.csv")).unwrap();
    // the provenance block comes first, as in sim.csv
    assert!(
        csv.starts_with("# swimbot"),
        "{}",
        &csv[..80.min(csv.len())]
    );
    let table: Vec<&str> = csv.lines().filter(|l| !l.starts_with('#')).collect();
    assert!(table[0].starts_with(swimbot::sim::rate_figure::RATE_CSV_HEADER.trim_end()));
    assert!(table.len() > 900, "every 10 ms over 10 s");
    let svg = std::fs::read_to_string(dir.path().join("rate.svg")).unwrap();
    swimbot::chart::legend_clear(&svg).unwrap();
    assert!(svg.contains("set-point +-2 %") && svg.contains("sensor, one-turn mean"));

    // Without --rate-hz the run is the voltage-mode one: no rate files.
    let plain = tempfile::tempdir().unwrap();
    let out = run_bin(&[
        "sim",
        "--script",
        "on@0s,off@1s",
        "-o",
        plain.path().to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert!(!plain.path().join("rate.svg").exists());

    for (bad, says) in [
        ("3", "outside the controller's range 0.2..=2 Hz"),
        ("0.8@soon", "the time must be"),
        ("fast", "expected a rate in Hz"),
        ("", "--rate-hz is empty"),
    ] {
        let out = run_bin(&["sim", "--rate-hz", bad, "-o", out_dir]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad}: {err}");
        assert!(err.contains(says), "{bad}: {err}");
    }
}

/// A robot tail whose wire is as thick as its wavelength is refused at
/// validation, naming the file and the field (it used to pass and then fail
/// inside the model without either).
#[test]
fn a_wire_as_thick_as_the_wavelength_is_refused_naming_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/data/robot.toml"))
        .unwrap()
        .replacen("wire_diameter_mm = 1.0", "wire_diameter_mm = 16.0", 1);
    let robot = dir.path().join("thick.toml");
    std::fs::write(&robot, text).unwrap();
    let out = crate::common::command()
        .args(["sim", "--robot"])
        .arg(&robot)
        .arg("-o")
        .arg(dir.path().join("out"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains("thick.toml") && err.contains("tail[0].wire_diameter_mm"),
        "{err}"
    );
    assert!(!dir.path().join("out").exists(), "nothing written");
}
