//! `--thermal FILE` of `cargo xtask fw|uf2|flash`: the motor housing's
//! thermal node from a bench fit (the `thermal.toml` that `swimbot log
//! --thermal` writes) built into the firmware. The file's two constants are
//! checked against the board's accepted ranges
//! (`swimbot_shared::board::HOUSING_*_RANGE`, which the shared crate checks
//! again at compile time) and handed to that one firmware build as
//! `SWIMBOT_HOUSING_R_TH_MK_PER_W` and `SWIMBOT_HOUSING_TAU_MS`, read by
//! `option_env!` in `shared/src/board.rs`. Without the flag no variable is
//! set and the build is the plain one.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use swimbot_shared::board::{HOUSING_R_TH_RANGE_MK_PER_W, HOUSING_TAU_RANGE_MS};

/// The housing node a fit gives, in the firmware's units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Housing {
    pub r_th_mk_per_w: u32,
    pub tau_ms: u32,
}

impl Housing {
    /// The build's environment for these constants.
    pub fn env(&self) -> Vec<(&'static str, OsString)> {
        vec![
            (
                "SWIMBOT_HOUSING_R_TH_MK_PER_W",
                self.r_th_mk_per_w.to_string().into(),
            ),
            ("SWIMBOT_HOUSING_TAU_MS", self.tau_ms.to_string().into()),
        ]
    }
}

/// `--thermal FILE` in `args` (after the subcommand), or `None`; any other
/// argument is refused.
pub fn file_arg(args: &[String]) -> Result<Option<PathBuf>, String> {
    match args {
        [] => Ok(None),
        [flag, file] if flag == "--thermal" => Ok(Some(PathBuf::from(file))),
        [flag] if flag == "--thermal" => Err("--thermal needs a file (thermal.toml)".into()),
        _ => Err(format!(
            "unknown arguments {args:?} (only `--thermal FILE`)"
        )),
    }
}

/// Read and check `path`.
pub fn read(path: &Path) -> Result<Housing, String> {
    let name = path.display().to_string();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{name}: {e}"))?;
    parse(&text, &name)
}

/// The two constants of a `thermal.toml`, in range: `housing_r_th_k_per_w`
/// (K/W) and `housing_tau_s` (s); other keys (the fit's residual, the
/// limits it implies) are the reader's.
pub fn parse(text: &str, file: &str) -> Result<Housing, String> {
    let table: toml::Table = text
        .parse()
        .map_err(|e: toml::de::Error| format!("{file}: not TOML: {}", e.message()))?;
    let number = |key: &str| -> Result<f64, String> {
        match table.get(key) {
            None => Err(format!("{file}: no `{key}`")),
            Some(toml::Value::Float(v)) => Ok(*v),
            Some(toml::Value::Integer(v)) => Ok(*v as f64),
            Some(other) => Err(format!("{file}: `{key}` is not a number: {other}")),
        }
    };
    let r = number("housing_r_th_k_per_w")?;
    let tau = number("housing_tau_s")?;
    let r_mk = checked(
        file,
        "housing_r_th_k_per_w",
        "K/W",
        r,
        HOUSING_R_TH_RANGE_MK_PER_W,
    )?;
    let tau_ms = checked(file, "housing_tau_s", "s", tau, HOUSING_TAU_RANGE_MS)?;
    Ok(Housing {
        r_th_mk_per_w: r_mk,
        tau_ms,
    })
}

/// `value` (in K/W or s) in thousandths, inside `range` (thousandths).
fn checked(
    file: &str,
    key: &str,
    unit: &str,
    value: f64,
    range: (u32, u32),
) -> Result<u32, String> {
    let milli = (value * 1e3).round();
    let (lo, hi) = (f64::from(range.0), f64::from(range.1));
    if !value.is_finite() || milli < lo || milli > hi {
        return Err(format!(
            "{file}: `{key}` = {value} {unit} is outside {}-{} {unit} (the board's accepted range, \
             shared/src/board.rs): refit, or check the run and the thermocouple",
            lo / 1e3,
            hi / 1e3
        ));
    }
    Ok(milli as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    const FIT: &str = "format = \"swimbot-thermal v1\"\n\
        housing_r_th_k_per_w = 31.25\nhousing_tau_s = 84.0\nrms_residual_k = 0.2\n";

    #[test]
    fn a_fit_in_range_becomes_the_build_environment() {
        let h = parse(FIT, "t.toml").unwrap();
        assert_eq!(
            h,
            Housing {
                r_th_mk_per_w: 31_250,
                tau_ms: 84_000
            }
        );
        let env = h.env();
        assert_eq!(env[0], ("SWIMBOT_HOUSING_R_TH_MK_PER_W", "31250".into()));
        assert_eq!(env[1], ("SWIMBOT_HOUSING_TAU_MS", "84000".into()));
        // Integers are numbers too.
        let h = parse("housing_r_th_k_per_w = 25\nhousing_tau_s = 100\n", "t.toml").unwrap();
        assert_eq!((h.r_th_mk_per_w, h.tau_ms), (25_000, 100_000));
    }

    #[test]
    fn out_of_range_missing_and_malformed_values_are_refused_by_name() {
        let err = parse("housing_r_th_k_per_w = 400\nhousing_tau_s = 84\n", "t.toml").unwrap_err();
        assert!(
            err.contains("t.toml")
                && err.contains("housing_r_th_k_per_w")
                && err.contains("2-150 K/W"),
            "{err}"
        );
        let err = parse("housing_r_th_k_per_w = 25\nhousing_tau_s = 5\n", "t.toml").unwrap_err();
        assert!(
            err.contains("housing_tau_s") && err.contains("10-1000 s"),
            "{err}"
        );
        let err = parse("housing_r_th_k_per_w = -1\nhousing_tau_s = 84\n", "t.toml").unwrap_err();
        assert!(err.contains("housing_r_th_k_per_w"), "{err}");
        let err = parse("housing_tau_s = 84\n", "t.toml").unwrap_err();
        assert!(err.contains("no `housing_r_th_k_per_w`"), "{err}");
        let err = parse(
            "housing_r_th_k_per_w = \"25\"\nhousing_tau_s = 84\n",
            "t.toml",
        )
        .unwrap_err();
        assert!(err.contains("is not a number"), "{err}");
        let err = parse("housing_r_th_k_per_w = = 1", "t.toml").unwrap_err();
        assert!(err.contains("not TOML"), "{err}");
        // The edges are inside.
        assert!(parse("housing_r_th_k_per_w = 2\nhousing_tau_s = 1000\n", "t").is_ok());
        assert!(parse("housing_r_th_k_per_w = 150\nhousing_tau_s = 10\n", "t").is_ok());
        assert!(parse("housing_r_th_k_per_w = 150.001\nhousing_tau_s = 10\n", "t").is_err());
    }

    #[test]
    fn without_the_flag_nothing_is_set() {
        assert_eq!(file_arg(&[]).unwrap(), None);
        let args = ["--thermal".to_string(), "fit.toml".to_string()];
        assert_eq!(file_arg(&args).unwrap(), Some(PathBuf::from("fit.toml")));
        assert!(file_arg(&["--thermal".to_string()]).is_err());
        assert!(file_arg(&["--fast".to_string()]).is_err());
    }
}
