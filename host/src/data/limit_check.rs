//! The checks of the documented input limits ([`super::limits`]: what is
//! allowed and why) and their wording: a resolved case against the ranges
//! and relations ([`check_case`]), one value ([`check_value`]), an id, the
//! quadrature's resolution, and how a message repeats the user's input
//! ([`echo`], [`show`]).

use super::limits::*;
use super::Case;

/// The trim's uncertainty against [`MAX_TRIM_UNCERTAINTY_OF_DISPLACED`].
fn check_trim_uncertainty(c: &Case, u: f64) -> Result<(), (&'static str, String)> {
    let displaced_g = c.density_kg_m3 * c.body_profile().volume_m3() * 1e3;
    let limit = MAX_TRIM_UNCERTAINTY_OF_DISPLACED * displaced_g;
    if u.is_finite() && u <= limit {
        return Ok(());
    }
    Err((
        "net_weight_g",
        format!(
            "its standard uncertainty (uncertainty.net_weight_g) is {} g: at most {:.0} % of the {} g of oil the body displaces is allowed \
             (a robot trimmed no better than that is not trimmed)",
            show(u),
            100.0 * MAX_TRIM_UNCERTAINTY_OF_DISPLACED,
            show(displaced_g)
        ),
    ))
}

/// Each input uncertainty at most [`MAX_RELATIVE_INPUT_UNCERTAINTY`] of its
/// value (none on a field whose value is 0); the signed trim against the
/// displaced oil instead.
fn check_input_uncertainties(c: &Case) -> Result<(), (&'static str, String)> {
    for (field, u) in c.inputs.nonzero(c) {
        if super::uncertainty::is_signed(field) {
            check_trim_uncertainty(c, u)?;
            continue;
        }
        let value = super::uncertainty::field_value(c, field).unwrap_or(0.0);
        let limit = MAX_RELATIVE_INPUT_UNCERTAINTY * value.abs();
        if !(u.is_finite() && u <= limit) {
            return Err((
                field,
                format!(
                    "its standard uncertainty (uncertainty.{field}) is {} for a value of {}: at most {:.0} % of the value is allowed \
                     (first-order propagation needs small input spreads; beyond half the value the input was not measured)",
                    show(u),
                    show(value),
                    100.0 * MAX_RELATIVE_INPUT_UNCERTAINTY
                ),
            ));
        }
    }
    Ok(())
}

/// `s` as an error message may repeat it: control characters and NUL
/// escaped (`\0`, `\n`, `\u{1b}`), at most [`MAX_ECHO_CHARS`] characters,
/// then `... (N characters in all)`.
pub fn echo(s: &str) -> String {
    let n = s.chars().count();
    let head: String = s.chars().take(MAX_ECHO_CHARS).collect();
    let escaped: String = head
        .chars()
        .flat_map(|c| {
            let keep = !c.is_control();
            let e: Vec<char> = if keep {
                vec![c]
            } else {
                c.escape_default().collect()
            };
            e
        })
        .collect();
    if n > MAX_ECHO_CHARS {
        format!("{escaped}... ({n} characters in all)")
    } else {
        escaped
    }
}

/// Checks the quadrature resolution for a tail of `turns` turns.
pub fn check_quadrature(nodes_per_wavelength: usize, turns: f64) -> Result<(), LimitError> {
    let nodes = nodes_per_wavelength as f64 * turns.max(1.0);
    if nodes_per_wavelength < 2 || nodes > MAX_QUADRATURE_NODES {
        return Err(LimitError::Quadrature {
            nodes_per_wavelength,
            turns,
        });
    }
    Ok(())
}

