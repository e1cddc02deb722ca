//! Complete elliptic integrals of the first and second kind, `K(m)` and
//! `E(m)` (parameter `m = k^2`), by the arithmetic-geometric mean.
//!
//! Hand-written rather than taken from a crate because the ring kernels need
//! them near `m -> 1`, where `K` has its logarithmic singularity and the
//! complementary modulus `k' = sqrt(1 - m)` must be supplied *directly*
//! (the kernels compute it as `d / rho` without cancellation); the crates we
//! know take `m` alone, losing every digit of `1 - m` near the singularity.
//! The AGM converges quadratically: five to six iterations give full double
//! precision for any `k' > 1e-300`.
//!
//! `K = pi / (2 AGM(1, k'))`, `E = K (1 - sum_n 2^(n-1) c_n^2)` with
//! `c_0 = k`, `c_{n+1} = (a_n - b_n) / 2`.
//!
//! References: M. Abramowitz & I. A. Stegun, *Handbook of Mathematical
//! Functions* (1964), §17.6; DLMF §19.8(i).

use std::f64::consts::PI;

/// `(K(m), E(m))` for `m = k^2` in `[0, 1)` and `kc = sqrt(1 - m)` (given
/// separately so that it keeps its relative precision near `m = 1`).
pub fn complete_ke(m: f64, kc: f64) -> (f64, f64) {
    let (mut a, mut b) = (1.0_f64, kc);
    let mut sum = 0.5 * m;
    let mut weight = 0.5;
    for _ in 0..60 {
        let c = 0.5 * (a - b);
        let next_b = (a * b).sqrt();
        a = 0.5 * (a + b);
        b = next_b;
        weight *= 2.0;
        sum += weight * c * c;
        if c.abs() <= 1e-17 * a {
            break;
        }
    }
    let k = PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// `(K(m), E(m))` from the parameter alone (for `m` away from 1).
pub fn complete_ke_m(m: f64) -> (f64, f64) {
    complete_ke(m, (1.0 - m).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tabulated_values() {
        // Abramowitz & Stegun Table 17.1 / DLMF: K(1/2), E(1/2).
        let (k, e) = complete_ke_m(0.5);
        assert!((k - 1.854_074_677_301_372).abs() < 1e-14, "{k}");
        assert!((e - 1.350_643_881_047_675).abs() < 1e-14, "{e}");
        let (k0, e0) = complete_ke_m(0.0);
        assert!((k0 - PI / 2.0).abs() < 1e-15 && (e0 - PI / 2.0).abs() < 1e-15);
    }

    #[test]
    fn legendre_relation_holds_up_to_the_singularity() {
        // E K' + E' K - K K' = pi / 2 (DLMF 19.7.1), a check independent of
        // any table, across the whole range including kc = 1e-12.
        for &kc in &[1e-12_f64, 1e-6, 1e-3, 0.1, 0.5, 0.9, 0.999] {
            let m = 1.0 - kc * kc;
            let k = m.sqrt();
            let (kk, ee) = complete_ke(m, kc);
            let (kp, ep) = complete_ke(kc * kc, k);
            let legendre = ee * kp + ep * kk - kk * kp;
            assert!((legendre - PI / 2.0).abs() < 1e-12, "kc {kc}: {legendre}");
        }
    }

    #[test]
    fn logarithmic_limit() {
        // K ~ ln(4 / k') + O(k'^2 ln k') as k' -> 0 (DLMF 19.12.1).
        let kc = 1e-8;
        let (k, e) = complete_ke(1.0 - kc * kc, kc);
        assert!((k - (4.0 / kc).ln()).abs() < 1e-12, "{k}");
        assert!((e - 1.0).abs() < 1e-12, "{e}");
    }
}
