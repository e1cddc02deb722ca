//! The second held-out catalogue (docs/held-out-2.md): twelve kinds of
//! physical effect, K14-K25, none of them a kind of batch 1 (K1-K13) or of
//! the development sets, each a fixture law of the model that the search
//! never sees. Where each law comes from is stated in the catalogue table
//! of docs/held-out-2.md; the variant docs give the law.

use crate::held_out::{onset, Law};
use nalgebra::Matrix6;
use rand::{rngs::StdRng, Rng};
use std::f64::consts::PI;
use swimbot::data::Case;
use swimbot::physics::coefficients::LocalDrag;
use swimbot::physics::solve::ForceBalance;

/// The cell voltage at which the drive's rate was set (V): a full Li-Po.
const FULL_CELL_V: f64 = 4.2;
/// Young's modulus of annealed copper (Pa), for the tail's bending
/// stiffness `E pi d^4 / 64`.
const COPPER_E_PA: f64 = 117e9;
/// Euler's constant, in Lamb's drag on a cylinder.
const EULER_GAMMA: f64 = 0.577_215_664_901_532_9;

/// One drawn truth: its kind and constants.
#[derive(Clone, Copy, Debug)]
pub enum Kind {
    /// K14 the body nears the tube's closed end: `D_x (1 + k max(0, h0/h - 1))`,
    /// h the recorded `window_below_end_mm`.
    EndApproach { k: f64, h0_mm: f64 },
    /// K15 an open-loop drive on a sagging cell: rate `(V - V_d)/(4.2 V - V_d)`,
    /// V the recorded `cell_voltage_v`.
    CellSag { v_drop: f64 },
    /// K16 oil taken up through the body's seal: axial load
    /// `-w days`, days the recorded `days_since_fill` (w in mN a day).
    SealIngress { w_mn_per_day: f64 },
    /// K17 the oil's pressure-viscosity (Barus) `mu exp(alpha p)`, p the
    /// recorded `gauge_pressure_kpa`, on body and tail alike at neutral trim.
    PressureViscosity { alpha_per_pa: f64 },
    /// K18 the flexible helix deforming past a critical elastoviscous
    /// number `S = mu omega L_t^4/(E I)`: thrust `1 - k max(0, 1 - S0/S)`.
    ElasticHelix { k: f64, s0: f64 },
    /// K19 a speed controller whose PWM saturates: rate
    /// `min(1, f_full (V/4.2 V) / f)`, V the recorded `cell_voltage_v`.
    PwmHeadroom { f_full_hz: f64 },
    /// K20 the body off the tube's axis by the recorded `body_offset_mm`:
    /// `E_x (1 + a (phi(eps) - 1))`, phi Sommerfeld's eccentric-annulus torque.
    EccentricBody { a: f64 },
    /// K21 the finite helix's end effect: thrust `1 - a lambda/L_t`.
    EndEffect { a: f64 },
    /// K22 a coated wire, hydrodynamic diameter `d (1 + c)`, in Lighthill's
    /// logarithms: nearly one constant on `c_t` and `c_n` together.
    CoatedWire { c: f64 },
    /// K23 the tail's swirl, confined by the tube, turning the body: load
    /// torque `k (D_b/D_ch)^2 B_t[wx,wx] omega` in the tail's sense.
    BodySwirl { k: f64 },
    /// K24 the wire's inertia in thin oils: Lamb's `c_n` where its Oseen
    /// length falls below Lighthill's `q` (an onset in the wire's Reynolds number).
    LambInertia,
    /// K25 the tail's axis tilted by the recorded `tail_tilt_deg`: rotational
    /// drag `1 + kappa sin^2(alpha) (L_t/R_h)^2 / 3`, the swept cone.
    TailTilt { kappa: f64 },
}

impl Kind {
    /// The place the law acts at; `None` where it cannot be observed.
    pub fn place(self) -> Option<&'static str> {
        Some(match self {
            Kind::EndApproach { .. } => "body.D_x",
            Kind::CellSag { .. } | Kind::PwmHeadroom { .. } => "drive.rate",
            Kind::SealIngress { .. } => "load.force",
            Kind::PressureViscosity { .. } => return None,
            Kind::ElasticHelix { .. } | Kind::EndEffect { .. } => "tail.thrust",
            Kind::EccentricBody { .. } => "body.E_x",
            Kind::CoatedWire { .. } => "tail.viscosity",
            Kind::BodySwirl { .. } => "load.torque",
            Kind::LambInertia => "tail.c_n",
            Kind::TailTilt { .. } => "tail.torque",
        })
    }

    /// The truth is in effect a constant at its place over the design.
    pub fn is_constant(self) -> bool {
        matches!(self, Kind::CoatedWire { .. })
    }
}

