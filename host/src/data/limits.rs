//! The documented input limits: for every numeric field of a case, the
//! physical range the model is meant for (and why), and the size limits
//! (cases, trials, identifiers) that keep memory and run time bounded.
//!
//! The parser ([`super::parse_str`]) first checks each value's type and
//! sign; [`check_case`] then checks the resolved case against these ranges
//! and relations, so that "absurd" has one definition, shared by the
//! dataset parser, the robot file, `sweep` and `helix`. A value outside its
//! range is an input error naming the field, the value and the range; it is
//! never clamped. The ranges are deliberately wide (a lab could build any
//! robot inside them); they exclude values at which the floating-point
//! evaluation of the model overflows, underflows or loses all precision.
//!
//! The table of limits is reproduced in `docs/notes/hardening.md`.

use super::Case;

/// A closed physical range of one field, with the reason for its ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limit {
    pub field: &'static str,
    pub min: f64,
    pub max: f64,
    pub unit: &'static str,
    pub why: &'static str,
}

const LENGTH_WHY: &str =
    "1 um to 10 m: below, the wire is thinner than any drawn wire; above, the \
     robot is no longer a cm-scale swimmer in a lab tube";

/// Every ranged numeric field of a case. Lengths share one range.
pub const LIMITS: &[Limit] = &[
    Limit { field: "wavelength_mm", min: 1e-3, max: 1e4, unit: "mm", why: LENGTH_WHY },
    Limit { field: "amplitude_mm", min: 1e-3, max: 1e4, unit: "mm", why: LENGTH_WHY },
    Limit { field: "tail_length_mm", min: 1e-3, max: 1e4, unit: "mm", why: LENGTH_WHY },
    Limit { field: "wire_diameter_mm", min: 1e-3, max: 1e4, unit: "mm", why: LENGTH_WHY },
    Limit { field: "channel_diameter_mm", min: 1e-3, max: 1e4, unit: "mm", why: LENGTH_WHY },
    Limit { field: "channel_length_mm", min: 1e-3, max: 1e5, unit: "mm", why: "up to 100 m of tube" },
    Limit { field: "body_diameter_mm", min: 1e-3, max: 1e4, unit: "mm", why: LENGTH_WHY },
    Limit { field: "body_length_mm", min: 1e-3, max: 1e4, unit: "mm", why: LENGTH_WHY },
    Limit { field: "coupler_diameter_mm", min: 0.0, max: 1e4, unit: "mm", why: "0 (no coupler) to 10 m" },
    Limit { field: "coupler_length_mm", min: 0.0, max: 1e4, unit: "mm", why: "0 (no coupler) to 10 m" },
    Limit { field: "coupler_gap_mm", min: 0.0, max: 1e4, unit: "mm", why: "coupler to seal; the spin solver refuses below 0.05 coupler radii" },
    Limit {
        field: "frequency_hz",
        min: 1e-6,
        max: 1e4,
        unit: "Hz",
        why: "a motor turns a tail at most at 10 kHz (600 000 rpm); below 1 uHz nothing moves within a lab's lifetime",
    },
    Limit {
        field: "viscosity_pa_s",
        min: 1e-6,
        max: 1e6,
        unit: "Pa s",
        why: "from below any gas (air 1.8e-5) to above the stiffest silicone gums (~1e5); Stokes flow needs a liquid",
    },
    Limit {
        field: "density_kg_m3",
        min: 0.1,
        max: 3e4,
        unit: "kg/m^3",
        why: "from a light gas to above the densest element (osmium, 22 590)",
    },
    Limit {
        field: "net_weight_g",
        min: 0.0,
        max: 1e4,
        unit: "g (absolute value)",
        why: "a trim error of up to 10 kg either way: beyond, the robot is not a swimmer but a sinker or a float",
    },
    Limit {
        field: "u_mm_s",
        min: 1e-6,
        max: 1e6,
        unit: "mm/s (absolute value)",
        why: "the error is relative to the measured mean, so 0 is undefined; 1 nm/s to 1 km/s",
    },
    Limit {
        field: "omega_body_hz",
        min: 1e-6,
        max: 1e4,
        unit: "Hz (absolute value)",
        why: "the error is relative to the measured mean, so 0 is undefined; as frequency_hz",
    },
    Limit {
        field: "confidence",
        min: 0.5,
        max: 0.999_999,
        unit: "",
        why: "a level below 0.5 or at 1 makes the Student-t factor 0 or infinite",
    },
];

