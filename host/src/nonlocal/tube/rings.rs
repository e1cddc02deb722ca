//! The tube solve by the wall's rotational symmetry: the same forces as the
//! dense solve of `super::mfs`, in a small fraction of its time and memory.
//!
//! # Why it works
//! The wall's ring points (`super::wall`) are `n_theta = M` equal stations
//! per ring. Write each ring point's velocity and force in the point's own
//! cylindrical frame `T = [e_x, e_r, e_theta]`. The free-space kernel obeys
//! `G(Rx, Ry) = R G(x, y) R^T` for a rotation `R` about the axis, so the
//! wall-wall block between station `k` of ring `g` and station `l` of ring
//! `h` depends on `k - l` only: the `3GM x 3GM` wall matrix is
//! block-circulant with `M` blocks `C_d` of size `3G` (`G` rings). A
//! discrete Fourier transform in the station index splits it into `M`
//! independent `3G` systems `C^_m = sum_d C_d exp(-2 pi i m d / M)`; real
//! `C_d` make `C^_{M-m}` the conjugate of `C^_m`, so only
//! `m = 0 .. M/2` are factored, each as the real `6G` system
//! `[Re -Im; Im Re]` (faer's real kernels; its complex ones are not
//! optimised in test builds). The normal completion of `super::mfs` is
//! constant in the local frame, so it keeps the symmetry.
//!
//! # The rest of the system
//! The moving objects and the wall's extra points (the caps' axis points,
//! or the graded caps of `CapLayout::Graded`) form the dense set `D`. With
//! the wall set `C` eliminated, the Schur complement
//! `S = A_DD - A_DC A_CC^-1 A_CD` is a dense `3 n_D` system: `A_CC^-1`
//! is applied to the `3 n_D` columns of `A_CD` mode by mode, and the wall
//! forces follow from `F_C = -A_CC^-1 A_CD F_D`. Nothing is approximated:
//! the forces equal the dense solve's to round-off (`tests/tail_tube.rs`).
//!
//! # Cost
//! `O(M G^3)` for the factorisations, `O(M G^2 n_D)` for the solves and
//! `O(G M n_D^2)` for `S`, against `O((GM + n_D)^3)` dense; memory
//! [`peak_bytes`]. The DFT is a direct sum (`M` is a few dozen and rarely
//! a power of two; its cost is below the solves', so an FFT crate would
//! not pay for itself).
//!
//! References: P. J. Davis, Circulant Matrices, Wiley (1979), ch. 5
//! (block-circulant matrices); the same splitting of an axisymmetric
//! boundary into Fourier modes is used by Pozrikidis, Boundary Integral and
//! Singularity Methods for Linearized Viscous Flow (1992), sec. 7.

use super::super::linalg;
use super::super::robot::Object;
use super::super::NonlocalError;
use super::mfs::{refuse_above, Solution, System};
use super::wall::Wall;
use faer::linalg::solvers::Solve;
use faer::{Accum, Mat, MatRef, Par};
use nalgebra::{DMatrix, Matrix3};
use rayon::prelude::*;
use std::f64::consts::PI;

const F64: usize = std::mem::size_of::<f64>();

/// Sizes of the split system.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RingSizes {
    /// Points in the dense set (moving objects and extra wall points).
    pub n_dense: usize,
    /// Rings, and stations per ring.
    pub n_rings: usize,
    pub n_theta: usize,
}

impl RingSizes {
    pub fn of(n_moving: usize, wall: &Wall) -> Self {
        RingSizes {
            n_dense: n_moving + wall.len() - wall.n_ring_points(),
            n_rings: wall.rings.len(),
            n_theta: wall.n_theta,
        }
    }

    fn modes(&self) -> usize {
        self.n_theta / 2 + 1
    }
}

