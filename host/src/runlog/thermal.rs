//! The motor housing's thermal resistance and time constant from the bench:
//! a run log of a stalled or slowed run (its records give the copper loss)
//! and the can's temperature read beside it (a thermocouple meter's CSV,
//! `t_s,temp_c`), fitted by the first-order model of the supervisor's
//! housing node (`shared/src/supervisor/thermal.rs`):
//! `tau dT/dt = R_th P(t) - T`, `T` the rise over the first reading.
//!
//! The loss per record is the supervisor's own estimate, `P = d V_cell^2 /
//! R` (duty `d`, the motor's `R`): exact for a stalled rotor, an
//! overestimate while it turns (the back-EMF lowers the current). A fit
//! from a slowed run therefore gives a smaller `R_th` than the can's, the
//! one that makes the supervisor's estimate match the measured rise, which
//! is what its limit needs. With the loss held over each record (zero-order
//! hold) the model steps exactly: `T_(k+1) = T_k a + R_th P_k (1 - a)`,
//! `a = exp(-dt / tau)`. For a given `tau` the rise is linear in `R_th`,
//! so `R_th` is the least-squares ratio `sum(u y) / sum(u^2)` of the unit
//! response `u` and the readings `y`; `tau` is found by a log-spaced scan
//! and a golden-section refinement of the residual. Hand-written: a
//! two-parameter separable least squares, smaller than wiring a general
//! optimiser to it.

use super::Trace;

/// A fitted housing node.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThermalFit {
    pub r_th_k_per_w: f64,
    pub tau_s: f64,
    /// RMS of the readings' residuals (K).
    pub rms_k: f64,
    /// Readings inside the log's span, used by the fit.
    pub readings: usize,
}

/// The readings of a `t_s,temp_c` CSV (a header line is allowed), each
/// row's fields checked: a bad row is named with its line and field.
pub fn read_temperatures(text: &str, file: &str) -> Result<Vec<(f64, f64)>, String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || (i == 0 && line.starts_with(|c: char| c.is_alphabetic())) {
            continue;
        }
        let mut fields = line.split(',').map(str::trim);
        let mut field = |name: &str| -> Result<f64, String> {
            let raw = fields
                .next()
                .ok_or_else(|| format!("{file}: line {}: no `{name}` field", i + 1))?;
            raw.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| format!("{file}: line {}: `{name}` is not a number: {raw:?}", i + 1))
        };
        let t = field("t_s")?;
        let temp = field("temp_c")?;
        if let Some(&(prev, _)) = out.last() {
            if t <= prev {
                return Err(format!(
                    "{file}: line {}: `t_s` {t} does not increase (previous {prev})",
                    i + 1
                ));
            }
        }
        out.push((t, temp));
    }
    if out.len() < 3 {
        return Err(format!(
            "{file}: {} readings; the fit needs at least 3",
            out.len()
        ));
    }
    Ok(out)
}

/// The loss over each record of `trace` (start time, W), from the
/// supervisor's model with the motor's resistance `r_ohm`.
pub fn losses(trace: &Trace, r_ohm: f64) -> Vec<(f64, f64)> {
    trace
        .points
        .iter()
        .map(|p| {
            let v = p.cell_v.unwrap_or(0.0);
            (p.t_s, p.duty * v * v / r_ohm)
        })
        .collect()
}

/// The model's rise at each reading time for `R_th` = 1 K/W: the losses
/// held from each start to the next (the last held to the last reading).
fn unit_response(loss: &[(f64, f64)], at: &[f64], tau_s: f64) -> Vec<f64> {
    let mut out = Vec::with_capacity(at.len());
    let (mut t, mut rise, mut k) = (loss[0].0, 0.0, 0);
    for &target in at {
        while t < target {
            let next = loss.get(k + 1).map_or(target, |l| l.0.min(target));
            let a = (-(next - t) / tau_s).exp();
            rise = rise * a + loss[k].1 * (1.0 - a);
            t = next;
            if loss.get(k + 1).is_some_and(|l| l.0 <= t) {
                k += 1;
            }
        }
        out.push(rise);
    }
    out
}

/// `R_th` and the sum of squared residuals for one `tau`.
fn solve(loss: &[(f64, f64)], at: &[f64], rise: &[f64], tau_s: f64) -> (f64, f64) {
    let u = unit_response(loss, at, tau_s);
    let uu: f64 = u.iter().map(|x| x * x).sum();
    let uy: f64 = u.iter().zip(rise).map(|(x, y)| x * y).sum();
    let r = if uu > 0.0 { uy / uu } else { 0.0 };
    let sse = u.iter().zip(rise).map(|(x, y)| (r * x - y).powi(2)).sum();
    (r, sse)
}

