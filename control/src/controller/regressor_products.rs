//! `Y θ̂` and `Yᵀ r` in one pass over the regressor.
//!
//! Why: the regressor is the largest thing a tick handles (N×M: 7×43 base parameters of arm7,
//! 2.4 kB; 7×70 standard ones). The law needs `Y θ̂` (the torque) and the adaptation `Yᵀ r`.
//! nalgebra computes each in its own pass, and `Yᵀ r` along the rows of a column-major matrix
//! (strided loads); here both come from one pass over the columns, each column contiguous: it
//! is added into `Y θ̂` scaled by `θ̂ₖ`, and dotted with `r` for the k-th entry of `Yᵀ r`.
//! Same products, summed in another order (rounding only).

use nalgebra::{SMatrix, SVector};

/// `(Y θ̂, Yᵀ r)`.
#[inline]
pub fn regressor_products<const N: usize, const M: usize>(
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
        for i in 0..N {
            y_theta[i] += column[i] * theta[k];
        }
        // The dot product in four interleaved partial sums (a fixed order, so the compiler
        // may keep them in one vector register) instead of one sequential chain.
        let mut lanes = [0.0; 4];
        for i in 0..N {
            lanes[i % 4] += column[i] * r[i];
        }
        y_tr_r[k] = (lanes[0] + lanes[2]) + (lanes[1] + lanes[3]);
    }
    (SVector::from(y_theta), SVector::from(y_tr_r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use dyngen_runtime::SplitMix64;

    #[test]
    fn equal_the_two_matrix_products() {
        let mut rng = SplitMix64::new(5);
        for _ in 0..50 {
            let y = SMatrix::<f64, 7, 43>::from_fn(|_, _| rng.uniform((-10.0, 10.0)));
            let theta = SVector::<f64, 43>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let r = SVector::<f64, 7>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let (y_theta, y_tr_r) = regressor_products(&y, &theta, &r);
            assert!((y_theta - y * theta).amax() < 1e-12 * (y * theta).amax().max(1.0));
            assert!((y_tr_r - y.tr_mul(&r)).amax() < 1e-12 * y.tr_mul(&r).amax().max(1.0));
        }
    }
}
