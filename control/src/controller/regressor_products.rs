//! `Y θ̂` and `Yᵀ r` in one pass over the regressor.
//!
//! Why: the regressor is the largest thing a tick handles (N×M: 7×43 base parameters of arm7,
//! 2.4 kB; 7×70 standard ones). The law needs `Y θ̂` (the torque) and the adaptation `Yᵀ r`.
//! nalgebra computes each in its own pass, and `Yᵀ r` along the rows of a column-major matrix
//! (strided loads); here both come from one pass over the columns, each column contiguous: it
//! is added into `Y θ̂` scaled by `θ̂ₖ`, and dotted with `r` for the k-th entry of `Yᵀ r`.
//! Same products, summed in another order (rounding only).

use dyngen_runtime::f64x4;
use nalgebra::{SMatrix, SVector};

/// `(Y θ̂, Yᵀ r)`.
#[inline]
pub fn regressor_products<const N: usize, const M: usize>(
    y: &SMatrix<f64, N, M>,
    theta: &SVector<f64, M>,
    r: &SVector<f64, N>,
) -> (SVector<f64, N>, SVector<f64, M>) {
    if (4..=8).contains(&N) {
        in_two_quads(y, theta, r)
    } else {
        column_by_column(y, theta, r)
    }
}

/// The rows `0..4` and `N−4..N` of a column of `4 ≤ N ≤ 8` entries as two 4-lane vectors (the
/// `8 − N` rows in the middle are in both).
#[inline(always)]
fn quads<const N: usize>(c: &[f64; N]) -> (f64x4, f64x4) {
    let h = N.saturating_sub(4);
    (
        f64x4::new([c[0], c[1], c[2], c[3]]),
        f64x4::new([c[h], c[h + 1], c[h + 2], c[h + 3]]),
    )
}

/// For `4 ≤ N ≤ 8` (arm7: 7): each column is two 4-lane vectors, so `Y θ̂` takes two
/// multiply-adds a column and each entry of `Yᵀ r` a multiply, a multiply-add and one sum of
/// four lanes. The rows in both vectors count once: `r` is zero there in the upper vector, and
/// `Y θ̂` takes them from the lower one.
#[inline]
fn in_two_quads<const N: usize, const M: usize>(
    y: &SMatrix<f64, N, M>,
    theta: &SVector<f64, M>,
    r: &SVector<f64, N>,
) -> (SVector<f64, N>, SVector<f64, M>) {
    let (y, theta) = (&y.data.0, &theta.data.0[0]);
    let (r_lo, r_hi) = quads(&r.data.0[0]);
    let r_hi = r_hi * f64x4::new(core::array::from_fn(|l| f64::from(u8::from(N + l >= 8))));
    let (mut lo, mut hi) = (f64x4::splat(0.0), f64x4::splat(0.0));
    let mut y_tr_r = [0.0; M];
    for k in 0..M {
        let (c_lo, c_hi) = quads(&y[k]);
        let t = f64x4::splat(theta[k]);
        lo = c_lo.mul_add(t, lo);
        hi = c_hi.mul_add(t, hi);
        y_tr_r[k] = c_hi.mul_add(r_hi, c_lo * r_lo).reduce_add();
    }
    let (lo, hi) = (lo.to_array(), hi.to_array());
    let y_theta = core::array::from_fn(|i| if i < 4 { lo[i] } else { hi[i + 4 - N] });
    (SVector::from(y_theta), SVector::from(y_tr_r))
}

/// Any `N`: each column added into `Y θ̂` scaled by `θ̂ₖ` and dotted with `r`.
#[inline]
fn column_by_column<const N: usize, const M: usize>(
    y: &SMatrix<f64, N, M>,
    theta: &SVector<f64, M>,
    r: &SVector<f64, N>,
) -> (SVector<f64, N>, SVector<f64, M>) {
    // Plain arrays and index loops (nalgebra's iterators do not unroll).
    let (y, theta, r) = (&y.data.0, &theta.data.0[0], &r.data.0[0]);
    let mut y_theta = [0.0; N];
    let mut y_tr_r = [0.0; M];
    for k in 0..M {
        let column = &y[k];
        let mut dot = 0.0;
        for i in 0..N {
            y_theta[i] += column[i] * theta[k];
            dot += column[i] * r[i];
        }
        y_tr_r[k] = dot;
    }
    (SVector::from(y_theta), SVector::from(y_tr_r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use dyngen_runtime::SplitMix64;

    fn agree<const N: usize, const M: usize>(rng: &mut SplitMix64) {
        for _ in 0..50 {
            let y = SMatrix::<f64, N, M>::from_fn(|_, _| rng.uniform((-10.0, 10.0)));
            let theta = SVector::<f64, M>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let r = SVector::<f64, N>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let (y_theta, y_tr_r) = (y * theta, y.tr_mul(&r));
            for (a, b) in [
                regressor_products(&y, &theta, &r),
                column_by_column(&y, &theta, &r),
            ] {
                assert!((a - y_theta).amax() < 1e-12 * y_theta.amax().max(1.0));
                assert!((b - y_tr_r).amax() < 1e-12 * y_tr_r.amax().max(1.0));
            }
        }
    }

    #[test]
    fn equal_the_two_matrix_products() {
        let mut rng = SplitMix64::new(5);
        agree::<7, 43>(&mut rng);
        agree::<7, 70>(&mut rng);
        agree::<6, 36>(&mut rng);
        agree::<4, 9>(&mut rng);
        agree::<8, 11>(&mut rng);
        agree::<3, 5>(&mut rng);
        agree::<12, 20>(&mut rng);
    }
}