fn recorded(c: &Case, name: &str) -> f64 {
    c.recorded
        .value(name)
        .unwrap_or_else(|| panic!("case {}: the design records {name}", c.id))
}

/// The tail's elastoviscous number `mu omega L_t^4 / (E pi d^4/64)`.
pub fn elastoviscous(c: &Case) -> f64 {
    let d = c.wire_diameter_mm * 1e-3;
    let ei = COPPER_E_PA * PI * d.powi(4) / 64.0;
    c.viscosity_pa_s * c.tail_rate_rad_s() * (c.tail_length_mm * 1e-3).powi(4) / ei
}

/// Sommerfeld's torque on a journal at eccentricity ratio `eps` over the
/// concentric (Petroff) torque: `2 (1 + 2 eps^2) / ((2 + eps^2) sqrt(1 - eps^2))`.
pub fn eccentric_torque_ratio(eps: f64) -> f64 {
    2.0 * (1.0 + 2.0 * eps * eps) / ((2.0 + eps * eps) * (1.0 - eps * eps).sqrt())
}

/// The annular gap around the body (mm).
pub fn body_gap_mm(c: &Case) -> f64 {
    0.5 * (c.channel_diameter_mm - c.body_diameter_mm)
}

/// Lamb's normal drag over Lighthill's: `(ln(q/a) + 1/2)/(ln(4 e^-gamma/Re_a) + 1/2)`
/// where the Oseen length is the shorter, 1 otherwise; `q = 0.09` of the
/// wire's arc length per wave, `a` its radius, `Re_a = rho omega B_o a/mu`.
pub fn lamb_factor(c: &Case) -> f64 {
    let a = 0.5 * c.wire_diameter_mm;
    let arc = (c.wavelength_mm.powi(2) + (2.0 * PI * c.amplitude_mm).powi(2)).sqrt();
    let stokes = (0.09 * arc / a).ln();
    let re_a =
        c.density_kg_m3 * c.tail_rate_rad_s() * c.amplitude_mm * 1e-3 * a * 1e-3 / c.viscosity_pa_s;
    let oseen = (4.0 * (-EULER_GAMMA).exp() / re_a).ln();
    if oseen < stokes {
        (stokes + 0.5) / (oseen + 0.5)
    } else {
        1.0
    }
}

impl Law for Kind {
    fn local_drag(&self, c: &Case, drag: &mut LocalDrag) {
        match *self {
            Kind::PressureViscosity { alpha_per_pa } => {
                *drag = drag.scaled(pressure_factor(c, alpha_per_pa))
            }
            Kind::CoatedWire { c: coat } => {
                let l = (2.0 * c.wavelength_mm / c.wire_diameter_mm).ln();
                let dl = (1.0 + coat).ln();
                drag.tangential *= l / (l - dl);
                drag.normal *= (l + 0.5) / (l + 0.5 - dl);
            }
            Kind::LambInertia => drag.normal *= lamb_factor(c),
            _ => {}
        }
    }
    fn tail(&self, c: &Case, t: &mut Matrix6<f64>) {
        let thrust = match *self {
            Kind::ElasticHelix { k, s0 } => 1.0 - k * (1.0 - s0 / elastoviscous(c)).max(0.0),
            Kind::EndEffect { a } => 1.0 - a * c.wavelength_mm / c.tail_length_mm,
            Kind::TailTilt { kappa } => {
                let s = recorded(c, "tail_tilt_deg").to_radians().sin();
                let r_h = c.amplitude_mm + 0.5 * c.wire_diameter_mm;
                t[(3, 3)] *= 1.0 + kappa * s * s * (c.tail_length_mm / r_h).powi(2) / 3.0;
                1.0
            }
            _ => 1.0,
        };
        t[(0, 3)] *= thrust;
        t[(3, 0)] *= thrust;
    }
    fn body(&self, c: &Case, b: &mut Matrix6<f64>) {
        match *self {
            Kind::EndApproach { k, h0_mm } => {
                b[(0, 0)] *= 1.0 + k * onset(h0_mm / recorded(c, "window_below_end_mm"), 1.0, 1.0)
            }
            Kind::PressureViscosity { alpha_per_pa } => *b *= pressure_factor(c, alpha_per_pa),
            Kind::EccentricBody { a } => {
                let eps = recorded(c, "body_offset_mm") / body_gap_mm(c);
                b[(3, 3)] *= 1.0 + a * (eccentric_torque_ratio(eps) - 1.0);
            }
            _ => {}
        }
    }
    fn balance(&self, c: &Case, fb: &mut ForceBalance) {
        match *self {
            Kind::CellSag { v_drop } => {
                let v = recorded(c, "cell_voltage_v");
                fb.tail_rate_rad_s *= (v - v_drop) / (FULL_CELL_V - v_drop);
            }
            Kind::PwmHeadroom { f_full_hz } => {
                let f_max = f_full_hz * recorded(c, "cell_voltage_v") / FULL_CELL_V;
                fb.tail_rate_rad_s *= (f_max / c.frequency_hz).min(1.0);
            }
            Kind::SealIngress { w_mn_per_day } => {
                fb.load[0] -= w_mn_per_day * recorded(c, "days_since_fill") * 1e-3
            }
            Kind::BodySwirl { k } => {
                let share = k * (c.body_diameter_mm / c.channel_diameter_mm).powi(2);
                fb.load[3] += SWIRL_SENSE * share * fb.tail[(3, 3)] * fb.tail_rate_rad_s;
            }
            _ => {}
        }
    }
}

