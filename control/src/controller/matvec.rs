//! `A x` and `Aᵀ y` for the small matrices of a tick (`J`, `J̇`: T×N; `G`: N×N), with fused
//! multiply-adds.
//!
//! Why: nalgebra's products multiply and add separately (Rust never contracts `a * b + c`),
//! and the reference velocity and acceleration are mostly such products. Here each term is
//! one [`mul_add`] (one instruction and one rounding where the build has FMA, `a * b + c` as
//! written elsewhere), over the matrix's column-major array in index loops that unroll.

use dyngen_runtime::mul_add;
use nalgebra::{SMatrix, SVector};

/// `A x`.
#[inline]
pub(crate) fn mul<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    x: &SVector<f64, C>,
) -> SVector<f64, R> {
    let (a, x) = (&a.data.0, &x.data.0[0]);
    let mut out = [0.0; R];
    for c in 0..C {
        for i in 0..R {
            out[i] = mul_add(a[c][i], x[c], out[i]);
        }
    }
    SVector::from(out)
}

/// `Aᵀ y`.
#[inline]
pub(crate) fn tr_mul<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    y: &SVector<f64, R>,
) -> SVector<f64, C> {
    let (a, y) = (&a.data.0, &y.data.0[0]);
    let mut out = [0.0; C];
    for c in 0..C {
        let mut s = 0.0;
        for i in 0..R {
            s = mul_add(a[c][i], y[i], s);
        }
        out[c] = s;
    }
    SVector::from(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use dyngen_runtime::SplitMix64;

    #[test]
    fn equal_nalgebra_products() {
        let mut rng = SplitMix64::new(11);
        for _ in 0..100 {
            let a = SMatrix::<f64, 3, 7>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let x = SVector::<f64, 7>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let y = SVector::<f64, 3>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            assert!((mul(&a, &x) - a * x).amax() < 1e-14);
            assert!((tr_mul(&a, &y) - a.tr_mul(&y)).amax() < 1e-14);
            let b = SMatrix::<f64, 6, 7>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let z = SVector::<f64, 6>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            assert!((mul(&b, &x) - b * x).amax() < 1e-14);
            assert!((tr_mul(&b, &z) - b.tr_mul(&z)).amax() < 1e-14);
        }
    }
}
