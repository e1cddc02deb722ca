//! The body's shape as a surface of revolution about the swimming axis:
//! either the model's prolate spheroid (`body_length_mm` x
//! `body_diameter_mm`), or coaxial cylindrical sections from nose to tail,
//! each `(length_mm, diameter_mm)`, joined by flat annular steps, with flat
//! end faces whose outer rims may be rounded by a fillet of radius
//! `rounded_mm` (equal to the end radius: a hemispherical end).
//!
//! [`BodyProfile::meridian`] gives the generating curve (axial `x`, radial
//! `sigma`, metres) from the nose on the axis to the tail on the axis, as
//! straight lines, circular arcs and an elliptical arc, with its sharp
//! corners (where the traction is singular and a mesh must be finer).
//!
//! References: the robot's parts, /work/shared/seed (cork 20 mm, glass
//! casing 18 mm, sealing element 20 mm); the spheroid as in the paper's
//! body model (eq. 10).

use std::f64::consts::PI;

/// One cylindrical section of the body.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Section {
    pub length_mm: f64,
    pub diameter_mm: f64,
}

/// The body's surface of revolution.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum BodyProfile {
    /// Prolate (or oblate) spheroid: full length and diameter.
    Spheroid { length_mm: f64, diameter_mm: f64 },
    /// Cylindrical sections from nose to tail; `rounded_mm` is the fillet
    /// radius of the nose's and the tail's outer rim (0: sharp).
    Sections {
        sections: Vec<Section>,
        rounded_mm: f64,
    },
}

/// One piece of a generating curve, parametrised by `t` in `[0, 1]`;
/// points are `[x, sigma]` in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Piece {
    Line {
        a: [f64; 2],
        b: [f64; 2],
    },
    /// Circular arc about `centre`, angle measured from `+x` towards `+sigma`.
    Arc {
        centre: [f64; 2],
        radius: f64,
        from_rad: f64,
        to_rad: f64,
    },
    /// Elliptical arc `x = cx + a cos th`, `sigma = b sin th`.
    Ellipse {
        centre_x: f64,
        semi_x: f64,
        semi_sigma: f64,
        from_rad: f64,
        to_rad: f64,
    },
}

impl Piece {
    pub fn point(&self, t: f64) -> [f64; 2] {
        match *self {
            Piece::Line { a, b } => [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])],
            Piece::Arc {
                centre,
                radius,
                from_rad,
                to_rad,
            } => {
                let th = from_rad + t * (to_rad - from_rad);
                [centre[0] + radius * th.cos(), centre[1] + radius * th.sin()]
            }
            Piece::Ellipse {
                centre_x,
                semi_x,
                semi_sigma,
                from_rad,
                to_rad,
            } => {
                let th = from_rad + t * (to_rad - from_rad);
                // The spheroid's arc runs pole to pole: exact zeros there
                // (sin(pi) is 1.2e-16, not 0).
                let s = if t <= 0.0 || t >= 1.0 {
                    0.0
                } else {
                    semi_sigma * th.sin()
                };
                [centre_x + semi_x * th.cos(), s]
            }
        }
    }

    /// `|dp/dt|` (metres per unit `t`).
    pub fn speed(&self, t: f64) -> f64 {
        match *self {
            Piece::Line { a, b } => (b[0] - a[0]).hypot(b[1] - a[1]),
            Piece::Arc {
                radius,
                from_rad,
                to_rad,
                ..
            } => radius * (to_rad - from_rad).abs(),
            Piece::Ellipse {
                semi_x,
                semi_sigma,
                from_rad,
                to_rad,
                ..
            } => {
                let th = from_rad + t * (to_rad - from_rad);
                (semi_x * th.sin()).hypot(semi_sigma * th.cos()) * (to_rad - from_rad).abs()
            }
        }
    }
}

