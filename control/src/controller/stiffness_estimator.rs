//! Online contact stiffness estimation (Remark 3 of the note). **No stability proof exists for
//! the controller that uses this estimate**; the demo shows where it works and where it fails.
//!
//! The contact directions are taken as known (they are fixed by the surface geometry, like `R`)
//! and the stiffness magnitudes are estimated: `K̂ = diag(k̂) K₀` with `K₀` the unit rows of the
//! nominal `K`. Each row is fitted by a normalised gradient on the measured force,
//! `k̂ᵢ ← k̂ᵢ + γ dt (F_{t,i} − k̂ᵢ sᵢ) sᵢ / (ε + sᵢ²)` with `sᵢ = K₀ᵢ (x_t − x_e)`, only while
//! that row is in contact (measured force above a threshold). Keeping `k̂ᵢ ≥ k_min > 0` keeps
//! `K̂` of full row rank (`K₀` has full row rank).

use super::error::ConfigError;
use super::task::Split;
use nalgebra::{SMatrix, SVector, Vector3};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StiffnessEstimator<const S: usize> {
    directions: SMatrix<f64, S, 3>,
    k_hat: SVector<f64, S>,
    /// Adaptation rate `γ` (1/s).
    pub rate: f64,
    /// Lower bound `k_min` on every `k̂ᵢ` (N/m).
    pub min_stiffness: f64,
    /// Rows update only while their measured force exceeds this (N).
    pub force_threshold: f64,
    /// `ε` in the normalisation (m²).
    pub epsilon: f64,
}

impl<const S: usize> StiffnessEstimator<S> {
    /// Starts from `k_hat0` (S×3, full row rank): its row norms are the initial magnitudes.
    pub fn new(k_hat0: &SMatrix<f64, S, 3>, rate: f64) -> Result<Self, ConfigError> {
        Split::new(k_hat0)?;
        if !(rate.is_finite() && rate >= 0.0) {
            return Err(ConfigError::Invalid {
                name: "stiffness estimation rate",
                detail: format!("{rate} must be ≥ 0"),
            });
        }
        let mut directions = *k_hat0;
        let mut k_hat = SVector::<f64, S>::zeros();
        for i in 0..S {
            let n = k_hat0.row(i).norm();
            k_hat[i] = n;
            directions.set_row(i, &(k_hat0.row(i) / n));
        }
        let min = k_hat.min();
        Ok(StiffnessEstimator {
            directions,
            k_hat,
            rate,
            min_stiffness: 1e-2 * min,
            force_threshold: 0.2,
            epsilon: 1e-10,
        })
    }

    /// The current `K̂`.
    pub fn stiffness(&self) -> SMatrix<f64, S, 3> {
        SMatrix::from_fn(|i, j| self.k_hat[i] * self.directions[(i, j)])
    }

    /// The current magnitudes `k̂`.
    pub fn magnitudes(&self) -> SVector<f64, S> {
        self.k_hat
    }

    /// One update from the task-frame deflection `x_t − x_e` and the measured `F_t`.
    pub fn update(&mut self, deflection: &Vector3<f64>, force: &SVector<f64, S>, dt: f64) {
        for i in 0..S {
            if force[i] <= self.force_threshold {
                continue;
            }
            let s = (self.directions.row(i) * deflection)[0];
            let e = force[i] - self.k_hat[i] * s;
            let k = self.k_hat[i] + self.rate * dt * e * s / (self.epsilon + s * s);
            if k.is_finite() {
                self.k_hat[i] = k.max(self.min_stiffness);
            }
        }
    }
}