/// The smallest confidence half-width relative to the mean's magnitude. A
/// narrower interval (or identical raw trials) gives the residual an
/// almost infinite weight: the chi-square overflows and the fit's SVD fails.
/// No speed or rate is measured to better than a part in 10^9.
pub const MIN_RELATIVE_CI: f64 = 1e-9;
/// The widest confidence half-width relative to the mean's magnitude.
pub const MAX_RELATIVE_CI: f64 = 1e6;
/// Trials behind one mean (`trials`, or the length of a raw-trials list).
pub const MAX_TRIALS: u32 = 100_000;
/// Cases in one dataset: every command evaluates the model per case, the
/// fit many times per case, so this bounds run time and memory.
pub const MAX_CASES: usize = 10_000;
/// Columns of a CSV dataset: the format's fields, their uncertainties and
/// a lab's recorded variables are a few dozen; a row of a million names is
/// no dataset (each name is checked against every field's for typos).
pub const MAX_COLUMNS: usize = 10_000;
/// Helix turns on one tail (`tail_length_mm / wavelength_mm`): every tail
/// model's cost grows with them (quadrature nodes, non-local segments); the
/// paper's tails have fewer than 15.
pub const MAX_TURNS: f64 = 1_000.0;
/// Quadrature nodes on one tail (`--nodes-per-wavelength` times turns): a
/// loop of 10^7 nodes takes well under a second; the paper used 100 per
/// wavelength.
pub const MAX_QUADRATURE_NODES: f64 = 1e7;
/// Characters in a case or tail id (it is a column of the tables).
pub const MAX_ID_CHARS: usize = 64;

/// The range of a user effect's multiplier at a place (`tail.c_n`,
/// `body.D_x`, ...): no physical effect changes a drag or thrust coefficient
/// by more than a factor of a million, and beyond it the model leaves the
/// floating-point range (a thrust multiplier of 1e300 overflowed to a
/// non-finite speed, 1e-300 to a NaN in the uncertainty check).
pub const USER_MULTIPLIER_RANGE: (f64, f64) = (1e-6, 1e6);
/// The largest magnitude of a user effect's added load (mN at `load.force`,
/// uN m at `load.torque`, rad/s at `drive.rate`): 1e6 mN is 1 kN, a
/// hundred thousand times the weight of the paper's robot.
pub const MAX_USER_LOAD: f64 = 1e6;

/// The largest standard uncertainty of an input relative to its value. The
/// propagation is first order (GUM 5.1.2): it holds while the model is
/// close to linear over the input's spread, which a spread of half the
/// value already strains; beyond it the input was not measured (a length
/// of 2.5 +- 1e6 mm could be negative), and the huge band it gives calls
/// any model "within the uncertainty" (`amplitude_mm = 1e6` turned a
/// 295 % error into "none needed").
pub const MAX_RELATIVE_INPUT_UNCERTAINTY: f64 = 0.5;

/// The largest standard uncertainty of the trim `net_weight_g`, relative
/// to the mass of the oil the body displaces. The trim is signed and often
/// 0, so a bound relative to its value cannot serve; a trim known only to
/// a tenth of the displaced oil (1.4 g, 13 mN on the paper's robot, whose
/// swimming thrust is a few mN) is no trim at all.
pub const MAX_TRIM_UNCERTAINTY_OF_DISPLACED: f64 = 0.1;

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

/// Characters in one formula of a user effect. A physical law fits in a
/// line or two; the evaluator walks the formula's tree recursively once per
/// case and fit step, so the length bounds its depth (a sum of 500 terms)
/// and its cost.
pub const MAX_FORMULA_CHARS: usize = 1_000;
/// Nesting of one formula: parentheses, calls, signs and powers inside one
/// another. The parser and the evaluator recurse once per level; without
/// this limit 8 000 nested parentheses overflow the stack (exit 134).
/// No law needs more than a handful of levels.
pub const MAX_FORMULA_DEPTH: usize = 64;
/// Bytes in one effects file (TOML): a file of a few dozen effects is a few
/// kB; the whole file is read into memory and parsed at once.
pub const MAX_EFFECT_FILE_BYTES: u64 = 1 << 20;
/// Characters of the user's own input that an error message repeats
/// (identifiers, formulas, values): beyond it the echo is cut and the
/// length said, so that a 10 MB identifier gives a one-line message.
pub const MAX_ECHO_CHARS: usize = 120;

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

/// The range of `field`, if it has one.
pub fn limit_of(field: &str) -> Option<&'static Limit> {
    LIMITS.iter().find(|l| l.field == field)
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