/// Fits the housing node to `temps` (s, deg C) under `loss` (s, W).
pub fn fit(loss: &[(f64, f64)], temps: &[(f64, f64)]) -> Result<ThermalFit, String> {
    let (Some(&(t0, _)), Some(&(t1, _))) = (loss.first(), loss.last()) else {
        return Err("the run log has no records".into());
    };
    if loss.iter().all(|l| l.1 <= 0.0) {
        return Err("the run log never drives the motor: no heat to fit".into());
    }
    let inside: Vec<_> = temps
        .iter()
        .filter(|(t, _)| *t >= t0 && *t <= t1 + 600.0)
        .copied()
        .collect();
    if inside.len() < 3 {
        return Err(format!(
            "{} readings within the log's {t0:.1}-{t1:.1} s (and 10 min after): need 3",
            inside.len()
        ));
    }
    let at: Vec<f64> = inside.iter().map(|r| r.0).collect();
    let base = inside[0].1;
    let rise: Vec<f64> = inside.iter().map(|r| r.1 - base).collect();
    let sse = |ln_tau: f64| solve(loss, &at, &rise, ln_tau.exp()).1;
    // Scan 0.5 s .. 5000 s, then refine around the best.
    let (lo, hi, n) = (0.5f64.ln(), 5000f64.ln(), 120);
    let step = (hi - lo) / n as f64;
    let best = (0..=n)
        .map(|i| lo + step * i as f64)
        .min_by(|a, b| sse(*a).total_cmp(&sse(*b)))
        .unwrap_or(lo);
    let (mut a, mut b) = (best - step, best + step);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..60 {
        let (c, d) = (b - g * (b - a), a + g * (b - a));
        if sse(c) < sse(d) {
            b = d;
        } else {
            a = c;
        }
    }
    let tau_s = ((a + b) / 2.0).exp();
    let (r, sse) = solve(loss, &at, &rise, tau_s);
    Ok(ThermalFit {
        r_th_k_per_w: r,
        tau_s,
        rms_k: (sse / at.len() as f64).sqrt(),
        readings: at.len(),
    })
}

/// The board constants the fit sets (`shared/src/board.rs`, `SUPERVISOR`'s
/// housing node), in the units written there.
pub fn report(fit: &ThermalFit) -> String {
    format!(
        "housing: R_th {:.1} K/W, tau {:.0} s (RMS residual {:.2} K over {} readings)\n\
         set in shared/src/board.rs, SUPERVISOR.thermal.housing:\n  \
         r_th_mk_per_w: {:.0},\n  tau_ms: {:.0},\n",
        fit.r_th_k_per_w,
        fit.tau_s,
        fit.rms_k,
        fit.readings,
        fit.r_th_k_per_w * 1e3,
        fit.tau_s * 1e3,
    )
}