/// A value as a person would write it: plain when moderate, else with an
/// exponent (`1e300`, not three hundred digits).
pub fn show(v: f64) -> String {
    if v == 0.0 || (1e-4..1e6).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Checks `value` of `field` (absolute value for the signed measured means).
pub fn check_value(field: &str, value: f64) -> Result<(), LimitError> {
    let Some(l) = limit_of(field) else {
        return Ok(());
    };
    let v = if matches!(field, "u_mm_s" | "omega_body_hz" | "net_weight_g") {
        value.abs()
    } else {
        value
    };
    if !v.is_finite() || v < l.min || v > l.max {
        return Err(LimitError::OutOfRange { value, limit: l });
    }
    Ok(())
}

/// A case or tail id: not empty, short, no control characters (they break
/// the tables), no comma (`--cases` splits at commas), no outer spaces.
pub fn check_id(id: &str) -> Result<(), LimitError> {
    if id.trim().is_empty() {
        return Err(LimitError::EmptyId);
    }
    if id.chars().count() > MAX_ID_CHARS {
        return Err(LimitError::LongId);
    }
    if id.chars().any(|c| c.is_control() || c == ',') || id.trim() != id {
        return Err(LimitError::IdCharacters(id.to_string()));
    }
    Ok(())
}

/// A value outside what the model and the data may hold, with the value
/// and the limit as data (the field is the caller's to name).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LimitError {
    /// `value` outside `limit`'s range (for a signed measured mean, its
    /// absolute value).
    #[error(
        "{} is outside the allowed range {:e}..={:e} {} ({})",
        show(*.value),
        .limit.min,
        .limit.max,
        .limit.unit,
        .limit.why
    )]
    OutOfRange { value: f64, limit: &'static Limit },
    #[error(
        "{nodes_per_wavelength} nodes per wavelength: needs at least 2, and at most {MAX_QUADRATURE_NODES:e} nodes on the tail ({turns} turns)"
    )]
    Quadrature {
        nodes_per_wavelength: usize,
        turns: f64,
    },
    #[error("the id is empty")]
    EmptyId,
    #[error("the id is longer than {MAX_ID_CHARS} characters")]
    LongId,
    /// The id as given.
    #[error("the id {0:?} contains a control character, a comma or leading/trailing spaces")]
    IdCharacters(String),
}

