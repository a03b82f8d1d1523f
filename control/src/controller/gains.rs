//! Controller gains, their checks, and the default `G = κ D̂(q₀)`.

use super::error::ConfigError;
use crate::mass_matrix_through_regressor;
use dyngen_runtime::{JointTrig, Parameterization};
use nalgebra::{Cholesky, SMatrix, SVector};

/// Gains of the law: `λ` (force and position error), `λ_n` (null-space posture), `G` (sliding
/// variable, symmetric positive definite), `Γ` (adaptation, diagonal, ≥ 0: a zero entry holds
/// that parameter at its estimate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gains<const N: usize, const M: usize> {
    pub lambda: f64,
    pub lambda_null: f64,
    pub g: SMatrix<f64, N, N>,
    pub gamma: SVector<f64, M>,
}

impl<const N: usize, const M: usize> Gains<N, M> {
    /// Checks every gain is positive (definite); `Γ` only when adapting, and there entries of 0
    /// are allowed (that parameter is not adapted: the joint terms of a robot whose
    /// joint-level gain is 0).
    pub fn validate(&self, adapting: bool) -> Result<(), ConfigError> {
        let pd = |name: &'static str, detail: String| ConfigError::NotPositiveDefinite { name, detail };
        if !(self.lambda.is_finite() && self.lambda > 0.0) {
            return Err(pd("λ", format!("λ = {} must be > 0", self.lambda)));
        }
        if !(self.lambda_null.is_finite() && self.lambda_null >= 0.0) {
            return Err(pd("λ_n", format!("λ_n = {} must be ≥ 0", self.lambda_null)));
        }
        let asym = (self.g - self.g.transpose()).amax();
        if !self.g.iter().all(|x| x.is_finite()) || asym > 1e-9 * self.g.amax().max(1.0) {
            return Err(pd("G", format!("not symmetric (‖G − Gᵀ‖ = {asym:.1e})")));
        }
        if Cholesky::new(self.g).is_none() {
            return Err(pd(
                "G",
                "the Cholesky factorisation fails: an eigenvalue is ≤ 0".into(),
            ));
        }
        if adapting {
            if let Some((i, g)) = self
                .gamma
                .iter()
                .enumerate()
                .find(|(_, g)| !(g.is_finite() && **g >= 0.0))
            {
                return Err(pd(
                    "Γ",
                    format!("entry {i} is {g}; every diagonal entry must be ≥ 0"),
                ));
            }
        }
        Ok(())
    }

    /// `λ_max(D̂⁻¹ G)`, the fastest mode of `D̂ ṙ = −G r`: 200 steps of power iteration
    /// `x ← D̂⁻¹ G x / ‖D̂⁻¹ G x‖` from `x ∝ (1, …, 1)` (a Cholesky solve each, no convergence
    /// test, stopping early only if the iterate vanishes or is not finite), returning the
    /// generalised Rayleigh quotient `xᵀGx / xᵀD̂x` of the iterate the last step started from.
    /// The eigenvalues of `D̂⁻¹G` are real and positive (those of the symmetric `L⁻¹ G L⁻ᵀ`,
    /// `D̂ = L Lᵀ`) and that quotient lies between the smallest and the largest, so the result
    /// never exceeds `λ_max`; when `G = κ D̂` for this very `D̂` it is exactly `κ`. The sampling
    /// limit checked with it is `λ_max(D̂⁻¹G)·dt ≲ 1.5` (`docs/controller.md`).
    pub fn stiffest_mode(&self, d_hat: &SMatrix<f64, N, N>) -> Result<f64, ConfigError> {
        let chol = Cholesky::new(*d_hat).ok_or_else(|| ConfigError::NotPositiveDefinite {
            name: "D̂(q₀)",
            detail: "the controller's mass matrix estimate is not positive definite".into(),
        })?;
        let mut x = SVector::<f64, N>::from_element(1.0).normalize();
        let mut lam = 0.0;
        for _ in 0..200 {
            let y = chol.solve(&(self.g * x));
            lam = x.dot(&(self.g * x)).max(0.0);
            // Rayleigh quotient in the D̂ metric: xᵀGx / xᵀD̂x, iterate x ← D̂⁻¹Gx.
            lam /= x.dot(&(d_hat * x));
            let n = y.norm();
            if !(n.is_finite() && n > 0.0) {
                break;
            }
            x = y / n;
        }
        Ok(lam)
    }
}

/// The controller's own mass matrix estimate `D̂(q)` at `θ̂`, symmetrised (rounding only).
pub fn mass_matrix_estimate<Z, const N: usize, const M: usize>(
    q: &SVector<f64, N>,
    theta_hat: &SVector<f64, M>,
) -> SMatrix<f64, N, N>
where
    Z: Parameterization<N, M>,
{
    let d = mass_matrix_through_regressor::<Z, N, M>(&JointTrig::new(q), theta_hat);
    (d + d.transpose()) * 0.5
}

/// `G = κ D̂(q₀)`, the full SPD gain that is stable at 1 kHz where a diagonal one is not
/// (`docs/controller.md`, gains).
pub fn mass_matrix_shaped_gain<Z, const N: usize, const M: usize>(
    kappa: f64,
    q0: &SVector<f64, N>,
    theta_hat: &SVector<f64, M>,
) -> SMatrix<f64, N, N>
where
    Z: Parameterization<N, M>,
{
    mass_matrix_estimate::<Z, N, M>(q0, theta_hat) * kappa
}
