//! A dataset from a run log's steady windows (`docs/data-format.md`): one
//! case per set-point, the named case's tail, robot, tube and oil with the
//! log's rate as `frequency_hz` and its standard error as the input
//! uncertainty `uncertainty.frequency_hz`. Each steady window is one trial:
//! the swimming speed and the body's rotation of each are the lab's to
//! measure (the log cannot know them), so the file lists the windows and
//! leaves `u_trials_mm_s` for the lab to fill in.
//!
//! The log's rate is the motor's, the tail relative to the body: a dataset
//! of it is read with the `motor-frame` effect (`--effect motor-frame`), or
//! converted to the lab frame once the body's counter-rotation is measured
//! (`f_lab = f_motor - omega_body`), as the paper's f is.

use super::steady::{show_rate, Pooled, CONFIDENCE};
use crate::data::uncertainty::Uncertainty;
use crate::data::{to_toml, Case, Dataset};
use crate::stats::student_t_quantile;
use std::fmt::Write as _;

/// The case id for a set-point: `tail-3@0.800Hz`.
pub fn case_id(base: &str, set_hz: f64) -> String {
    format!("{base}@{set_hz:.3}Hz")
}

/// One case per set-point, from `base` (its measurements dropped).
pub fn cases(base: &Case, pooled: &[Pooled]) -> Vec<Case> {
    pooled
        .iter()
        .map(|p| {
            let mut c = base.clone();
            c.id = case_id(&base.id, p.set_hz);
            c.frequency_hz = p.mean_hz;
            c.u_mm_s = None;
            c.omega_body_hz = None;
            let se = p.ci_hz / student_t_quantile(CONFIDENCE, p.turns as u32);
            c.inputs.uncertainties.retain(|(k, _)| *k != "frequency_hz");
            c.inputs
                .uncertainties
                .push(("frequency_hz", Uncertainty::Absolute(se)));
            c
        })
        .collect()
}

/// The dataset file: a comment block per case (its windows, what is left
/// for the lab), then the cases.
pub fn dataset_toml(base: &Case, pooled: &[Pooled], source: &str) -> String {
    let data = Dataset {
        name: format!("{} from the run log", base.id),
        source: source.to_string(),
        cases: cases(base, pooled),
        rig: Default::default(),
    };
    let mut head = String::new();
    let _ = writeln!(
        head,
        "# Trials from the robot's run log ({source}), written by `swimbot log`.\n\
         # frequency_hz is the MOTOR's rate (tail relative to body, the Hall ring on the\n\
         # coupler), the mean over whole turns in the steady windows; uncertainty.frequency_hz\n\
         # is its standard error. Read with `--effect motor-frame`, or subtract the body's\n\
         # measured counter-rotation for the lab-frame rate the paper's f is.\n\
         # Each steady window below is one trial: measure its swimming speed (and the body's\n\
         # rotation) and add u_trials_mm_s = [...] (omega_body_trials_hz = [...]) to its case."
    );
    for p in pooled {
        let _ = writeln!(
            head,
            "#\n# case {}: set-point {} Hz, {} ({} % CI, {} turns, {} window(s))",
            case_id(&base.id, p.set_hz),
            p.set_hz,
            show_rate(p.mean_hz, p.ci_hz),
            100.0 * CONFIDENCE,
            p.turns,
            p.windows.len()
        );
        for (k, w) in p.windows.iter().enumerate() {
            let _ = writeln!(
                head,
                "#   trial {}: {:.1}-{:.1} s, {} over {} turns, duty {:.1} %{}",
                k + 1,
                w.from_s,
                w.to_s,
                show_rate(w.mean_hz, w.ci_hz),
                w.turn_means_hz.len(),
                100.0 * w.mean_duty,
                w.mean_cell_v
                    .map_or(String::new(), |v| format!(", cell {v:.2} V"))
            );
        }
    }
    head + "\n" + &to_toml(&data)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::runlog::steady::SteadyWindow;

    fn window(set: f64, turns: Vec<f64>) -> SteadyWindow {
        let (mean_hz, ci_hz) = crate::stats::mean_and_ci(&turns, CONFIDENCE);
        SteadyWindow {
            from_s: 0.0,
            to_s: 10.0,
            set_hz: set,
            turn_means_hz: turns,
            mean_hz,
            ci_hz,
            mean_duty: 0.3,
            mean_cell_v: None,
        }
    }

    #[test]
    fn the_video_uncertainty_gives_way_to_the_logs_standard_error() {
        let paper = crate::data::paper();
        let base = &paper.cases[2];
        assert!(
            base.inputs.standard(base, "frequency_hz") > 0.01,
            "the paper's 2 %"
        );
        let w = [window(0.8, vec![0.79, 0.80, 0.81, 0.80])];
        let pooled = super::super::steady::pool(&w);
        let cases = cases(base, &pooled);
        let c = &cases[0];
        assert_eq!(c.id, format!("{}@0.800Hz", base.id));
        assert!((c.frequency_hz - 0.8).abs() < 1e-12);
        // sd 0.00816 over 4 turns: standard error 0.00408.
        let u = c.inputs.standard(c, "frequency_hz");
        assert!((u - 0.008165 / 2.0).abs() < 1e-5, "{u}");
        assert_eq!(c.wavelength_mm, base.wavelength_mm);
        assert!(c.u_mm_s.is_none() && c.omega_body_hz.is_none());
        // What is written parses back to the same numbers.
        let text = dataset_toml(base, &pooled, "test");
        let back = crate::data::parse_str(&text, "trials.toml").unwrap();
        assert_eq!(back.cases[0].frequency_hz, c.frequency_hz);
        assert!(
            (back.cases[0]
                .inputs
                .standard(&back.cases[0], "frequency_hz")
                - u)
                .abs()
                < 1e-15
        );
    }
}
