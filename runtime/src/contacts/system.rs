//! What a contact solve reads at one state, computed by one generated call: a generated robot
//! shares the kinematics and the factored mass matrix among them, where calling
//! [`ContactDynamics`](super::ContactDynamics)' rows one by one factors the mass matrix once
//! for `M⁻¹ Jᵀ` and again for the free acceleration, and leaves `K` to a dense product.

use nalgebra::{SMatrix, SVector};

/// The matrices of the contact rows at a configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactMatrices<const NV: usize, const NC: usize> {
    /// `J` (NC × NV): the contacts' rows, stacked.
    pub jacobian: SMatrix<f64, NC, NV>,
    /// `M⁻¹ Jᵀ` (NV × NC): how the robot accelerates under a unit force in each row.
    pub response: SMatrix<f64, NV, NC>,
    /// The Delassus matrix `K = J M⁻¹ Jᵀ` (NC × NC, symmetric): how each row accelerates under
    /// a unit force in each row.
    pub delassus: SMatrix<f64, NC, NC>,
}

/// The matrices of the contact rows and the vectors of a state: everything constrained forward
/// dynamics solves with.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSystem<const NV: usize, const NC: usize> {
    pub matrices: ContactMatrices<NV, NC>,
    /// What `J a` is at `a = 0` along `v`.
    pub drift: SVector<f64, NC>,
    /// Forward dynamics without contacts, `M⁻¹ (τ − b)`.
    pub free_acceleration: SVector<f64, NV>,
}