/// A generating curve and its sharp corners.
#[derive(Debug, Clone, PartialEq)]
pub struct Meridian {
    pub pieces: Vec<Piece>,
    pub corners: Vec<[f64; 2]>,
}

impl BodyProfile {
    /// The prolate spheroid of the model's body.
    pub fn spheroid(length_mm: f64, diameter_mm: f64) -> Self {
        BodyProfile::Spheroid {
            length_mm,
            diameter_mm,
        }
    }

    /// One plain cylinder with flat ends rounded by `rounded_mm`.
    pub fn cylinder(length_mm: f64, diameter_mm: f64, rounded_mm: f64) -> Self {
        BodyProfile::Sections {
            sections: vec![Section {
                length_mm,
                diameter_mm,
            }],
            rounded_mm,
        }
    }

    /// `length:diameter,...` in mm, nose first (the `--profile` flag).
    pub fn parse_sections(spec: &str, rounded_mm: f64) -> Result<Self, ProfileError> {
        let mut sections = Vec::new();
        for (i, part) in spec.split(',').enumerate() {
            let (l, d) = part.split_once(':').ok_or_else(|| ProfileError::NotAPair {
                section: i + 1,
                text: part.to_string(),
            })?;
            let num = |v: &str, what: &'static str| {
                v.trim()
                    .parse::<f64>()
                    .map_err(|_| ProfileError::NotANumber {
                        section: i + 1,
                        text: part.to_string(),
                        what,
                        value: v.to_string(),
                    })
            };
            sections.push(Section {
                length_mm: num(l, "length")?,
                diameter_mm: num(d, "diameter")?,
            });
        }
        let p = BodyProfile::Sections {
            sections,
            rounded_mm,
        };
        p.validate()?;
        Ok(p)
    }

    /// Every length positive and finite, roundings that fit.
    pub fn validate(&self) -> Result<(), ProfileError> {
        let positive = |v: f64, field: String| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(ProfileError::NotPositive { field, value: v })
            }
        };
        match self {
            BodyProfile::Spheroid {
                length_mm,
                diameter_mm,
            } => {
                positive(*length_mm, "spheroid length_mm".into())?;
                positive(*diameter_mm, "spheroid diameter_mm".into())
            }
            BodyProfile::Sections {
                sections,
                rounded_mm,
            } => {
                if sections.is_empty() {
                    return Err(ProfileError::NoSections);
                }
                for (i, s) in sections.iter().enumerate() {
                    positive(s.length_mm, format!("section {} length_mm", i + 1))?;
                    positive(s.diameter_mm, format!("section {} diameter_mm", i + 1))?;
                }
                let r = *rounded_mm;
                if !(r.is_finite() && r >= 0.0) {
                    return Err(ProfileError::BadRounding(r));
                }
                let (first, last) = (sections[0], sections[sections.len() - 1]);
                let fits = if sections.len() == 1 {
                    2.0 * r <= first.length_mm && r <= 0.5 * first.diameter_mm
                } else {
                    r <= first.length_mm
                        && r <= last.length_mm
                        && r <= 0.5 * first.diameter_mm
                        && r <= 0.5 * last.diameter_mm
                };
                if !fits {
                    return Err(ProfileError::RoundingDoesNotFit(r));
                }
                Ok(())
            }
        }
    }

    pub fn length_mm(&self) -> f64 {
        match self {
            BodyProfile::Spheroid { length_mm, .. } => *length_mm,
            BodyProfile::Sections { sections, .. } => sections.iter().map(|s| s.length_mm).sum(),
        }
    }

    pub fn max_diameter_mm(&self) -> f64 {
        match self {
            BodyProfile::Spheroid { diameter_mm, .. } => *diameter_mm,
            BodyProfile::Sections { sections, .. } => {
                sections.iter().map(|s| s.diameter_mm).fold(0.0, f64::max)
            }
        }
    }

    /// Short human-readable description.
    pub fn describe(&self) -> String {
        match self {
            BodyProfile::Spheroid {
                length_mm,
                diameter_mm,
            } => format!("spheroid {length_mm} x {diameter_mm} mm"),
            BodyProfile::Sections {
                sections,
                rounded_mm,
            } => {
                let s: Vec<String> = sections
                    .iter()
                    .map(|s| format!("{}:{}", s.length_mm, s.diameter_mm))
                    .collect();
                format!("sections {} mm, ends rounded {rounded_mm} mm", s.join(","))
            }
        }
    }

    /// Volume (m^3), exact for the shape (fillets included).
    pub fn volume_m3(&self) -> f64 {
        match self {
            BodyProfile::Spheroid {
                length_mm,
                diameter_mm,
            } => PI / 6.0 * length_mm * diameter_mm * diameter_mm * 1e-9,
            BodyProfile::Sections {
                sections,
                rounded_mm,
            } => {
                let cyl: f64 = sections
                    .iter()
                    .map(|s| 0.25 * PI * s.diameter_mm * s.diameter_mm * s.length_mm)
                    .sum();
                // Each rounded rim removes the torus-corner volume
                // 2 pi [r^2 (1 - pi/4) R - r^3 (5/6 - pi/4)] (Pappus).
                let r = *rounded_mm;
                let rim = |d: f64| {
                    let big = 0.5 * d;
                    2.0 * PI * (r * r * (1.0 - PI / 4.0) * big - r.powi(3) * (5.0 / 6.0 - PI / 4.0))
                };
                let ends =
                    rim(sections[0].diameter_mm) + rim(sections[sections.len() - 1].diameter_mm);
                (cyl - ends) * 1e-9
            }
        }
    }

    /// The generating curve with the body centred at `centre_x_m`, nose at
    /// `+x`, from the nose on the axis to the tail on the axis.
    pub fn meridian(&self, centre_x_m: f64) -> Meridian {
        match self {
            BodyProfile::Spheroid {
                length_mm,
                diameter_mm,
            } => Meridian {
                pieces: vec![Piece::Ellipse {
                    centre_x: centre_x_m,
                    semi_x: 0.5e-3 * length_mm,
                    semi_sigma: 0.5e-3 * diameter_mm,
                    from_rad: 0.0,
                    to_rad: PI,
                }],
                corners: Vec::new(),
            },
            BodyProfile::Sections {
                sections,
                rounded_mm,
            } => sections_meridian(sections, rounded_mm * 1e-3, centre_x_m),
        }
    }
}

