//! `J⁺`, `J⁻` and their time derivatives, with the singularity guard.
//!
//! # Singularity guard
//! `J⁺ = Jᵀ (J Jᵀ + μ² I)⁻¹` (damped least squares) where the damping is **zero** while the
//! smallest eigenvalue `σ²_min` of `J Jᵀ` (the squared smallest singular value of the 3×N
//! position Jacobian) stays above `σ₀²`, so the exact law of the note holds away from
//! singularities; below it `μ² = μ²_max (1 − σ²_min/σ₀²)` grows continuously to `μ²_max`. The
//! time derivative of `J⁺` includes the derivative of `μ²` (`dσ²_min/dt = uᵀ (J̇Jᵀ + JJ̇ᵀ) u` for
//! the unit eigenvector `u`), so `q̈_r` stays the exact derivative of `q̇_r` and the closed loop
//! `D ṙ + C r + G r = Y θ̃` (hence `V̇ = −rᵀ G r`) holds inside the damped region too; what is
//! lost there is exact task tracking (`J J⁺ ≠ I`), not stability of `r`. The torque is also
//! saturated and checked for NaN in the law (see `law.rs`).

use super::error::TickError;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Damped-least-squares settings (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SingularityGuard {
    /// `σ₀`: the smallest singular value of the position Jacobian (m/rad) below which damping
    /// starts.
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
pub struct Projections<const N: usize> {
    j: SMatrix<f64, 3, N>,
    jd: SMatrix<f64, 3, N>,
    /// `(J Jᵀ + μ² I)⁻¹`
    a_inv: Matrix3<f64>,
    /// `dμ²/dt`
    damping_dot: f64,
    /// The damping `μ²` used (0 away from singularities).
    pub damping: f64,
    /// Smallest singular value of `J` (a lower bound of it when far from the threshold).
    pub sigma_min: f64,
}

/// Smallest singular value of a 3×N Jacobian and the unit eigenvector of `J Jᵀ` that goes with it.
pub fn smallest_singular<const N: usize>(j: &SMatrix<f64, 3, N>) -> (f64, nalgebra::Vector3<f64>) {
    let a = j * j.transpose();
    let eig = a.symmetric_eigen();
    let (mut k, mut min) = (0, f64::INFINITY);
    for (i, &e) in eig.eigenvalues.iter().enumerate() {
        if e < min {
            min = e;
            k = i;
        }
    }
    (min.max(0.0).sqrt(), eig.eigenvectors.column(k).into_owned())
}

impl<const N: usize> Projections<N> {
    pub fn new(
        j: &SMatrix<f64, 3, N>,
        jd: &SMatrix<f64, 3, N>,
        guard: &SingularityGuard,
    ) -> Result<Self, TickError> {
        let a = j * j.transpose();
        let a_dot = jd * j.transpose() + j * jd.transpose();
        let s0 = guard.sigma_threshold * guard.sigma_threshold;
        // Cheap lower bound first: for eigenvalues l1 ≤ l2 ≤ l3 of the SPD `A`,
        // l2·l3 ≤ (tr/2)², so l1 ≥ 4 det / tr². The eigen-decomposition is needed only when the
        // bound does not already clear the threshold (near a singularity).
        let tr = a.trace();
        let bound = 4.0 * a.determinant() / (tr * tr);
        let (sigma_min, damping, damping_dot) = if bound >= s0 {
            (bound.sqrt(), 0.0, 0.0)
        } else {
            let (sigma_min, u) = smallest_singular(j);
            let s2 = sigma_min * sigma_min;
            if s2 < s0 {
                let d_s2 = (u.transpose() * a_dot * u)[0];
                (
                    sigma_min,
                    guard.max_damping * (1.0 - s2 / s0),
                    -guard.max_damping / s0 * d_s2,
                )
            } else {
                (sigma_min, 0.0, 0.0)
            }
        };
        let a_inv = (a + Matrix3::identity() * damping)
            .try_inverse()
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

impl<const N: usize> Projections<N> {
    /// `J⁺ v = Jᵀ (A⁻¹ v)`.
    #[inline]
    pub fn pinv_mul(&self, v: &Vector3<f64>) -> SVector<f64, N> {
        self.j.tr_mul(&(self.a_inv * v))
    }

    /// `d(J⁺)/dt v = J̇ᵀ y − J⁺ (Ȧ + dμ²/dt I) y` with `y = A⁻¹ v`, `Ȧ y = J̇ (Jᵀ y) + J (J̇ᵀ y)`.
    #[inline]
    pub fn pinv_dot_mul(&self, v: &Vector3<f64>) -> SVector<f64, N> {
        let y = self.a_inv * v;
        let a_dot_y = self.jd * self.j.tr_mul(&y) + self.j * self.jd.tr_mul(&y) + y * self.damping_dot;
        self.jd.tr_mul(&y) - self.pinv_mul(&a_dot_y)
    }

    /// `J⁻ v = v − J⁺ (J v)`.
    #[inline]
    pub fn null_mul(&self, v: &SVector<f64, N>) -> SVector<f64, N> {
        v - self.pinv_mul(&(self.j * v))
    }

    /// `J̇` (position rows).
    #[inline]
    pub fn jd(&self) -> &SMatrix<f64, 3, N> {
        &self.jd
    }

    /// `J⁺` as a matrix (for inspection; the law never forms it).
    pub fn pinv(&self) -> SMatrix<f64, N, 3> {
        self.j.transpose() * self.a_inv
    }
}
