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

/// A contact solve done in one generated call (constrained forward dynamics or an impact): one
/// or a few proximal steps, with what the runtime checks them by and refines them from.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactStep<const NV: usize, const NC: usize> {
    /// `a` from the forces below (`q̈` or `ν̇`; for an impact the velocity just after).
    pub acceleration: SVector<f64, NV>,
    /// The forces of the last proximal step, `λ_k = (K + μ I)⁻¹ (rhs + μ λ_{k−1})`.
    pub forces: SVector<f64, NC>,
    /// `λ_{k−1}`, the forces of the step before (the start, after one step), which the change
    /// of the last step is measured from.
    pub previous_forces: SVector<f64, NC>,
    /// The Delassus matrix `K = J M⁻¹ Jᵀ`.
    pub delassus: SMatrix<f64, NC, NC>,
    /// The pivots of `K + μ I`'s `L D Lᵀ` factor (`D`'s diagonal): one at rounding level
    /// against `K`'s diagonal means rows that depend on one another.
    pub pivots: SVector<f64, NC>,
    /// `rhs`, what `K λ` must equal: the rows' target less what they do without forces.
    pub rhs: SVector<f64, NC>,
}

/// The operational-space inertia of the contact rows computed in one generated call.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactInertia<const NC: usize> {
    /// `(K + ε I)⁻¹`.
    pub inertia: SMatrix<f64, NC, NC>,
    /// The pivots of `K + ε I`'s `L D Lᵀ` factor.
    pub pivots: SVector<f64, NC>,
    /// `K`'s diagonal, which the pivots are judged against.
    pub delassus_diagonal: SVector<f64, NC>,
}