fn sections_meridian(sections: &[Section], rf: f64, centre_x: f64) -> Meridian {
    let total: f64 = sections.iter().map(|s| s.length_mm).sum::<f64>() * 1e-3;
    let (xn, xt) = (centre_x + 0.5 * total, centre_x - 0.5 * total);
    let radius = |i: usize| 0.5e-3 * sections[i].diameter_mm;
    let last = sections.len() - 1;
    let mut pieces = Vec::new();
    let mut corners = Vec::new();
    let line = |a: [f64; 2], b: [f64; 2], pieces: &mut Vec<Piece>| {
        if (b[0] - a[0]).hypot(b[1] - a[1]) > 1e-12 {
            pieces.push(Piece::Line { a, b });
        }
    };
    // Nose face and rim.
    let r0 = radius(0);
    line([xn, 0.0], [xn, r0 - rf], &mut pieces);
    if rf > 0.0 {
        pieces.push(Piece::Arc {
            centre: [xn - rf, r0 - rf],
            radius: rf,
            from_rad: 0.0,
            to_rad: 0.5 * PI,
        });
    } else {
        corners.push([xn, r0]);
    }
    let mut x = xn - rf;
    let mut x_end = xn;
    for (i, section) in sections.iter().enumerate() {
        let r = radius(i);
        if i > 0 {
            let rp = radius(i - 1);
            if (r - rp).abs() > 1e-12 {
                line([x, rp], [x, r], &mut pieces);
                corners.push([x, rp]);
                corners.push([x, r]);
            }
        }
        x_end -= section.length_mm * 1e-3;
        let stop = if i == last { xt + rf } else { x_end };
        line([x, r], [stop, r], &mut pieces);
        x = stop;
    }
    let rl = radius(last);
    if rf > 0.0 {
        pieces.push(Piece::Arc {
            centre: [xt + rf, rl - rf],
            radius: rf,
            from_rad: 0.5 * PI,
            to_rad: PI,
        });
    } else {
        corners.push([xt, rl]);
    }
    line([xt, rl - rf], [xt, 0.0], &mut pieces);
    Meridian { pieces, corners }
}

