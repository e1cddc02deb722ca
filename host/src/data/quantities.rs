//! Case quantities: the dataset's own fields and the dimensionless groups a
//! physicist would try when a correction must scale with something.
//!
//! Each quantity has an identifier (`id`, usable in effect formulas and on
//! the command line), a name that states its formula in the paper's symbols
//! (`lambda`, `B_o`, `L_t`, `D_t`, `R_ch`/`D_ch`, `R_body`, `f`, `omega`,
//! `ell`), a unit and one line of meaning. A quantity that involves the
//! channel names `R_ch` or `D_ch`; one that involves the tail's rate names
//! `f`, `omega` or `shear`.
//!
//! The chord length `ell` of the wire follows from the recorded helix:
//! `ell = L_t sqrt(1 + (2 pi B_o / lambda)^2)` (the paper's `alpha = L_t/ell`).

use super::Case;
use std::f64::consts::PI;

/// One case quantity.
pub struct Quantity {
    /// Identifier in formulas: `[a-z][a-z0-9_]*`.
    pub id: &'static str,
    /// The formula in the paper's symbols.
    pub name: &'static str,
    pub unit: &'static str,
    pub doc: &'static str,
    pub value: fn(&Case) -> f64,
}

impl Quantity {
    pub fn of(&self, case: &Case) -> f64 {
        (self.value)(case)
    }
}

/// Radial clearance between the helix's outer edge and the wall (mm).
fn tail_gap_mm(c: &Case) -> f64 {
    0.5 * c.channel_diameter_mm - c.amplitude_mm - 0.5 * c.wire_diameter_mm
}

/// The wire's chord length implied by the recorded helix (mm).
pub fn chord_length_mm(c: &Case) -> f64 {
    c.tail_length_mm * (1.0 + (2.0 * PI * c.amplitude_mm / c.wavelength_mm).powi(2)).sqrt()
}

/// Derived groups, the library `diagnose` searches over.
pub const FEATURES: &[Quantity] = &[
    Quantity {
        id: "amplitude_ratio",
        name: "B_o/R_body",
        unit: "1",
        doc: "helix amplitude against body radius: the paper's grouping variable",
        value: |c| c.amplitude_ratio(),
    },
    Quantity {
        id: "n_waves",
        name: "N_lambda = L_t/lambda",
        unit: "1",
        doc: "number of waves on the tail",
        value: |c| c.n_waves(),
    },
    Quantity {
        id: "pitch_angle_deg",
        name: "psi = atan(2 pi B_o/lambda)",
        unit: "deg",
        doc: "pitch angle of the helix",
        value: |c| {
            (2.0 * PI * c.amplitude_mm / c.wavelength_mm)
                .atan()
                .to_degrees()
        },
    },
    Quantity {
        id: "alpha",
        name: "alpha = L_t/ell",
        unit: "1",
        doc: "apparent tail length over the wire's chord length (eqs. 6-7)",
        value: |c| c.tail_length_mm / chord_length_mm(c),
    },
    Quantity {
        id: "slenderness",
        name: "1/ln(lambda/D_t)",
        unit: "1",
        doc: "the small parameter of RFT: large values mean a stubby wire",
        value: |c| 1.0 / (c.wavelength_mm / c.wire_diameter_mm).ln(),
    },
    Quantity {
        id: "helix_over_gap",
        name: "(B_o + D_t/2)/(R_ch - B_o - D_t/2)",
        unit: "1",
        doc: "the helix's outer radius over its gap to the wall: the confinement of the tail as a whole",
        value: |c| (c.amplitude_mm + 0.5 * c.wire_diameter_mm) / tail_gap_mm(c),
    },
    Quantity {
        id: "tail_clearance",
        name: "(B_o + D_t/2)/R_ch",
        unit: "1",
        doc: "how far the helix reaches towards the wall (1 = touching)",
        value: |c| (c.amplitude_mm + 0.5 * c.wire_diameter_mm) / (0.5 * c.channel_diameter_mm),
    },
    Quantity {
        id: "tail_gap_ratio",
        name: "(R_ch - B_o - D_t/2)/R_ch",
        unit: "1",
        doc: "radial gap between helix and wall over the channel radius",
        value: |c| tail_gap_mm(c) / (0.5 * c.channel_diameter_mm),
    },
    Quantity {
        id: "wire_over_gap",
        name: "(D_t/2)/(R_ch - B_o - D_t/2)",
        unit: "1",
        doc: "wire radius over its gap to the wall: lubrication grows with it",
        value: |c| 0.5 * c.wire_diameter_mm / tail_gap_mm(c),
    },
    Quantity {
        id: "body_ratio",
        name: "D_b/D_ch",
        unit: "1",
        doc: "body diameter over channel diameter",
        value: |c| c.body_diameter_mm / c.channel_diameter_mm,
    },
    Quantity {
        id: "body_gap_ratio",
        name: "(R_ch - R_body)/R_ch",
        unit: "1",
        doc: "annular gap around the body over the channel radius",
        value: |c| 1.0 - c.body_diameter_mm / c.channel_diameter_mm,
    },
    Quantity {
        id: "body_over_gap",
        name: "R_body/(R_ch - R_body)",
        unit: "1",
        doc:
            "body radius over the annular gap to the wall: lubrication along the body grows with it",
        value: |c| c.body_diameter_mm / (c.channel_diameter_mm - c.body_diameter_mm),
    },
    Quantity {
        id: "tail_length_ratio",
        name: "L_t/D_ch",
        unit: "1",
        doc: "tail length over channel diameter",
        value: |c| c.tail_length_mm / c.channel_diameter_mm,
    },
    Quantity {
        id: "wavelength_ratio",
        name: "lambda/D_ch",
        unit: "1",
        doc: "wavelength over channel diameter",
        value: |c| c.wavelength_mm / c.channel_diameter_mm,
    },
    Quantity {
        id: "tail_over_body",
        name: "L_t/L_b",
        unit: "1",
        doc: "tail length over body length",
        value: |c| c.tail_length_mm / c.body_length_mm,
    },
    Quantity {
        id: "frequency",
        name: "f",
        unit: "Hz",
        doc: "recorded tail rotation rate",
        value: |c| c.frequency_hz,
    },
    Quantity {
        id: "shear_rate",
        name: "shear = omega B_o/(D_t/2)",
        unit: "1/s",
        doc: "the wire's characteristic shear rate: the helix speed over the wire radius",
        value: |c| 2.0 * PI * c.frequency_hz * c.amplitude_mm / (0.5 * c.wire_diameter_mm),
    },
    Quantity {
        id: "wave_speed",
        name: "U_wave = lambda f",
        unit: "mm/s",
        doc: "speed of the helical wave along the tail",
        value: |c| c.wavelength_mm * c.frequency_hz,
    },
];