/// The fit as `thermal.toml`, what `cargo xtask fw|uf2|flash --thermal`
/// builds into the firmware (`housing_r_th_k_per_w`, `housing_tau_s`; xtask
/// checks their range). Also the limit they imply with the board's winding
/// node and allowed rise, for the reader: the steady loss that takes the
/// winding to its limit, `rise_max / (R_winding + R_housing)`.
pub fn toml_text(fit: &ThermalFit, log: &str, readings: &str) -> String {
    let t = swimbot_shared::board::SUPERVISOR.thermal;
    let rise_max_k = f64::from(t.winding_rise_max_mk) * 1e-3;
    let winding_k_per_w = f64::from(t.winding.r_th_mk_per_w) * 1e-3;
    let limit_w = rise_max_k / (winding_k_per_w + fit.r_th_k_per_w);
    format!(
        "# The motor housing's thermal node fitted by `swimbot log --thermal`\n\
         # from {log:?} and {readings:?}; build it in with\n\
         # `cargo xtask uf2 --thermal thermal.toml` (firmware/README.md).\n\
         format = \"swimbot-thermal v1\"\n\
         housing_r_th_k_per_w = {:.2}\n\
         housing_tau_s = {:.1}\n\
         rms_residual_k = {:.3}\n\
         readings = {}\n\
         # The limit these give with the board's winding node ({winding_k_per_w} K/W)\n\
         # and allowed winding rise ({rise_max_k} K): the steady loss that reaches it.\n\
         winding_rise_max_k = {rise_max_k}\n\
         steady_loss_limit_w = {limit_w:.3}\n",
        fit.r_th_k_per_w, fit.tau_s, fit.rms_k, fit.readings
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_toml_carries_the_fit_and_the_limit_it_implies() {
        let fit = ThermalFit {
            r_th_k_per_w: 30.0,
            tau_s: 84.25,
            rms_k: 0.125,
            readings: 120,
        };
        let text = toml_text(&fit, "run.swlog", "can.csv");
        let table: toml::Table = text.parse().unwrap();
        assert_eq!(table["format"].as_str(), Some("swimbot-thermal v1"));
        assert_eq!(table["housing_r_th_k_per_w"].as_float(), Some(30.0));
        assert_eq!(table["housing_tau_s"].as_float(), Some(84.2));
        assert_eq!(table["readings"].as_integer(), Some(120));
        // 70 K over 10 + 30 K/W.
        assert_eq!(table["steady_loss_limit_w"].as_float(), Some(1.75));
    }

    /// A 1 s-record loss: `w` from `on_s` to `off_s`, 0 around, over `len_s`.
    fn step_loss(w: f64, on_s: f64, off_s: f64, len_s: f64) -> Vec<(f64, f64)> {
        (0..(len_s as usize))
            .map(|i| {
                let t = i as f64;
                (t, if t >= on_s && t < off_s { w } else { 0.0 })
            })
            .collect()
    }

    /// The exact first-order rise of a step of `w` on at `on_s`, off at `off_s`.
    fn exact(t: f64, w: f64, r: f64, tau: f64, on_s: f64, off_s: f64) -> f64 {
        let up = |t: f64| {
            if t > on_s {
                1.0 - (-(t - on_s) / tau).exp()
            } else {
                0.0
            }
        };
        let down = |t: f64| {
            if t > off_s {
                1.0 - (-(t - off_s) / tau).exp()
            } else {
                0.0
            }
        };
        w * r * (up(t) - down(t))
    }

    #[test]
    fn recovers_a_known_node_from_its_analytic_response() {
        let loss = step_loss(1.8, 10.0, 400.0, 900.0);
        let temps: Vec<_> = (0..180)
            .map(|i| {
                let t = 5.0 * i as f64;
                (t, 30.0 + exact(t, 1.8, 25.0, 100.0, 10.0, 400.0))
            })
            .collect();
        let f = fit(&loss, &temps).unwrap();
        assert!((f.r_th_k_per_w / 25.0 - 1.0).abs() < 1e-3, "{f:?}");
        assert!((f.tau_s / 100.0 - 1.0).abs() < 1e-3, "{f:?}");
        assert!(f.rms_k < 1e-3);
    }

    /// Twice the loss for the same readings: half the resistance, same time
    /// constant (the model is linear in P R_th).
    #[test]
    fn the_fit_scales_inversely_with_the_loss() {
        let temps: Vec<_> = (0..120)
            .map(|i| {
                let t = 5.0 * i as f64;
                (t, 20.0 + exact(t, 1.0, 40.0, 60.0, 0.0, 300.0))
            })
            .collect();
        let one = fit(&step_loss(1.0, 0.0, 300.0, 600.0), &temps).unwrap();
        let two = fit(&step_loss(2.0, 0.0, 300.0, 600.0), &temps).unwrap();
        assert!((one.r_th_k_per_w / two.r_th_k_per_w - 2.0).abs() < 1e-6);
        assert!((one.tau_s / two.tau_s - 1.0).abs() < 1e-6);
    }

    #[test]
    fn bad_readings_are_named_by_line_and_field() {
        let e = read_temperatures("t_s,temp_c\n0,20\n1,x\n", "can.csv").unwrap_err();
        assert!(e.contains("can.csv: line 3") && e.contains("temp_c"), "{e}");
        let e = read_temperatures("0,20\n1\n", "can.csv").unwrap_err();
        assert!(e.contains("line 2") && e.contains("temp_c"), "{e}");
        let e = read_temperatures("0,20\n0,21\n1,22\n", "can.csv").unwrap_err();
        assert!(e.contains("does not increase"), "{e}");
        let e = read_temperatures("0,NaN\n", "can.csv").unwrap_err();
        assert!(e.contains("not a number"), "{e}");
        assert_eq!(
            read_temperatures("t_s,temp_c\n0,20\n1,21\n2,22\n", "c").unwrap(),
            [(0.0, 20.0), (1.0, 21.0), (2.0, 22.0)]
        );
    }

    #[test]
    fn a_log_without_drive_is_refused() {
        let temps = [(0.0, 20.0), (1.0, 20.0), (2.0, 20.0)];
        let e = fit(&step_loss(0.0, 0.0, 0.0, 10.0), &temps).unwrap_err();
        assert!(e.contains("no heat"), "{e}");
    }
}
