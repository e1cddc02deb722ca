//! The documented input limits: for every numeric field of a case, the
//! physical range the model is meant for (and why), and the size limits
//! (cases, trials, identifiers) that keep memory and run time bounded.
//!
//! The parser ([`super::parse_str`]) first checks each value's type and
//! sign; [`check_case`] (`super::limit_check`: the checks and their
//! wording) then checks the resolved case against these ranges
//! and relations, so that "absurd" has one definition, shared by the
//! dataset parser, the robot file, `sweep` and `helix`. A value outside its
//! range is an input error naming the field, the value and the range; it is
//! never clamped. The ranges are deliberately wide (a lab could build any
//! robot inside them); they exclude values at which the floating-point
//! evaluation of the model overflows, underflows or loses all precision.
//!
//! The table of limits is reproduced in `docs/limits.md`.

pub use super::limit_check::{
    check_case, check_id, check_quadrature, check_value, echo, show, LimitError,
};

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

/// The range of `field`, if it has one.
pub fn limit_of(field: &str) -> Option<&'static Limit> {
    LIMITS.iter().find(|l| l.field == field)
}
