//! Dense assembly (rayon) and LU solve of the `3N x 3N` collocation systems.
//!
//! Every non-local model here ends in `A F = U` with one 3x3 block per
//! (target, source) pair and six right-hand sides (the unit rigid motions).

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

/// Memory of the dense matrix (bytes) for `n_blocks` sources.
pub fn dense_bytes(n_blocks: usize) -> usize {
    let n = 3 * n_blocks;
    n * n * std::mem::size_of::<f64>()
}
