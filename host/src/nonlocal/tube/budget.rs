//! Memory and time of a tube solve, from the point counts alone, before
//! anything is built: the counts follow the same rules as `super::wall`
//! (checked against built walls in the tests below) but in floating point,
//! so a 1000 km tube is a large number, not an allocation.
//!
//! Memory is [`super::rings::peak_bytes`] or [`super::mfs::dense_peak_bytes`]
//! plus the `O(N)` arrays; measured against the process's peak resident
//! memory in `tests/tail_tube.rs`. Time is a floating-point operation count
//! over a sustained rate measured on this project's 2-core machine: an
//! order of magnitude, for announcing long work, not a promise.

use super::wall::{ring_count, CapLayout};
use super::{rings, TubeSettings, WallModel, WallSolver};
use std::f64::consts::PI;

/// Counts above this are not built to be counted (they are refused anyway).
pub const MAX_COUNTED: usize = 10_000_000;

/// Sustained rate of the dense kernels (LU, matrix products), flop/s,
/// measured on this machine (release build, 2 cores).
const FLOP_RATE: f64 = 1.5e10;
/// Time of one 3x3 kernel block (assembly and diagnostics), s.
const BLOCK_S: f64 = 3.0e-8;

/// Wall points of a tube: rings of `n_theta` stations and extra points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallCounts {
    pub n_rings: f64,
    pub n_theta: f64,
    pub n_extra: f64,
}

fn round1(v: f64) -> f64 {
    v.round().max(1.0)
}

/// Points of `surface::disc` at spacing `h` (axis point included).
fn disc_points(radius_m: f64, h: f64) -> f64 {
    let n_caps = round1(radius_m / h);
    if n_caps > 1e5 {
        return PI * (radius_m / h).powi(2);
    }
    let dr = radius_m / n_caps;
    1.0 + (1..n_caps as usize)
        .map(|j| round1(2.0 * PI * (j as f64 + 0.5) * dr / h))
        .sum::<f64>()
}

impl WallCounts {
    pub fn of(radius_m: f64, (x0_m, x1_m): (f64, f64), closed: bool, s: &TubeSettings) -> Self {
        let h = s.wall_spacing_m;
        let cylinder = round1((x1_m - x0_m) / h);
        let n_theta = if 2.0 * PI * radius_m / h < MAX_COUNTED as f64 {
            ring_count(radius_m, h) as f64
        } else {
            2.0 * PI * radius_m / h
        };
        let (cap_rings, cap_extra) = match (closed, s.wall, s.caps) {
            (false, _, _) => (0.0, 0.0),
            (true, WallModel::Leaky, _) => (0.0, disc_points(radius_m, h)),
            (true, WallModel::Mfs, CapLayout::Graded) => (1.0, disc_points(radius_m, h)),
            (true, WallModel::Mfs, CapLayout::Rings) => (round1(radius_m / h), 1.0),
        };
        WallCounts {
            n_rings: cylinder + 2.0 * cap_rings,
            n_theta,
            n_extra: 2.0 * cap_extra,
        }
    }

    pub fn n_points(&self) -> f64 {
        self.n_rings * self.n_theta + self.n_extra
    }
}

/// What a solve will cost, known before it starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Points of the moving objects and of the wall (3 unknowns each).
    pub n_moving: usize,
    pub n_wall: usize,
    /// Estimated peak memory (bytes) and wall-clock time (s) on 2 cores.
    pub peak_bytes: usize,
    pub seconds: f64,
}

fn to_count(v: f64) -> usize {
    if v < usize::MAX as f64 {
        v as usize
    } else {
        usize::MAX
    }
}

/// Quadrature points of the flux and wall-slip diagnostics.
fn diagnostic_points(w: &WallCounts) -> f64 {
    let per_section = 24.0 * (3.0 * w.n_theta).max(64.0);
    3.0 * per_section + 2.0 * w.n_points()
}

impl Budget {
    pub fn new(n_moving: usize, w: &WallCounts, solver: WallSolver) -> Self {
        let n_wall = w.n_points();
        let n = n_moving as f64 + n_wall;
        let (bytes, flops, blocks) = match solver {
            WallSolver::Dense => {
                let u = 3.0 * n;
                (
                    super::mfs::dense_peak_bytes(to_count(n)),
                    2.0 / 3.0 * u.powi(3),
                    n * n,
                )
            }
            WallSolver::Rings => {
                let sizes = rings::RingSizes {
                    n_dense: to_count(n_moving as f64 + w.n_extra),
                    n_rings: to_count(w.n_rings),
                    n_theta: to_count(w.n_theta),
                };
                let k = 3.0 * (n_moving as f64 + w.n_extra);
                let (g6, m) = (6.0 * w.n_rings, w.n_theta);
                let l = 3.0 * w.n_rings * m;
                let modes = (m / 2.0).floor() + 1.0;
                let flops = modes * (2.0 / 3.0 * g6.powi(3) + 2.0 * g6 * g6 * k)
                    + 4.0 * modes * l * k
                    + 2.0 * k * l * k
                    + 2.0 / 3.0 * k.powi(3);
                let blocks =
                    (k / 3.0).powi(2) + 2.0 * (l / 3.0) * (k / 3.0) + m * w.n_rings.powi(2);
                (rings::peak_bytes(sizes), flops, blocks)
            }
        };
        let o_n = to_count(n).saturating_mul(24 * 8);
        Budget {
            n_moving,
            n_wall: to_count(n_wall),
            peak_bytes: bytes.saturating_add(o_n),
            seconds: flops / FLOP_RATE + (blocks + diagnostic_points(w) * n) * BLOCK_S / 2.0,
        }
    }

    /// Points of the whole system.
    pub fn n_points(&self) -> usize {
        self.n_moving.saturating_add(self.n_wall)
    }
}

#[cfg(test)]
mod tests {
    use super::super::wall::Wall;
    use super::*;

    #[test]
    fn counts_match_the_walls_they_predict() {
        for (r, x, h) in [(0.0175, (-0.2, 0.05), 0.003), (0.01, (0.0, 0.013), 0.0041)] {
            for caps in [CapLayout::Rings, CapLayout::Graded] {
                for closed in [true, false] {
                    let s = TubeSettings {
                        wall_spacing_m: h,
                        caps,
                        ..TubeSettings::default()
                    };
                    let c = WallCounts::of(r, x, closed, &s);
                    let w = Wall::mfs(r, x, h, 1.5, closed.then_some(caps));
                    assert_eq!(c.n_rings as usize, w.rings.len());
                    assert_eq!(c.n_theta as usize, w.n_theta);
                    assert_eq!(c.n_points() as usize, w.len(), "{caps:?} {closed}");
                }
            }
            let s = TubeSettings {
                wall: WallModel::Leaky,
                wall_spacing_m: h,
                ..TubeSettings::default()
            };
            let w = Wall::leaky(r, x, h, 1.0, true);
            assert_eq!(WallCounts::of(r, x, true, &s).n_points() as usize, w.len());
        }
    }

    #[test]
    fn absurd_tubes_are_large_numbers_not_allocations() {
        let s = TubeSettings::default();
        let w = WallCounts::of(5e5, (-1e6, 1e6), true, &s);
        let b = Budget::new(200, &w, WallSolver::Rings);
        assert!(b.peak_bytes > 1 << 50 && b.seconds > 1e6, "{b:?}");
        let b = Budget::new(200, &w, WallSolver::Dense);
        assert_eq!(b.peak_bytes, usize::MAX);
    }
}
