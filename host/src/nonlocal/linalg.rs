//! Dense assembly (rayon) and LU solve of the `3N x 3N` collocation systems.
//!
//! Every non-local model here ends in `A F = U` with one 3x3 block per
//! (target, source) pair and six right-hand sides (the unit rigid motions).
//!
//! Every solver calls [`check_memory`] before it assembles: a dense system
//! of `n` blocks needs `(3n)^2` doubles for the matrix, as many again for
//! the LU factors (faer factors a copy) and `O(n)` besides, so the peak is
//! about `2 (3n)^2 8` bytes. Above [`MAX_DENSE_BYTES`] the solve is refused
//! with an error that names the size, instead of aborting on allocation or
//! running for hours (LU costs `(2/3)(3n)^3` operations).

use super::NonlocalError;
use nalgebra::{DMatrix, Matrix3};
use rayon::prelude::*;

/// Column-major dense matrix assembled block by block in parallel:
/// block `(i, j)` maps the force on source `j` to the velocity of target `i`.
pub fn assemble<F>(n_blocks: usize, block: F) -> DMatrix<f64>
where
    F: Fn(usize, usize) -> Matrix3<f64> + Sync,
{
    let n = 3 * n_blocks;
    let mut data = vec![0.0; n * n];
    // Source `j` owns three contiguous columns, so threads never share memory.
    data.par_chunks_mut(3 * n)
        .enumerate()
        .for_each(|(j, cols)| {
            for i in 0..n_blocks {
                let b = block(i, j);
                for c in 0..3 {
                    for r in 0..3 {
                        cols[c * n + 3 * i + r] = b[(r, c)];
                    }
                }
            }
        });
    DMatrix::from_vec(n, n, data)
}

/// Solve `A X = B` by LU with partial pivoting (faer, multithreaded through
/// rayon), rejecting singular or non-finite systems instead of panicking.
pub fn solve(a: DMatrix<f64>, b: &DMatrix<f64>) -> Result<DMatrix<f64>, NonlocalError> {
    let n = a.nrows();
    check_memory(n / 3)?;
    if a.iter().any(|v| !v.is_finite()) {
        return Err(NonlocalError::Singular("non-finite matrix entry".into()));
    }
    let fa = faer::MatRef::from_column_major_slice(a.as_slice(), n, n);
    let fb = faer::MatRef::from_column_major_slice(b.as_slice(), n, b.ncols());
    let lu = fa.partial_piv_lu();
    use faer::linalg::solvers::Solve;
    let x = lu.solve(fb);
    let out = DMatrix::from_fn(n, b.ncols(), |i, j| x[(i, j)]);
    if out.iter().any(|v| !v.is_finite()) {
        return Err(NonlocalError::Singular(format!(
            "LU of the {n}x{n} system produced non-finite forces"
        )));
    }
    Ok(out)
}

/// Memory of the dense matrix (bytes) for `n_blocks` sources (saturating).
pub fn dense_bytes(n_blocks: usize) -> usize {
    let n = n_blocks.saturating_mul(3);
    n.saturating_mul(n)
        .saturating_mul(std::mem::size_of::<f64>())
}

/// The largest estimated peak memory of one dense solve: 8 GiB, i.e. about
/// 7 700 blocks (a 23 000-unknown system, ~10^13 operations). The confined
/// whole-robot systems (tail segments + body and tube-wall points at the
/// default spacings) of the paper's longest tail have about 4 500 blocks
/// (~3 GB); the tail alone needs fewer than 200.
pub const MAX_DENSE_BYTES: usize = 8 << 30;

/// Refuse a dense solve of `n_blocks` sources whose matrix and LU factors
/// would exceed [`MAX_DENSE_BYTES`].
pub fn check_memory(n_blocks: usize) -> Result<(), NonlocalError> {
    let peak = dense_bytes(n_blocks).saturating_mul(2);
    if peak > MAX_DENSE_BYTES {
        return Err(NonlocalError::Settings(format!(
            "a dense system of {n_blocks} segments needs about {:.1} GiB (matrix and LU factors), above the limit of {} GiB: use fewer segments per turn or a shorter tail",
            peak as f64 / f64::from(1u32 << 30),
            MAX_DENSE_BYTES >> 30
        )));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn memory_estimate_refuses_huge_systems_and_accepts_converged_tails() {
        assert!(check_memory(200).is_ok());
        assert!(check_memory(3_000).is_ok() && check_memory(7_000).is_ok());
        let e = check_memory(100_000).unwrap_err().to_string();
        assert!(e.contains("100000 segments") && e.contains("GiB"), "{e}");
        // Saturation: no overflow for absurd counts.
        assert!(check_memory(usize::MAX).is_err());
    }
}