/// The dataset's numeric fields, by their names in the data format.
pub const FIELDS: &[Quantity] = &[
    Quantity {
        id: "wavelength_mm",
        name: "lambda",
        unit: "mm",
        doc: "helix wavelength",
        value: |c| c.wavelength_mm,
    },
    Quantity {
        id: "amplitude_mm",
        name: "B_o",
        unit: "mm",
        doc: "helix amplitude (centre-line radius)",
        value: |c| c.amplitude_mm,
    },
    Quantity {
        id: "tail_length_mm",
        name: "L_t",
        unit: "mm",
        doc: "axial tail length",
        value: |c| c.tail_length_mm,
    },
    Quantity {
        id: "wire_diameter_mm",
        name: "D_t",
        unit: "mm",
        doc: "wire diameter",
        value: |c| c.wire_diameter_mm,
    },
    Quantity {
        id: "frequency_hz",
        name: "f",
        unit: "Hz",
        doc: "recorded tail rotation rate",
        value: |c| c.frequency_hz,
    },
    Quantity {
        id: "channel_diameter_mm",
        name: "D_ch",
        unit: "mm",
        doc: "channel inner diameter",
        value: |c| c.channel_diameter_mm,
    },
    Quantity {
        id: "channel_length_mm",
        name: "L_ch",
        unit: "mm",
        doc: "channel length",
        value: |c| c.channel_length_mm,
    },
    Quantity {
        id: "viscosity_pa_s",
        name: "mu",
        unit: "Pa s",
        doc: "oil viscosity",
        value: |c| c.viscosity_pa_s,
    },
    Quantity {
        id: "density_kg_m3",
        name: "rho",
        unit: "kg/m^3",
        doc: "oil density",
        value: |c| c.density_kg_m3,
    },
    Quantity {
        id: "body_diameter_mm",
        name: "D_b",
        unit: "mm",
        doc: "body diameter",
        value: |c| c.body_diameter_mm,
    },
    Quantity {
        id: "body_length_mm",
        name: "L_b",
        unit: "mm",
        doc: "body length",
        value: |c| c.body_length_mm,
    },
    Quantity {
        id: "coupler_diameter_mm",
        name: "D_c",
        unit: "mm",
        doc: "coupler diameter",
        value: |c| c.coupler_diameter_mm,
    },
    Quantity {
        id: "coupler_length_mm",
        name: "L_c",
        unit: "mm",
        doc: "coupler length",
        value: |c| c.coupler_length_mm,
    },
    Quantity {
        id: "coupler_gap_mm",
        name: "g_c",
        unit: "mm",
        doc: "gap between the coupler and the body's seal",
        value: |c| c.coupler_gap_mm,
    },
];

