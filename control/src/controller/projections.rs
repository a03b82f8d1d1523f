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
use nalgebra::{Cholesky, SMatrix, SVector};

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
    /// `(J Jᵀ + μ² I)⁻¹`
    a_inv: SMatrix<f64, T, T>,
    /// `dμ²/dt`
    damping_dot: f64,
    /// The damping `μ²` used (0 away from singularities).
    pub damping: f64,
    /// Smallest singular value of `J` (a lower bound of it when far from the threshold).
    pub sigma_min: f64,
}

/// Smallest singular value of a T×N Jacobian and the unit eigenvector of `J Jᵀ` that goes with it.
pub fn smallest_singular<const N: usize, const T: usize>(j: &SMatrix<f64, T, N>) -> (f64, SVector<f64, T>) {
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
pub fn symmetric_eigen<const T: usize>(a: &SMatrix<f64, T, T>) -> (SVector<f64, T>, SMatrix<f64, T, T>) {
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
        let a = j * j.transpose();
        let s0 = guard.sigma_threshold * guard.sigma_threshold;
        // Cheap lower bound first: for eigenvalues l1 ≤ … ≤ l_T of the SPD `A`, the product of
        // the other T − 1 is at most (tr/(T − 1))^(T−1), so l1 ≥ det / (tr/(T − 1))^(T−1)
        // (4 det / tr² for T = 3). det from the Cholesky factor. The eigen-decomposition is
        // needed only when the bound does not already clear the threshold (near a singularity).
        let tr = a.trace();
        let chol = Cholesky::new(a);
        let bound = chol.as_ref().map_or(0.0, |c| {
            let d = c.l_dirty().diagonal().iter().fold(1.0, |p, x| p * x * x);
            d / (tr / (T - 1) as f64).powi(T as i32 - 1)
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
        let chol = match chol {
            Some(c) if damping == 0.0 => Some(c),
            _ => Cholesky::new(a + SMatrix::<f64, T, T>::identity() * damping),
        };
        let a_inv = chol
            .map(|c| c.inverse())
            .filter(|m| m.iter().all(|x| x.is_finite()))
            .ok_or(TickError::Singular(sigma_min * sigma_min))?;
        Ok(Projections {
            j: *j,
            jd: *jd,
            a_inv,
            damping_dot,
            damping,
            sigma_min,
        })
    }
}

impl<const N: usize, const T: usize> Projections<N, T> {
    /// `J⁺ v = Jᵀ (A⁻¹ v)`.
    #[inline]
    pub fn pinv_mul(&self, v: &SVector<f64, T>) -> SVector<f64, N> {
        self.j.tr_mul(&(self.a_inv * v))
    }

    /// `d(J⁺)/dt v = J̇ᵀ y − J⁺ (Ȧ + dμ²/dt I) y` with `y = A⁻¹ v`, `Ȧ y = J̇ (Jᵀ y) + J (J̇ᵀ y)`.
    #[inline]
    pub fn pinv_dot_mul(&self, v: &SVector<f64, T>) -> SVector<f64, N> {
        let y = self.a_inv * v;
        let a_dot_y = self.jd * self.j.tr_mul(&y) + self.j * self.jd.tr_mul(&y) + y * self.damping_dot;
        self.jd.tr_mul(&y) - self.pinv_mul(&a_dot_y)
    }

    /// `J⁻ v = v − J⁺ (J v)`.
    #[inline]
    pub fn null_mul(&self, v: &SVector<f64, N>) -> SVector<f64, N> {
        v - self.pinv_mul(&(self.j * v))
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
        self.j.transpose() * self.a_inv
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
}
