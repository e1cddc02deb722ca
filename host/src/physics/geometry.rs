//! Geometry of the two-link swimmer in the swimmer frame (paper section II.B,
//! Fig. 3): a rigid helical tail behind an axisymmetric body, in a circular
//! channel.
//!
//! Frame: `x` is the robot's long axis, pointing from the tail to the body
//! (the swimming direction, "up" in the vertical channel); the origin is the
//! body's centre. All lengths inside the model are metres; constructors that
//! take millimetres say so in their names.
//!
//! The tail centre-line, with axial coordinate `xi` in `[0, L_t]` measured
//! backwards from the joint at `x_joint`, is
//!
//! ```text
//! P(xi) = ( x_joint - xi,  B cos(k xi + phi),  -chi B sin(k xi + phi) ),   k = 2 pi / lambda
//! ```
//!
//! with `chi = +1` for a right-handed helix (positive torsion), `-1` for its
//! mirror image. Arc length per unit axial length is
//! `l / L_t = sqrt(1 + (k B)^2)` (the paper's `1/alpha`).

use std::f64::consts::PI;

/// Handedness of the helix; the paper's tails are right-handed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Handedness {
    Right,
    Left,
}

impl Handedness {
    /// `chi` in the centre-line formula: +1 right-handed, -1 left-handed.
    pub fn sign(self) -> f64 {
        match self {
            Handedness::Right => 1.0,
            Handedness::Left => -1.0,
        }
    }

    pub fn mirrored(self) -> Self {
        match self {
            Handedness::Right => Handedness::Left,
            Handedness::Left => Handedness::Right,
        }
    }
}

/// A uniform rigid helix of round wire (the tail).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Helix {
    /// Helix pitch `lambda` (m).
    pub wavelength_m: f64,
    /// Centre-line radius `B_o` (m), the paper's "amplitude".
    pub amplitude_m: f64,
    /// Axial (apparent) length `L_t` (m).
    pub axial_length_m: f64,
    /// Wire diameter `D_t` (m).
    pub wire_diameter_m: f64,
    pub handedness: Handedness,
    /// Phase `phi` of the centre-line at the joint (rad).
    pub phase_rad: f64,
    /// Axial position of the joint end of the helix in the swimmer frame (m).
    pub joint_x_m: f64,
}

impl Helix {
    /// A right-handed helix with zero phase whose joint is at the origin.
    pub fn from_mm(
        wavelength_mm: f64,
        amplitude_mm: f64,
        axial_length_mm: f64,
        wire_diameter_mm: f64,
    ) -> Self {
        Helix {
            wavelength_m: wavelength_mm * 1e-3,
            amplitude_m: amplitude_mm * 1e-3,
            axial_length_m: axial_length_mm * 1e-3,
            wire_diameter_m: wire_diameter_mm * 1e-3,
            handedness: Handedness::Right,
            phase_rad: 0.0,
            joint_x_m: 0.0,
        }
    }

    /// Axial wavenumber `k = 2 pi / lambda` (1/m).
    pub fn wavenumber(&self) -> f64 {
        2.0 * PI / self.wavelength_m
    }

    /// `l / L_t = sqrt(1 + (k B)^2)`: arc length per unit axial length.
    pub fn arc_per_axial(&self) -> f64 {
        (1.0 + (self.wavenumber() * self.amplitude_m).powi(2)).sqrt()
    }

    /// Wire (chord) length `l` (m).
    pub fn arc_length_m(&self) -> f64 {
        self.axial_length_m * self.arc_per_axial()
    }

    /// The paper's `alpha = L_t / l`.
    pub fn alpha(&self) -> f64 {
        1.0 / self.arc_per_axial()
    }

    /// Number of waves `N_lambda = L_t / lambda`.
    pub fn n_waves(&self) -> f64 {
        self.axial_length_m / self.wavelength_m
    }

    /// Pitch angle between the tangent and the axis, `atan(k B)` (rad).
    pub fn pitch_angle_rad(&self) -> f64 {
        (self.wavenumber() * self.amplitude_m).atan()
    }

    /// Outer radius of the tail envelope, centre-line radius plus wire radius (m).
    pub fn envelope_radius_m(&self) -> f64 {
        self.amplitude_m + 0.5 * self.wire_diameter_m
    }

    /// Centre-line point at axial coordinate `xi` (m from the joint).
    pub fn point(&self, xi: f64) -> [f64; 3] {
        let th = self.wavenumber() * xi + self.phase_rad;
        let chi = self.handedness.sign();
        [
            self.joint_x_m - xi,
            self.amplitude_m * th.cos(),
            -chi * self.amplitude_m * th.sin(),
        ]
    }