/// Dimensionless groups of the setup fields (the oil, the channel's
/// length, the body and coupler), which a lab may vary between cases.
pub const SETUP_GROUPS: &[Quantity] = &[
    Quantity {
        id: "reynolds",
        name: "Re = rho omega B_o D_t/mu",
        unit: "1",
        doc: "the wire's Reynolds number: the helix speed omega B_o over the oil's kinematic viscosity, on the wire diameter",
        value: |c| {
            c.density_kg_m3 * 2.0 * PI * c.frequency_hz * c.amplitude_mm * c.wire_diameter_mm
                * 1e-6
                / c.viscosity_pa_s
        },
    },
    Quantity {
        id: "body_reynolds",
        name: "Re_b = rho omega R_body^2/mu",
        unit: "1",
        doc: "the body's rotational Reynolds number, with the omega the tail turns at",
        value: |c| {
            c.density_kg_m3 * 2.0 * PI * c.frequency_hz * (0.5 * c.body_diameter_mm).powi(2) * 1e-6
                / c.viscosity_pa_s
        },
    },
    Quantity {
        id: "channel_length_ratio",
        name: "L_ch/D_ch",
        unit: "1",
        doc: "channel length over channel diameter: end effects fade with it",
        value: |c| c.channel_length_mm / c.channel_diameter_mm,
    },
    Quantity {
        id: "body_aspect",
        name: "L_b/D_b",
        unit: "1",
        doc: "body length over body diameter",
        value: |c| c.body_length_mm / c.body_diameter_mm,
    },
    Quantity {
        id: "coupler_ratio",
        name: "D_c/D_b",
        unit: "1",
        doc: "coupler diameter over body diameter",
        value: |c| c.coupler_diameter_mm / c.body_diameter_mm,
    },
    Quantity {
        id: "coupler_length_ratio",
        name: "L_c/L_b",
        unit: "1",
        doc: "coupler length over body length",
        value: |c| c.coupler_length_mm / c.body_length_mm,
    },
];

/// A feature, a setup group, a field or a model quantity
/// ([`super::model_quantities`]) by its identifier.
pub fn by_id(id: &str) -> Option<&'static Quantity> {
    FEATURES
        .iter()
        .chain(SETUP_GROUPS)
        .chain(FIELDS)
        .chain(super::model_quantities::MODEL_QUANTITIES)
        .find(|q| q.id == id)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identifiers_are_unique_and_formula_safe() {
        let all: Vec<&Quantity> = FEATURES
            .iter()
            .chain(SETUP_GROUPS)
            .chain(FIELDS)
            .chain(super::super::model_quantities::MODEL_QUANTITIES)
            .collect();
        for (i, q) in all.iter().enumerate() {
            assert!(
                q.id.starts_with(|c: char| c.is_ascii_lowercase()),
                "{}",
                q.id
            );
            assert!(
                q.id.chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_'),
                "{}",
                q.id
            );
            assert!(all[..i].iter().all(|o| o.id != q.id), "duplicate {}", q.id);
            assert!(!q.doc.is_empty() && !q.unit.is_empty());
        }
    }

    /// The helix's confinement `R_h/gap` is `t/(1 - t)` of its clearance
    /// `t = R_h/R_ch`, and grows without bound as the helix nears the wall.
    #[test]
    fn helix_over_gap_is_the_clearance_over_what_is_left() {
        let by = |id: &str| FEATURES.iter().find(|q| q.id == id).expect(id);
        let (h, t) = (by("helix_over_gap"), by("tail_clearance"));
        let mut c = crate::data::paper().cases[0].clone();
        for d_ch in [14.0, 20.0, 35.0, 50.0] {
            c.channel_diameter_mm = d_ch;
            let t = t.of(&c);
            assert!((h.of(&c) - t / (1.0 - t)).abs() < 1e-12 * h.of(&c));
        }
        c.channel_diameter_mm = 2.0 * (c.amplitude_mm + 0.5 * c.wire_diameter_mm) + 1e-9;
        assert!(h.of(&c) > 1e6);
    }

    #[test]
    fn names_say_when_a_feature_involves_the_channel_or_the_rate() {
        let paper = crate::data::paper();
        let base = &paper.cases[2];
        for q in FEATURES.iter().chain(SETUP_GROUPS) {
            let mut wider = base.clone();
            wider.channel_diameter_mm *= 1.3;
            let mut faster = base.clone();
            faster.frequency_hz *= 1.3;
            if q.of(&wider) != q.of(base) {
                assert!(
                    q.name.contains("R_ch") || q.name.contains("D_ch"),
                    "{}",
                    q.name
                );
            }
            if q.of(&faster) != q.of(base) {
                assert!(
                    ["f", "omega", "shear"].iter().any(|s| q.name.contains(s)),
                    "{}",
                    q.name
                );
            }
        }
    }

    #[test]
    fn the_paper_tails_give_finite_features_and_the_known_chord_lengths() {
        let paper = crate::data::paper();
        for c in &paper.cases {
            for q in FEATURES {
                assert!(q.of(c).is_finite(), "{} on {}", q.id, c.id);
            }
        }
        // Tail #1: 130 mm x sqrt(1 + (2 pi 2.5 / 15.5)^2) = 130 x 1.42373.
        let ell = chord_length_mm(&paper.cases[0]);
        assert!((ell - 185.085).abs() < 0.01, "{ell}");
    }
}
