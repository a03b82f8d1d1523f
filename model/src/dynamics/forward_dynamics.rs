//! Forward dynamics `q̈ = D⁻¹ (τ − C q̇ − g)` and the inverse mass matrix `D⁻¹`, by the
//! composite-rigid-body `D`, the inverse-dynamics bias `C q̇ + g` (RNEA at `q̈ = 0`) and the tree
//! `LᵀΔL` factorisation of `D`.
//!
//! Why not the articulated-body algorithm: flattened, this route costs fewer operations on arms
//! of up to a few dozen joints (`D` and the bias are already among the cheapest generated
//! functions, and the factorisation and solves are `O(n·depth²)` scalar operations), while the
//! articulated-body inertias are dense 6×6 matrices updated by rank-one corrections at every
//! joint. The operation counts: `docs/performance-notes.md`.
//!
//! Joint-level terms, when the model has them (`joint_terms.rs`), enter as everywhere else: the
//! armature on the diagonal of `D`, friction and offset in the bias. `joint_values` are the
//! model's (or an identified θ's) values of those terms.

use super::crba::mass_matrix;
use super::joint_terms::{add_armature, joint_term_torques};
use super::newton_euler::inverse_dynamics;
use super::tree_ldl::TreeLdl;
use crate::model::{JointTermValues, Model};
use crate::scalar::Scalar;
use crate::spatial::{CompositeFrame, RigidInertia};
use nalgebra::DMatrix;

/// `C(q, q̇) q̇ + g(q)` plus the joint-level friction and offset: inverse dynamics at zero
/// acceleration.
pub fn bias_torque<S: Scalar, X: CompositeFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
) -> Vec<S> {
    let zero = vec![S::zero(); model.dof()];
    let rigid = inverse_dynamics(model, x, inertias, qd, &zero);
    if model.joint_terms().kinds.is_empty() {
        return rigid;
    }
    let joint = joint_term_torques(model, joint_values, qd, qd, &zero);
    rigid.into_iter().zip(joint).map(|(r, j)| r + j).collect()
}

/// The factored mass matrix (armature included) at the configuration of `x`.
pub fn factor_mass_matrix<S: Scalar, X: CompositeFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
) -> TreeLdl<S> {
    let mut d = mass_matrix(model, x, inertias);
    add_armature(model, joint_values, &mut d);
    TreeLdl::factor(model, &d)
}

/// `q̈` with `D q̈ + C q̇ + g = τ`, given the factored `D`.
pub fn forward_dynamics_factored<S: Scalar, X: CompositeFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    factor: &TreeLdl<S>,
    qd: &[S],
    tau: &[S],
) -> Vec<S> {
    let bias = bias_torque(model, x, inertias, joint_values, qd);
    let rhs: Vec<S> = tau.iter().zip(&bias).map(|(&t, &b)| t - b).collect();
    factor.solve(&rhs)
}

/// Forward dynamics: `q̈ = D⁻¹ (τ − C q̇ − g)`.
pub fn forward_dynamics<S: Scalar, X: CompositeFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    tau: &[S],
) -> Vec<S> {
    let factor = factor_mass_matrix(model, x, inertias, joint_values);
    forward_dynamics_factored(model, x, inertias, joint_values, &factor, qd, tau)
}

/// `D(q)⁻¹`, full and symmetric.
pub fn mass_matrix_inverse<S: Scalar, X: CompositeFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
) -> DMatrix<S> {
    factor_mass_matrix(model, x, inertias, joint_values).inverse()
}