    /// Unit tangent at `xi`, pointing from the joint towards the free end.
    pub fn tangent(&self, xi: f64) -> [f64; 3] {
        let k = self.wavenumber();
        let th = k * xi + self.phase_rad;
        let chi = self.handedness.sign();
        let g = self.arc_per_axial();
        let kb = k * self.amplitude_m;
        [-1.0 / g, -kb * th.sin() / g, -chi * kb * th.cos() / g]
    }

    /// The mirror image through the x-y plane (z -> -z): opposite handedness.
    pub fn mirrored(&self) -> Self {
        Helix {
            handedness: self.handedness.mirrored(),
            ..*self
        }
    }
}

/// The axisymmetric body, modelled as a prolate spheroid of the overall
/// length and diameter (Table I).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    pub length_m: f64,
    pub diameter_m: f64,
}

impl Body {
    pub fn from_mm(length_mm: f64, diameter_mm: f64) -> Self {
        Body {
            length_m: length_mm * 1e-3,
            diameter_m: diameter_mm * 1e-3,
        }
    }

    pub fn radius_m(&self) -> f64 {
        0.5 * self.diameter_m
    }
}

/// The coupler shaft between the body and the tail (a short cylinder on the axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coupler {
    pub length_m: f64,
    pub diameter_m: f64,
}

/// The circular channel the robot swims in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Channel {
    pub diameter_m: f64,
    pub length_m: f64,
    /// Both ends sealed: the robot's displaced volume must flow back past it.
    pub closed: bool,
    /// Vertical channel: weight and buoyancy act along the swimming axis.
    pub vertical: bool,
}

impl Channel {
    pub fn radius_m(&self) -> f64 {
        0.5 * self.diameter_m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_is_unit_and_matches_centre_line_derivative() {
        let h = Helix {
            phase_rad: 0.7,
            ..Helix::from_mm(15.5, 2.5, 130.0, 1.0)
        };
        for i in 0..50 {
            let xi = i as f64 * h.axial_length_m / 49.0;
            let t = h.tangent(xi);
            let n = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
            assert!((n - 1.0).abs() < 1e-12);
            let d = 1e-7;
            let (a, b) = (h.point(xi - d), h.point(xi + d));
            let g = h.arc_per_axial();
            for c in 0..3 {
                let fd = (b[c] - a[c]) / (2.0 * d) / g;
                assert!((fd - t[c]).abs() < 1e-6, "component {c}: {fd} vs {}", t[c]);
            }
        }
    }

    #[test]
    fn right_handed_helix_has_positive_torsion() {
        // torsion sign = sign((r' x r'') . r''') for any regular parametrisation
        for (hand, expected) in [(Handedness::Right, 1.0), (Handedness::Left, -1.0)] {
            let h = Helix {
                handedness: hand,
                ..Helix::from_mm(10.0, 2.5, 88.0, 1.0)
            };
            let d = 1e-4;
            let p = |s: f64| h.point(s);
            let xi = 0.013;
            let (pm2, pm1, p0, pp1, pp2) = (
                p(xi - 2.0 * d),
                p(xi - d),
                p(xi),
                p(xi + d),
                p(xi + 2.0 * d),
            );
            let mut r1 = [0.0; 3];
            let mut r2 = [0.0; 3];
            let mut r3 = [0.0; 3];
            for c in 0..3 {
                r1[c] = (pp1[c] - pm1[c]) / (2.0 * d);
                r2[c] = (pp1[c] - 2.0 * p0[c] + pm1[c]) / (d * d);
                r3[c] = (pp2[c] - 2.0 * pp1[c] + 2.0 * pm1[c] - pm2[c]) / (2.0 * d * d * d);
            }
            let cross = [
                r1[1] * r2[2] - r1[2] * r2[1],
                r1[2] * r2[0] - r1[0] * r2[2],
                r1[0] * r2[1] - r1[1] * r2[0],
            ];
            let triple = cross[0] * r3[0] + cross[1] * r3[1] + cross[2] * r3[2];
            assert_eq!(triple.signum(), expected, "{hand:?}");
        }
    }

    #[test]
    fn paper_tail_one_arc_length() {
        let h = Helix::from_mm(15.5, 2.5, 130.0, 1.0);
        let expected = 130.0 * (1.0 + (2.0 * PI * 2.5 / 15.5f64).powi(2)).sqrt();
        assert!((h.arc_length_m() * 1e3 - expected).abs() < 1e-9);
        assert!((h.n_waves() - 130.0 / 15.5).abs() < 1e-12);
    }
}