/// A body profile that is no body: the section (1-based, nose first) or
/// the field, and what is wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ProfileError {
    /// A section of a `--profile` spec, as written, without its `:`.
    #[error("section {section} `{text}`: expected `length_mm:diameter_mm`")]
    NotAPair { section: usize, text: String },
    /// A section's `length` or `diameter` that is not a number.
    #[error("section {section} `{text}`: {what} `{value}` is not a number")]
    NotANumber {
        section: usize,
        text: String,
        what: &'static str,
        value: String,
    },
    /// A length (`field`, e.g. `section 2 diameter_mm`) not positive and finite.
    #[error("{field} must be a positive finite number, got {value}")]
    NotPositive { field: String, value: f64 },
    #[error("the profile has no sections")]
    NoSections,
    #[error("rounded_mm must be finite and >= 0, got {0}")]
    BadRounding(f64),
    #[error(
        "rounded_mm {0} does not fit: it must not exceed the end sections' radii and lengths (half the length for a single section)"
    )]
    RoundingDoesNotFit(f64),
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ends(m: &Meridian) -> ([f64; 2], [f64; 2]) {
        (
            m.pieces[0].point(0.0),
            m.pieces[m.pieces.len() - 1].point(1.0),
        )
    }

    #[test]
    fn curves_are_continuous_and_run_axis_to_axis() {
        for p in [
            BodyProfile::spheroid(50.0, 20.0),
            BodyProfile::cylinder(50.0, 20.0, 0.0),
            BodyProfile::cylinder(50.0, 20.0, 10.0),
            BodyProfile::parse_sections("20:20,18:18,12:20", 3.0).unwrap(),
        ] {
            let m = p.meridian(0.01);
            let (a, b) = ends(&m);
            assert!((a[0] - 0.01 - 0.5e-3 * p.length_mm()).abs() < 1e-12 && a[1].abs() < 1e-15);
            assert!((b[0] - 0.01 + 0.5e-3 * p.length_mm()).abs() < 1e-12 && b[1].abs() < 1e-15);
            for w in m.pieces.windows(2) {
                let (e, s) = (w[0].point(1.0), w[1].point(0.0));
                assert!(
                    (e[0] - s[0]).hypot(e[1] - s[1]) < 1e-12,
                    "{p:?}: gap {e:?} {s:?}"
                );
            }
        }
    }

    #[test]
    fn bad_profiles_are_rejected_with_the_section_named() {
        let e = BodyProfile::parse_sections("10:20,x:18", 0.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("section 2"), "{e}");
        let e = BodyProfile::parse_sections("10:20,5:-1", 0.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("section 2 diameter_mm"), "{e}");
        assert!(BodyProfile::cylinder(10.0, 20.0, 6.0).validate().is_err());
        assert!(BodyProfile::cylinder(20.0, 20.0, 10.0).validate().is_ok());
    }

    #[test]
    fn volume_of_a_capsule() {
        // Cylinder 20 x 20 with hemispherical ends: a sphere of radius 10.
        let v = BodyProfile::cylinder(20.0, 20.0, 10.0).volume_m3();
        let sphere = 4.0 / 3.0 * PI * 1e-6;
        assert!((v / sphere - 1.0).abs() < 1e-12, "{v}");
    }
}