/// The sign that puts the swirl's torque on the body in the tail's sense
/// (it slows the body's counter-rotation); checked in `check_swirl_sense`.
pub const SWIRL_SENSE: f64 = 1.0;

fn pressure_factor(c: &Case, alpha_per_pa: f64) -> f64 {
    (alpha_per_pa * recorded(c, "gauge_pressure_kpa") * 1e3).exp()
}

/// The kinds' numbers in the catalogue.
pub const FIRST: usize = 14;
pub const LAST: usize = 25;

/// Draw kind `n`'s constants from the catalogue's ranges; `load_mn` is the
/// base model's load scale and `s_ref` the paper's median elastoviscous
/// number.
pub fn draw_kind(n: usize, r: &mut StdRng, load_mn: f64, s_ref: f64) -> Kind {
    match n {
        14 => Kind::EndApproach {
            k: r.gen_range(0.3..0.8),
            h0_mm: r.gen_range(40.0..70.0),
        },
        15 => Kind::CellSag {
            v_drop: r.gen_range(0.2..0.5),
        },
        16 => Kind::SealIngress {
            w_mn_per_day: load_mn * r.gen_range(0.15..0.45) / 40.0,
        },
        17 => Kind::PressureViscosity {
            alpha_per_pa: r.gen_range(1e-8..2e-8),
        },
        18 => Kind::ElasticHelix {
            k: r.gen_range(0.15..0.3),
            s0: s_ref * r.gen_range(0.9..1.3),
        },
        19 => Kind::PwmHeadroom {
            f_full_hz: r.gen_range(1.4..1.8),
        },
        20 => Kind::EccentricBody {
            a: r.gen_range(0.5..1.0),
        },
        21 => Kind::EndEffect {
            a: r.gen_range(0.2..0.5),
        },
        22 => Kind::CoatedWire {
            c: r.gen_range(0.3..0.6),
        },
        23 => Kind::BodySwirl {
            k: r.gen_range(0.1..0.3),
        },
        24 => Kind::LambInertia,
        25 => Kind::TailTilt {
            kappa: r.gen_range(0.5..1.0),
        },
        _ => panic!("K{n} is not in the second catalogue (K{FIRST}-K{LAST})"),
    }
}

/// What kind `n` needs of a case: its recorded column or the field it
/// varies, drawn from the design's stream in kind order.
pub fn vary_for(n: usize, v: &mut Case, r: &mut StdRng) {
    let record = |v: &mut Case, name: &str, x: f64| v.recorded.values.push((name.into(), x));
    match n {
        14 => record(v, "window_below_end_mm", r.gen_range(20.0..200.0)),
        15 => record(v, "cell_voltage_v", r.gen_range(3.5..4.2)),
        16 => record(v, "days_since_fill", r.gen_range(0.0..40.0)),
        17 => {
            record(v, "gauge_pressure_kpa", r.gen_range(0.0..50.0));
            // neutral trim: a viscosity common to body and tail cancels
            v.net_weight_g = 0.0;
        }
        18 => v.viscosity_pa_s *= r.gen_range(0.5..1.5),
        19 => record(v, "cell_voltage_v", r.gen_range(3.6..4.2)),
        20 => {
            let eps = r.gen_range(0.0..0.75);
            record(v, "body_offset_mm", eps * body_gap_mm(v));
        }
        24 => v.viscosity_pa_s *= r.gen_range(0.008f64.ln()..0.2f64.ln()).exp(),
        25 => record(v, "tail_tilt_deg", r.gen_range(0.0..2.0)),
        _ => {}
    }
}
