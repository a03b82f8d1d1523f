//! `J⁺`, `J⁻` and their time derivatives, with the singularity guard.
//!
//! # Singularity guard
//! `J⁺ = Jᵀ (J Jᵀ + μ² I)⁻¹` (damped least squares) where the damping is **zero** while the
//! smallest eigenvalue `σ²_min` of `J Jᵀ` (the squared smallest singular value of the T×N
//! task Jacobian: m/rad in position rows, rad/rad in orientation rows, unscaled) stays above `σ₀²`, so the exact law of the note holds away from
//! singularities; below it `μ² = μ²_max (1 − σ²_min/σ₀²)` grows continuously to `μ²_max`. The
//! time derivative of `J⁺` includes the derivative of `μ²` (`dσ²_min/dt = uᵀ (J̇Jᵀ + JJ̇ᵀ) u` for
//! the unit eigenvector `u`), so `q̈_r` stays the exact derivative of `q̇_r` and the closed loop
//! `D ṙ + C r + G r = Y θ̃` (hence `V̇ = −rᵀ G r`) holds inside the damped region too; what is
//! lost there is exact task tracking (`J J⁺ ≠ I`), not stability of `r`. The torque is also
//! saturated and checked for NaN in the law (see `law.rs`).

use super::error::TickError;
use super::matvec;
use super::spd::SpdFactor;
use nalgebra::{SMatrix, SVector};

/// Damped-least-squares settings (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SingularityGuard {
    /// `σ₀`: the smallest singular value of the task Jacobian (m/rad for position rows; the
    /// orientation rows are rad/rad and not scaled) below which damping starts.
    pub sigma_threshold: f64,
    /// `μ²_max` (m²): the damping reached at an exact singularity.
    pub max_damping: f64,
}

impl Default for SingularityGuard {
    fn default() -> Self {
        SingularityGuard {
            sigma_threshold: 0.03,
            max_damping: 4.0e-4,
        }
    }
}

/// `J⁺`, `J⁻ = I − J⁺J` and their time derivatives at one state, applied to vectors (no N×N
/// matrix is formed: `J⁻ v = v − J⁺(J v)`, `d(J⁻)/dt v = −(d(J⁺)/dt (J v) + J⁺ (J̇ v))`).
#[derive(Clone, Copy, Debug)]
pub struct Projections<const N: usize, const T: usize = 3> {
    j: SMatrix<f64, T, N>,
    jd: SMatrix<f64, T, N>,
    /// The Cholesky factor of `A = J Jᵀ + μ² I`: `A⁻¹ v` is a solve, `A⁻¹` is never formed.
    a: SpdFactor<T>,
    /// `dμ²/dt`
    damping_dot: f64,
    /// The damping `μ²` used (0 away from singularities).
    pub damping: f64,
    /// Smallest singular value of `J` (a lower bound of it when far from the threshold).
    pub sigma_min: f64,
}

/// Smallest singular value of a T×N Jacobian and the unit eigenvector of `J Jᵀ` that goes with it.
pub(crate) fn smallest_singular<const N: usize, const T: usize>(
    j: &SMatrix<f64, T, N>,
) -> (f64, SVector<f64, T>) {
    let (values, vectors) = symmetric_eigen(&(j * j.transpose()));
    let (mut k, mut min) = (0, f64::INFINITY);
    for (i, &e) in values.iter().enumerate() {
        if e < min {
            min = e;
            k = i;
        }
    }
    (min.max(0.0).sqrt(), vectors.column(k).into_owned())
}