/// Peak memory of [`solve`] (bytes), from the counts alone: the largest
/// set of buffers alive at once in its four phases (the mode solves; the
/// inverse transform; `S`; the LU of `S`), each buffer counted as the
/// `f64`s it holds, [`with_slack`]. Saturating, so absurd counts give a
/// huge number.
pub fn peak_bytes(s: RingSizes) -> usize {
    let k = s.n_dense.saturating_mul(3);
    let g3 = s.n_rings.saturating_mul(3);
    let l = g3.saturating_mul(s.n_theta);
    let m = |a: usize, b: usize| a.saturating_mul(b);
    let add = |v: &[usize]| v.iter().fold(0usize, |acc, &x| acc.saturating_add(x));
    let (kk, lk) = (m(k, k), m(l, k));
    // all modes' right-hand sides, the real pairs twice the size
    let hat = m(m(s.modes(), 2), m(g3, k));
    // per mode being solved at once: its matrix, the LU factors, and the
    // copy of the right-hand sides the row permutation works in
    let threads = rayon::current_num_threads().min(s.modes());
    let mode_lu = m(
        threads,
        m(2, m(2 * g3, 2 * g3)).saturating_add(m(2 * g3, k)),
    );
    let blocks = m(s.n_theta, m(g3, g3));
    let phase_modes = add(&[kk, lk, blocks, hat, mode_lu]);
    let phase_inverse = add(&[kk, hat, lk]);
    let phase_schur = add(&[kk, lk, lk]);
    let phase_lu = add(&[m(3, kk), lk]);
    let peak = phase_modes
        .max(phase_inverse)
        .max(phase_schur)
        .max(phase_lu);
    with_slack(m(peak, F64))
}

/// What the allocator and the thread pool add to the counted buffers: 10 %
/// and 6 MB. Measured as the growth of the peak resident memory: 27.0 MB
/// against 21.9 MB counted (tail #3, 4 mm wall, test build), 72 MB
/// against 65 MB (tail #1, 3 mm wall, release); freed buffers below
/// glibc's mmap threshold stay in the heap and fragment it.
pub fn with_slack(counted_bytes: usize) -> usize {
    let extra = (counted_bytes / 10).saturating_add(6_000_000);
    counted_bytes.saturating_add(extra)
}

/// Cosine and sine of `2 pi t / M`, `t = 0 .. M`.
fn twiddles(m: usize) -> (Vec<f64>, Vec<f64>) {
    (0..m)
        .map(|t| (2.0 * PI * t as f64 / m as f64).sin_cos())
        .map(|(s, c)| (c, s))
        .unzip()
}

/// Indices of the split system.
struct Split<'s, 'a> {
    sys: &'s System<'a>,
    dense: Vec<usize>,
    frames: Vec<Matrix3<f64>>,
    g: usize,
    m: usize,
}

impl Split<'_, '_> {
    /// Global index of station `k` of ring `g`.
    fn ring_point(&self, g: usize, k: usize) -> usize {
        self.sys.n_moving() + g * self.m + k
    }

    /// Row of local component `a` of station `k`, ring `g`, in `3GM`.
    fn row(&self, g: usize, k: usize) -> usize {
        3 * (k * self.g + g)
    }

    fn l(&self) -> usize {
        3 * self.g * self.m
    }
}

/// Fill column-major `rows x cols` in parallel, three columns per source.
fn fill(rows: usize, n_src: usize, f: impl Fn(usize, &mut [f64]) + Sync) -> Vec<f64> {
    let mut data = vec![0.0; rows * 3 * n_src];
    data.par_chunks_mut(3 * rows)
        .enumerate()
        .for_each(|(j, cols)| f(j, cols));
    data
}

fn put(cols: &mut [f64], rows: usize, r0: usize, b: &Matrix3<f64>) {
    for c in 0..3 {
        for r in 0..3 {
            cols[c * rows + r0 + r] = b[(r, c)];
        }
    }
}

/// `A_DD` (`K x K`), `T^T A_CD` (`L x K`) and `A_DC T` (`K x L`).
fn dense_dense(sp: &Split) -> Vec<f64> {
    let k = 3 * sp.dense.len();
    fill(k, sp.dense.len(), |j, cols| {
        for (i, &gi) in sp.dense.iter().enumerate() {
            put(cols, k, 3 * i, &sp.sys.block(gi, sp.dense[j]));
        }
    })
}

fn wall_dense(sp: &Split) -> Vec<f64> {
    let l = sp.l();
    fill(l, sp.dense.len(), |j, cols| {
        for g in 0..sp.g {
            for k in 0..sp.m {
                let b = sp.frames[g * sp.m + k].transpose()
                    * sp.sys.block(sp.ring_point(g, k), sp.dense[j]);
                put(cols, l, sp.row(g, k), &b);
            }
        }
    })
}

