//! The Cholesky factor `A = L Lᵀ` of a small symmetric positive definite matrix (`T ≤ 6`: the
//! task's `J Jᵀ + μ² I`), for solves.
//!
//! Why not nalgebra's `Cholesky`: its loops are written for any dimension and stay loops (and
//! its `inverse` solves `T` systems) where, at `T = 3..6` known at compile time, plain index
//! loops unroll into straight-line code. The tick applies `A⁻¹` to three vectors, so it solves
//! with the factor instead of forming `A⁻¹` (`T²` operations per solve either way, without the
//! `T³` of the inverse). The reciprocals of the pivots are kept, so a solve multiplies and
//! never divides.

use nalgebra::{SMatrix, SVector};

/// `L` (lower triangle used) and `1/Lᵢᵢ`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SpdFactor<const T: usize> {
    l: SMatrix<f64, T, T>,
    inv_pivot: SVector<f64, T>,
}

impl<const T: usize> SpdFactor<T> {
    /// Factors the lower triangle of `a` (the upper one is not read). `None` unless every pivot
    /// is finite and > 0, i.e. unless `a` is (numerically) positive definite.
    #[inline]
    pub fn new(a: &SMatrix<f64, T, T>) -> Option<Self> {
        let mut l = SMatrix::<f64, T, T>::zeros();
        let mut inv_pivot = SVector::<f64, T>::zeros();
        for c in 0..T {
            let mut d = a[(c, c)];
            for k in 0..c {
                d -= l[(c, k)] * l[(c, k)];
            }
            // `!(d > 0)` also refuses NaN.
            if !(d > 0.0 && d.is_finite()) {
                return None;
            }
            let pivot = d.sqrt();
            l[(c, c)] = pivot;
            inv_pivot[c] = 1.0 / pivot;
            for r in c + 1..T {
                let mut s = a[(r, c)];
                for k in 0..c {
                    s -= l[(r, k)] * l[(c, k)];
                }
                l[(r, c)] = s * inv_pivot[c];
            }
        }
        Some(SpdFactor { l, inv_pivot })
    }

    /// `det A = ∏ Lᵢᵢ²`.
    #[inline]
    pub fn determinant(&self) -> f64 {
        (0..T).fold(1.0, |p, i| p * self.l[(i, i)] * self.l[(i, i)])
    }

    /// `A⁻¹ b`: forward substitution with `L`, then back substitution with `Lᵀ`.
    #[inline]
    pub fn solve(&self, b: &SVector<f64, T>) -> SVector<f64, T> {
        let l = &self.l;
        let mut x = *b;
        for i in 0..T {
            let mut s = x[i];
            for k in 0..i {
                s -= l[(i, k)] * x[k];
            }
            x[i] = s * self.inv_pivot[i];
        }
        for i in (0..T).rev() {
            let mut s = x[i];
            for k in i + 1..T {
                s -= l[(k, i)] * x[k];
            }
            x[i] = s * self.inv_pivot[i];
        }
        x
    }

    /// `A⁻¹` (for inspection; the tick only solves).
    pub fn inverse(&self) -> SMatrix<f64, T, T> {
        let mut inv = SMatrix::<f64, T, T>::zeros();
        for c in 0..T {
            let e = SVector::<f64, T>::from_fn(|i, _| if i == c { 1.0 } else { 0.0 });
            inv.set_column(c, &self.solve(&e));
        }
        inv
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dyngen_runtime::SplitMix64;
    use nalgebra::Cholesky;

    fn agrees_with_nalgebra<const T: usize>(rng: &mut SplitMix64) {
        for _ in 0..200 {
            // Well and badly conditioned: B Bᵀ plus a diagonal from 1e-8 to 1.
            let b = SMatrix::<f64, T, 7>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let shift = 10f64.powf(rng.uniform((-8.0, 0.0)));
            let a = b * b.transpose() + SMatrix::<f64, T, T>::identity() * shift;
            let v = SVector::<f64, T>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let ours = SpdFactor::new(&a).expect("positive definite");
            let theirs = Cholesky::new(a).expect("positive definite");
            let (x, x_ref) = (ours.solve(&v), theirs.solve(&v));
            // Both solve the same system to rounding: compare the residuals, and the solutions
            // relative to the conditioning.
            assert!((a * x - v).amax() < 1e-9 * (a.amax() * x.amax()).max(1.0));
            assert!((x - x_ref).amax() <= 1e-8 * x_ref.amax() / shift.min(1.0).sqrt());
            let det = theirs.determinant();
            assert!((ours.determinant() - det).abs() <= 1e-12 * det.abs().max(1e-300));
            let inv = theirs.inverse();
            assert!((ours.inverse() - inv).amax() <= 1e-8 * inv.amax());
        }
    }

    #[test]
    fn solves_and_determinants_agree_with_nalgebra_cholesky() {
        let mut rng = SplitMix64::new(21);
        agrees_with_nalgebra::<3>(&mut rng);
        agrees_with_nalgebra::<5>(&mut rng);
        agrees_with_nalgebra::<6>(&mut rng);
    }

    #[test]
    fn refuses_what_is_not_positive_definite() {
        let singular = SMatrix::<f64, 3, 3>::new(1.0, 1.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 1.0);
        assert!(SpdFactor::new(&singular).is_none());
        assert!(SpdFactor::new(&(-SMatrix::<f64, 3, 3>::identity())).is_none());
        let mut nan = SMatrix::<f64, 3, 3>::identity();
        nan[(1, 1)] = f64::NAN;
        assert!(SpdFactor::new(&nan).is_none());
        assert!(SpdFactor::new(&(SMatrix::<f64, 3, 3>::identity() * f64::INFINITY)).is_none());
    }
}
