//! Forward dynamics, `D⁻¹` and the derivatives of the dynamics in `f64`: the same generic
//! algorithms the generator traces, for any model at run time.

use super::derivatives::{forward_dynamics_derivatives, inverse_dynamics_derivatives};
use super::forward_dynamics::{forward_dynamics, mass_matrix_inverse};
use super::NumericDynamics;
use nalgebra::{DMatrix, DVector};

impl NumericDynamics<'_> {
    /// Forward dynamics `q̈ = D⁻¹ (τ − C q̇ − g)`.
    pub fn forward_dynamics(&self, q: &[f64], qd: &[f64], tau: &[f64]) -> DVector<f64> {
        let x = self.configuration(q).transforms;
        DVector::from_vec(forward_dynamics(
            self.model,
            &x,
            &self.inertias,
            &self.joint_values,
            qd,
            tau,
        ))
    }

    /// `D(q)⁻¹`.
    pub fn mass_matrix_inverse(&self, q: &[f64]) -> DMatrix<f64> {
        let x = self.configuration(q).transforms;
        mass_matrix_inverse(self.model, &x, &self.inertias, &self.joint_values)
    }

    /// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics at `(q, q̇, q̈)`.
    pub fn inverse_dynamics_derivatives(
        &self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
    ) -> (DMatrix<f64>, DMatrix<f64>) {
        assert_eq!(q.len(), self.model.dof(), "q has the wrong length");
        inverse_dynamics_derivatives(self.model, q, &self.inertias, &self.joint_values, qd, qdd)
    }

    /// `(∂q̈/∂q, ∂q̈/∂q̇)` of forward dynamics at `(q, q̇, τ)`.
    pub fn forward_dynamics_derivatives(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
    ) -> (DMatrix<f64>, DMatrix<f64>) {
        assert_eq!(q.len(), self.model.dof(), "q has the wrong length");
        forward_dynamics_derivatives(self.model, q, &self.inertias, &self.joint_values, qd, tau)
    }
}