fn dense_wall(sp: &Split) -> Vec<f64> {
    let kd = 3 * sp.dense.len();
    let mut data = vec![0.0; kd * sp.l()];
    // column block of station k, ring g starts at column row(g, k)
    data.par_chunks_mut(3 * kd)
        .enumerate()
        .for_each(|(c, cols)| {
            let (k, g) = (c / sp.g, c % sp.g);
            let t = sp.frames[g * sp.m + k];
            for (i, &gi) in sp.dense.iter().enumerate() {
                put(
                    cols,
                    kd,
                    3 * i,
                    &(sp.sys.block(gi, sp.ring_point(g, k)) * t),
                );
            }
        });
    data
}

/// The circulant blocks `C_d`, each `3G x 3G` column-major.
fn circulant_blocks(sp: &Split) -> Vec<Vec<f64>> {
    let g3 = 3 * sp.g;
    (0..sp.m)
        .into_par_iter()
        .map(|d| {
            let mut c = vec![0.0; g3 * g3];
            for h in 0..sp.g {
                let th = sp.frames[h * sp.m];
                for g in 0..sp.g {
                    let tg = sp.frames[g * sp.m + d].transpose();
                    let b = tg * sp.sys.block(sp.ring_point(g, d), sp.ring_point(h, 0)) * th;
                    put(&mut c[3 * h * g3..], g3, 3 * g, &b);
                }
            }
            c
        })
        .collect()
}

/// `C^_m^-1` applied to the transform of `y` (`L x K`): the mode's
/// solution, `[Re; Im]` stacked (`6G x K`), or `Re` alone (`3G x K`) for
/// the real modes `m = 0` and `m = M / 2`.
fn mode_solve(sp: &Split, blocks: &[Vec<f64>], y: &[f64], mode: usize) -> Vec<f64> {
    let (g3, m, kd) = (3 * sp.g, sp.m, 3 * sp.dense.len());
    let (cos, sin) = twiddles(m);
    let real = mode == 0 || 2 * mode == m;
    let n = if real { g3 } else { 2 * g3 };
    // column-major `n x n`: [P -Q; Q P] with P + iQ the mode's block
    let mut e = vec![0.0; n * n];
    for (d, c) in blocks.iter().enumerate() {
        let t = (mode * d) % m;
        let (re, im) = (cos[t], -sin[t]);
        for (col, cc) in c.chunks_exact(g3).enumerate() {
            let top = &mut e[col * n..col * n + n];
            for (o, v) in top[..g3].iter_mut().zip(cc) {
                *o += re * v;
            }
            if !real {
                for (o, v) in top[g3..].iter_mut().zip(cc) {
                    *o += im * v;
                }
                let right = &mut e[(g3 + col) * n..(g3 + col + 1) * n];
                for (o, v) in right[..g3].iter_mut().zip(cc) {
                    *o -= im * v;
                }
                for (o, v) in right[g3..].iter_mut().zip(cc) {
                    *o += re * v;
                }
            }
        }
    }
    let e = MatRef::from_column_major_slice(&e, n, n);
    let mut rhs = vec![0.0; n * kd];
    for (yj, out) in y.chunks_exact(sp.l()).zip(rhs.chunks_exact_mut(n)) {
        for (k, slab) in yj.chunks_exact(g3).enumerate() {
            let t = (mode * k) % m;
            let (c, s) = (cos[t], sin[t]);
            for (o, v) in out[..g3].iter_mut().zip(slab) {
                *o += c * v;
            }
            if !real {
                for (o, v) in out[g3..].iter_mut().zip(slab) {
                    *o -= s * v;
                }
            }
        }
    }
    e.partial_piv_lu()
        .solve_in_place(faer::MatMut::from_column_major_slice_mut(&mut rhs, n, kd));
    rhs
}