/// Checks a resolved case: id, field ranges, the measured values and the
/// relations the geometry needs beyond those of the parser. The error is
/// `(field, message)`.
pub fn check_case(c: &Case) -> Result<(), (&'static str, String)> {
    check_id(&c.id).map_err(|m| ("id", m.to_string()))?;
    let fields: [(&'static str, f64); 15] = [
        ("wavelength_mm", c.wavelength_mm),
        ("amplitude_mm", c.amplitude_mm),
        ("tail_length_mm", c.tail_length_mm),
        ("wire_diameter_mm", c.wire_diameter_mm),
        ("channel_diameter_mm", c.channel_diameter_mm),
        ("channel_length_mm", c.channel_length_mm),
        ("body_diameter_mm", c.body_diameter_mm),
        ("body_length_mm", c.body_length_mm),
        ("coupler_diameter_mm", c.coupler_diameter_mm),
        ("coupler_length_mm", c.coupler_length_mm),
        ("coupler_gap_mm", c.coupler_gap_mm),
        ("frequency_hz", c.frequency_hz),
        ("viscosity_pa_s", c.viscosity_pa_s),
        ("density_kg_m3", c.density_kg_m3),
        ("net_weight_g", c.net_weight_g),
    ];
    for (f, v) in fields {
        check_value(f, v).map_err(|m| (f, m.to_string()))?;
    }
    for (mean_f, ci_f, m) in [
        ("u_mm_s", "u_ci_mm_s", c.u_mm_s),
        ("omega_body_hz", "omega_body_ci_hz", c.omega_body_hz),
    ] {
        let Some(m) = m else { continue };
        check_value(mean_f, m.mean).map_err(|e| (mean_f, e.to_string()))?;
        check_value("confidence", m.confidence).map_err(|e| ("confidence", e.to_string()))?;
        if m.trials > MAX_TRIALS {
            return Err((
                "trials",
                format!("{} trials: at most {MAX_TRIALS} are allowed", m.trials),
            ));
        }
        let rel = m.ci_half_width / m.mean.abs();
        if !(MIN_RELATIVE_CI..=MAX_RELATIVE_CI).contains(&rel) {
            return Err((
                ci_f,
                format!(
                    "a half-width of {} for a mean of {} ({rel:.3e} of it) is outside {MIN_RELATIVE_CI:e}..={MAX_RELATIVE_CI:e} of the mean \
                     (identical trials or a vanishing interval would give the measurement an infinite weight)",
                    show(m.ci_half_width),
                    show(m.mean)
                ),
            ));
        }
    }
    if c.coupler_diameter_mm >= c.channel_diameter_mm {
        return Err((
            "coupler_diameter_mm",
            format!(
                "the coupler ({} mm) does not fit in the {} mm channel",
                c.coupler_diameter_mm, c.channel_diameter_mm
            ),
        ));
    }
    check_input_uncertainties(c)?;
    let turns = c.tail_length_mm / c.wavelength_mm;
    if turns > MAX_TURNS {
        return Err((
            "tail_length_mm",
            format!(
                "{} helix turns (tail_length_mm / wavelength_mm): at most {MAX_TURNS} are allowed",
                show(turns)
            ),
        ));
    }
    let robot_mm = c.body_length_mm + c.coupler_length_mm + c.tail_length_mm;
    if c.channel_length_mm < robot_mm {
        return Err((
            "channel_length_mm",
            format!(
                "the {} mm channel is shorter than the {robot_mm} mm robot (body + coupler + tail)",
                c.channel_length_mm
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_paper_cases_are_inside_every_limit() {
        for c in &super::super::paper().cases {
            assert_eq!(check_case(c), Ok(()), "{}", c.id);
        }
    }

    #[test]
    fn each_kind_of_nonsense_is_named() {
        let base = super::super::paper().cases[0].clone();
        type Mutation = Box<dyn Fn(&mut Case)>;
        let cases: Vec<(&str, Mutation)> = vec![
            ("id", Box::new(|c| c.id = String::new())),
            ("id", Box::new(|c| c.id = "a\u{1b}[2J".into())),
            ("frequency_hz", Box::new(|c| c.frequency_hz = 1e300)),
            (
                "coupler_diameter_mm",
                Box::new(|c| c.coupler_diameter_mm = 40.0),
            ),
            ("channel_length_mm", Box::new(|c| c.channel_length_mm = 1.0)),
            (
                "u_mm_s",
                Box::new(|c| c.u_mm_s.as_mut().unwrap().mean = 0.0),
            ),
            (
                "u_ci_mm_s",
                Box::new(|c| c.u_mm_s.as_mut().unwrap().ci_half_width = 1e-200),
            ),
            (
                "confidence",
                Box::new(|c| c.u_mm_s.as_mut().unwrap().confidence = 1e-300),
            ),
            (
                "trials",
                Box::new(|c| c.u_mm_s.as_mut().unwrap().trials = u32::MAX),
            ),
        ];
        for (field, mutate) in cases {
            let mut c = base.clone();
            mutate(&mut c);
            let (f, msg) = check_case(&c).unwrap_err();
            assert_eq!(f, field, "{msg}");
            assert!(!msg.is_empty());
        }
    }

    #[test]
    fn every_limit_is_a_proper_range_with_a_reason() {
        for l in LIMITS {
            assert!(l.min < l.max && l.min >= 0.0, "{}", l.field);
            assert!(!l.why.is_empty());
        }
    }

    #[test]
    fn input_uncertainties_are_limited_relative_to_their_values() {
        let text = crate::data::to_toml(&crate::data::paper());
        assert!(
            text.contains("amplitude_mm = 0.3"),
            "the paper states 0.3 mm"
        );
        for (u, ok) in [
            ("1.25", true),
            ("1.3", false),
            ("1e6", false),
            ("\"49%\"", true),
            ("\"51%\"", false),
        ] {
            let t = text.replace("amplitude_mm = 0.3", &format!("amplitude_mm = {u}"));
            let r = crate::data::parse_str(&t, "u.toml");
            assert_eq!(r.is_ok(), ok, "{u}: {r:?}");
            if let Err(e) = r {
                let e = e.to_string();
                assert!(
                    e.contains("uncertainty.amplitude_mm") && e.contains("50 %"),
                    "{e}"
                );
            }
        }
    }
}
