//! Forward dynamics `q̈ = D⁻¹ (τ − C q̇ − g)` and the inverse inertia matrix `D⁻¹`, by the
//! composite-rigid-body `D`, the inverse-dynamics bias `C q̇ + g` (RNEA at `q̈ = 0`) and the tree
//! `LᵀΔL` factorisation of `D`.
//!
//! Why not the articulated-body algorithm: flattened, this route costs fewer operations on arms
//! of up to a few dozen joints (`D` and the bias are already among the cheapest generated
//! functions, and the factorisation and solves are `O(n·depth²)` scalar operations), while the
//! articulated-body inertias are dense 6×6 matrices updated by rank-one corrections at every
//! joint. The figures are in `BENCHMARKS.md`.

use super::crba::mass_matrix;
use super::slotine_li::inverse_dynamics;
use super::tree_ldl::TreeLdl;
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{RigidInertia, Transform};
use nalgebra::DMatrix;

/// `C(q, q̇) q̇ + g(q)`: inverse dynamics at zero acceleration.
pub(crate) fn bias_torque<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    qd: &[S],
) -> Vec<S> {
    let zero = vec![S::zero(); model.dof()];
    inverse_dynamics(model, x, inertias, qd, &zero)
}

/// The factored inertia matrix at the configuration of `x`.
pub fn factor_mass_matrix<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
) -> TreeLdl<S> {
    TreeLdl::factor(model, &mass_matrix(model, x, inertias))
}

/// `q̈` with `D q̈ + C q̇ + g = τ`, given the factored `D`.
pub(crate) fn forward_dynamics_factored<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    factor: &TreeLdl<S>,
    qd: &[S],
    tau: &[S],
) -> Vec<S> {
    let bias = bias_torque(model, x, inertias, qd);
    let rhs: Vec<S> = tau.iter().zip(&bias).map(|(&t, &b)| t - b).collect();
    factor.solve(&rhs)
}

/// Forward dynamics: `q̈ = D⁻¹ (τ − C q̇ − g)`.
pub fn forward_dynamics<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    qd: &[S],
    tau: &[S],
) -> Vec<S> {
    let factor = factor_mass_matrix(model, x, inertias);
    forward_dynamics_factored(model, x, inertias, &factor, qd, tau)
}

/// `D(q)⁻¹`, full and symmetric.
pub fn mass_matrix_inverse<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
) -> DMatrix<S> {
    factor_mass_matrix(model, x, inertias).inverse()
}