/// `Z = A_CC^-1 A_CD` (local frames, `L x K`) from the modes' solutions.
fn inverse_transform(sp: &Split, hat: &[Vec<f64>]) -> Vec<f64> {
    let (g3, m, l) = (3 * sp.g, sp.m, sp.l());
    let (cos, sin) = twiddles(m);
    let mut z = vec![0.0; l * 3 * sp.dense.len()];
    z.par_chunks_mut(l).enumerate().for_each(|(j, zj)| {
        for (mode, h) in hat.iter().enumerate() {
            let real = mode == 0 || 2 * mode == m;
            let n = if real { g3 } else { 2 * g3 };
            let hj = &h[j * n..(j + 1) * n];
            let w = if real { 1.0 } else { 2.0 } / m as f64;
            for (k, slab) in zj.chunks_exact_mut(g3).enumerate() {
                let t = (mode * k) % m;
                let (c, s) = (w * cos[t], w * sin[t]);
                for (v, re) in slab.iter_mut().zip(&hj[..g3]) {
                    *v += c * re;
                }
                if !real {
                    for (v, im) in slab.iter_mut().zip(&hj[g3..]) {
                        *v -= s * im;
                    }
                }
            }
        }
    });
    z
}

/// The same forces as `super::mfs::solve_dense`, by the ring symmetry;
/// refuses (before allocating) above `max_bytes` of [`peak_bytes`].
pub fn solve<'a>(
    moving: &'a [Object],
    wall: &'a Wall,
    viscosity_pa_s: f64,
    max_bytes: usize,
) -> Result<Solution<'a>, NonlocalError> {
    let t0 = std::time::Instant::now();
    let sys = System::new(moving, wall, viscosity_pa_s);
    let sizes = RingSizes::of(sys.n_moving(), wall);
    let need = peak_bytes(sizes);
    refuse_above(need, max_bytes, sys.len(), "ring-symmetric solve")?;
    linalg::check_memory(sizes.n_dense)?;
    let n_ring = wall.n_ring_points();
    let dense: Vec<usize> = (0..sys.n_moving())
        .chain(sys.n_moving() + n_ring..sys.len())
        .collect();
    let frames = (0..wall.rings.len())
        .flat_map(|g| (0..wall.n_theta).map(move |k| (g, k)))
        .map(|(g, k)| wall.frame(g, k))
        .collect();
    let sp = Split {
        sys: &sys,
        dense,
        frames,
        g: wall.rings.len(),
        m: wall.n_theta,
    };
    let (kd, l) = (3 * sp.dense.len(), sp.l());
    let mut s = dense_dense(&sp);
    let z = {
        let y = wall_dense(&sp);
        let blocks = circulant_blocks(&sp);
        let hat: Vec<Vec<f64>> = (0..sizes.modes())
            .into_par_iter()
            .map(|mode| mode_solve(&sp, &blocks, &y, mode))
            .collect();
        drop((y, blocks));
        inverse_transform(&sp, &hat)
    };
    let zr = MatRef::from_column_major_slice(&z, l, kd);
    {
        let a_dc = dense_wall(&sp);
        let a = MatRef::from_column_major_slice(&a_dc, kd, l);
        let sm = faer::MatMut::from_column_major_slice_mut(&mut s, kd, kd);
        faer::linalg::matmul::matmul(sm, Accum::Add, a, zr, -1.0, Par::rayon(0));
    }
    let rhs = sys.rhs(&sp.dense);
    let f_d = linalg::solve(DMatrix::from_vec(kd, kd, s), &rhs)?;
    let ncol = f_d.ncols();
    let fd = MatRef::from_column_major_slice(f_d.as_slice(), kd, ncol);
    let mut f_c = Mat::<f64>::zeros(l, ncol);
    faer::linalg::matmul::matmul(f_c.as_mut(), Accum::Replace, zr, fd, -1.0, Par::rayon(0));
    let mut forces = DMatrix::zeros(3 * sys.len(), ncol);
    for (i, &gi) in sp.dense.iter().enumerate() {
        for c in 0..ncol {
            for a in 0..3 {
                forces[(3 * gi + a, c)] = f_d[(3 * i + a, c)];
            }
        }
    }
    for g in 0..sp.g {
        for k in 0..sp.m {
            let (t, r, gi) = (sp.frames[g * sp.m + k], sp.row(g, k), sp.ring_point(g, k));
            for c in 0..ncol {
                let local = nalgebra::Vector3::new(f_c[(r, c)], f_c[(r + 1, c)], f_c[(r + 2, c)]);
                let f = t * local;
                for a in 0..3 {
                    forces[(3 * gi + a, c)] = f[a];
                }
            }
        }
    }
    Ok(Solution {
        system: sys,
        forces,
        peak_bytes: need,
        seconds: t0.elapsed().as_secs_f64(),
    })
}