/// Eigenvalues and eigenvectors (columns) of a small symmetric matrix by cyclic Jacobi
/// rotations: for any `T` on stable Rust (nalgebra's `symmetric_eigen` needs a type-level
/// dimension), allocation-free, accurate to rounding. Called only near singularities.
pub(crate) fn symmetric_eigen<const T: usize>(
    a: &SMatrix<f64, T, T>,
) -> (SVector<f64, T>, SMatrix<f64, T, T>) {
    let mut a = (a + a.transpose()) * 0.5;
    let mut v = SMatrix::<f64, T, T>::identity();
    for _sweep in 0..50 {
        let off: f64 = (0..T)
            .flat_map(|p| (p + 1..T).map(move |q| (p, q)))
            .map(|(p, q)| a[(p, q)] * a[(p, q)])
            .sum();
        let scale: f64 = a.diagonal().iter().map(|x| x * x).sum();
        if off.is_nan() || off <= 1e-32 * scale {
            break;
        }
        for p in 0..T {
            for q in p + 1..T {
                let apq = a[(p, q)];
                if apq == 0.0 {
                    continue;
                }
                // The rotation that zeroes a[p][q] (Golub & Van Loan, symmetric Schur).
                let theta = (a[(q, q)] - a[(p, p)]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..T {
                    let (akp, akq) = (a[(k, p)], a[(k, q)]);
                    a[(k, p)] = c * akp - s * akq;
                    a[(k, q)] = s * akp + c * akq;
                }
                for k in 0..T {
                    let (apk, aqk) = (a[(p, k)], a[(q, k)]);
                    a[(p, k)] = c * apk - s * aqk;
                    a[(q, k)] = s * apk + c * aqk;
                }
                for k in 0..T {
                    let (vkp, vkq) = (v[(k, p)], v[(k, q)]);
                    v[(k, p)] = c * vkp - s * vkq;
                    v[(k, q)] = s * vkp + c * vkq;
                }
            }
        }
    }
    (a.diagonal(), v)
}

impl<const N: usize, const T: usize> Projections<N, T> {
    pub fn new(
        j: &SMatrix<f64, T, N>,
        jd: &SMatrix<f64, T, N>,
        guard: &SingularityGuard,
    ) -> Result<Self, TickError> {
        let a = gram(j);
        let s0 = guard.sigma_threshold * guard.sigma_threshold;
        // Cheap lower bound first: for eigenvalues l1 ≤ … ≤ l_T of the SPD `A`, the product of
        // the other T − 1 is at most (tr/(T − 1))^(T−1), so l1 ≥ det / (tr/(T − 1))^(T−1)
        // (4 det / tr² for T = 3). det from the Cholesky factor. The eigen-decomposition is
        // needed only when the bound does not already clear the threshold (near a singularity).
        let tr = a.trace();
        let factor = SpdFactor::new(&a);
        let bound = factor.as_ref().map_or(0.0, |f| {
            f.determinant() / (tr / (T - 1) as f64).powi(T as i32 - 1)
        });
        let (sigma_min, damping, damping_dot) = if bound >= s0 {
            (bound.sqrt(), 0.0, 0.0)
        } else {
            let (sigma_min, u) = smallest_singular(j);
            let s2 = sigma_min * sigma_min;
            if s2 < s0 {
                // dσ²/dt = uᵀ Ȧ u = 2 (Jᵀu)ᵀ (J̇ᵀu): Ȧ = J̇Jᵀ + JJ̇ᵀ is needed only here.
                let d_s2 = 2.0 * j.tr_mul(&u).dot(&jd.tr_mul(&u));
                (
                    sigma_min,
                    guard.max_damping * (1.0 - s2 / s0),
                    -guard.max_damping / s0 * d_s2,
                )
            } else {
                (sigma_min, 0.0, 0.0)
            }
        };
        let factor = match factor {
            Some(f) if damping == 0.0 => Some(f),
            _ => SpdFactor::new(&(a + SMatrix::<f64, T, T>::identity() * damping)),
        };
        // Every pivot of the factor is finite and > 0, so every solve is finite (short of an
        // overflow, which the law's check of the torque catches).
        let a = factor.ok_or(TickError::Singular(sigma_min * sigma_min))?;
        Ok(Projections {
            j: *j,
            jd: *jd,
            a,
            damping_dot,
            damping,
            sigma_min,
        })
    }
}

/// `J Jᵀ`, symmetric by construction: each of the `T(T+1)/2` distinct entries is one dot
/// product of two rows (a general product would compute the `T(T−1)/2` others twice).
#[inline]
fn gram<const N: usize, const T: usize>(j: &SMatrix<f64, T, N>) -> SMatrix<f64, T, T> {
    let mut a = SMatrix::<f64, T, T>::zeros();
    for r in 0..T {
        for c in 0..=r {
            let mut s = 0.0;
            for k in 0..N {
                s += j[(r, k)] * j[(c, k)];
            }
            a[(r, c)] = s;
            a[(c, r)] = s;
        }
    }
    a
}

impl<const N: usize, const T: usize> Projections<N, T> {
    /// `J⁺ v = Jᵀ (A⁻¹ v)`.
    #[inline]
    pub fn pinv_mul(&self, v: &SVector<f64, T>) -> SVector<f64, N> {
        matvec::tr_mul(&self.j, &self.a.solve(v))
    }

    /// `d(J⁺)/dt v = J̇ᵀ y − J⁺ (Ȧ + dμ²/dt I) y` with `y = A⁻¹ v`, `Ȧ y = J̇ (Jᵀ y) + J (J̇ᵀ y)`.
    #[inline]
    pub fn pinv_dot_mul(&self, v: &SVector<f64, T>) -> SVector<f64, N> {
        let y = self.a.solve(v);
        let a_dot_y = self.jd * self.j.tr_mul(&y) + self.j * self.jd.tr_mul(&y) + y * self.damping_dot;
        self.jd.tr_mul(&y) - self.pinv_mul(&a_dot_y)
    }

    /// `J⁻ v = v − J⁺ (J v)`.
    #[inline]
    pub fn null_mul(&self, v: &SVector<f64, N>) -> SVector<f64, N> {
        v - self.pinv_mul(&matvec::mul(&self.j, v))
    }

    /// `v = J⁺ w + J⁻ x` and its time derivative `v̇ = d(J⁺)/dt w + J⁺ ẇ + d(J⁻)/dt x + J⁻ ẋ`
    /// (the reference velocity `q̇_r` and acceleration `q̈_r` from the task-space `w`, `ẇ` and
    /// the joint-space `x = q̇_d`, `ẋ = q̈_d`).
    ///
    /// The same as [`Self::pinv_mul`], [`Self::pinv_dot_mul`] and [`Self::null_mul`] combined,
    /// with what they share computed once: with `u = w − J x` (so `v = J⁺ u + x`),
    /// `y = A⁻¹ u`, `p = Jᵀ y = J⁺ u` and `s = J̇ᵀ y`,
    ///
    /// ```text
    /// v̇ = d(J⁺)/dt u + J⁺ (ẇ − J̇ x − J ẋ) + ẋ
    ///   = s + Jᵀ A⁻¹ (ẇ − J̇ (x + p) − J (ẋ + s) − dμ²/dt y) + ẋ
    /// ```
    ///
    /// since `d(J⁺)/dt u = s − Jᵀ A⁻¹ (J̇ p + J s + dμ²/dt y)`: two solves and six products
    /// with `J` or `J̇` instead of four solves and thirteen products.
    #[inline]
    pub fn range_and_null_with_rate(
        &self,
        w: &SVector<f64, T>,
        w_dot: &SVector<f64, T>,
        x: &SVector<f64, N>,
        x_dot: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, N>) {
        let (j, jd) = (&self.j, &self.jd);
        let y = self.a.solve(&(w - matvec::mul(j, x)));
        let p = matvec::tr_mul(j, &y);
        let s = matvec::tr_mul(jd, &y);
        let v = p + x;
        let z = w_dot - matvec::mul(jd, &v) - matvec::mul(j, &(x_dot + s)) - y * self.damping_dot;
        let v_dot = s + matvec::tr_mul(j, &self.a.solve(&z)) + x_dot;
        (v, v_dot)
    }

    /// `J̇` (task rows).
    #[inline]
    pub fn jd(&self) -> &SMatrix<f64, T, N> {
        &self.jd
    }

    /// `J` (task rows).
    #[inline]
    pub fn j(&self) -> &SMatrix<f64, T, N> {
        &self.j
    }

    /// `J⁺` as a matrix (for inspection; the law never forms it).
    pub fn pinv(&self) -> SMatrix<f64, N, T> {
        self.j.transpose() * self.a.inverse()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_eigen_decomposes_symmetric_matrices() {
        let mut rng = dyngen_runtime::SplitMix64::new(9);
        for _ in 0..50 {
            let b = SMatrix::<f64, 6, 6>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let a = b * b.transpose();
            let (values, vectors) = symmetric_eigen(&a);
            let back = vectors * SMatrix::<f64, 6, 6>::from_diagonal(&values) * vectors.transpose();
            assert!((back - a).amax() < 1e-12 * a.amax(), "{}", (back - a).amax());
            assert!((vectors.transpose() * vectors - SMatrix::<f64, 6, 6>::identity()).amax() < 1e-12);
        }
    }

    /// The combined `q̇_r`, `q̈_r` equal the separate products they replace, damped or not.
    #[test]
    fn combined_reference_equals_the_separate_products() {
        let mut rng = dyngen_runtime::SplitMix64::new(17);
        let guard = SingularityGuard::default();
        for k in 0..100 {
            let mut j = SMatrix::<f64, 3, 7>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            if k % 2 == 1 {
                // Near-singular: the third row almost a copy of the first, so the guard damps.
                let row = j.row(0) + j.row(2) * 1e-3;
                j.set_row(2, &row);
            }
            let jd = SMatrix::<f64, 3, 7>::from_fn(|_, _| rng.uniform((-1.0, 1.0)));
            let p = Projections::new(&j, &jd, &guard).expect("projections");
            assert_eq!(p.damping > 0.0, k % 2 == 1);
            let vec3 = |rng: &mut dyngen_runtime::SplitMix64| {
                SVector::<f64, 3>::from_fn(|_, _| rng.uniform((-1.0, 1.0)))
            };
            let vec7 = |rng: &mut dyngen_runtime::SplitMix64| {
                SVector::<f64, 7>::from_fn(|_, _| rng.uniform((-1.0, 1.0)))
            };
            let (w, wd, x, xd) = (vec3(&mut rng), vec3(&mut rng), vec7(&mut rng), vec7(&mut rng));
            let (v, v_dot) = p.range_and_null_with_rate(&w, &wd, &x, &xd);
            let v_ref = p.pinv_mul(&w) + p.null_mul(&x);
            // d(J⁻)/dt x = −(d(J⁺)/dt (J x) + J⁺ (J̇ x)).
            let v_dot_ref = p.pinv_dot_mul(&w) + p.pinv_mul(&wd)
                - (p.pinv_dot_mul(&(j * x)) + p.pinv_mul(&(jd * x)))
                + p.null_mul(&xd);
            let scale = v_dot_ref.amax().max(1.0);
            assert!(
                (v - v_ref).amax() < 1e-12 * v_ref.amax().max(1.0),
                "{}",
                (v - v_ref).amax()
            );
            assert!(
                (v_dot - v_dot_ref).amax() < 1e-10 * scale,
                "{}",
                (v_dot - v_dot_ref).amax()
            );
        }
    }
}
