//! Derivatives of inverse and forward dynamics with respect to `q` and `q̇`, by forward-mode
//! differentiation of the inverse-dynamics recursion itself: it is run on [`Dual`] numbers once
//! per direction (`q_j`, then `q̇_j`), so the derivatives are the same algorithm, written once.
//!
//! Symbolically (with `S = Expr`) every run's values are the nodes of the plain recursion and
//! every tangent that the tree makes zero folds away as it is built (joint `j`'s angle moves only
//! the bodies below it; its force reaches only `j`'s ancestors), so the flattened cost is that of
//! the analytical derivatives of Carpentier & Mansard (2018) without a second algorithm to own.
//! Operation counts are compared in `BENCHMARKS.md`.
//!
//! The velocity derivative needs no differentiation either: `τ = D q̈ + C q̇ + g` with `C` the
//! Christoffel-consistent matrix, `(C q̇)_i = Σ_jk Γ_ijk q̇_j q̇_k` with `Γ_ijk = Γ_ikj`, so
//! `∂τ/∂q̇ = 2 C(q, q̇)`, which [`coriolis_matrix`] computes in fewer operations than `n` dual
//! runs of the recursion (Panda: 2191 against about 4900).
//!
//! Joint-level terms (when the model has them) depend on `q̇` and `q̈` only: their `∂/∂q̇` is
//! diagonal and comes from one dual run of those terms per joint (Coulomb friction without
//! smoothing, `sign(q̇)`, has derivative zero where it exists).
//!
//! Forward dynamics needs no differentiation of its own: with `q̈ = FD(q, q̇, τ)` fixed,
//! `D ∂q̈/∂x = −∂τ/∂x |_{q̈}`, so `∂q̈/∂x = −D⁻¹ ∂ID/∂x` evaluated at that `q̈`, solved with the
//! factors forward dynamics already has.

use super::coriolis::coriolis_matrix;
use super::forward_dynamics::{factor_mass_matrix, forward_dynamics_factored};
use super::joint::joint_transforms;
use super::joint_terms::joint_term_torques;
use super::slotine_li::inverse_dynamics;
use crate::model::{JointTermValues, Model};
use crate::scalar::Scalar;
use crate::scalar_dual::Dual;
use crate::spatial::{RigidInertia, Vec3};
use nalgebra::DMatrix;

fn constant<S: Scalar>(v: &[S]) -> Vec<Dual<S>> {
    v.iter().map(|&x| Dual::constant(x)).collect()
}

/// `v` with the derivative taken along its entry `j`.
fn seeded<S: Scalar>(v: &[S], j: usize) -> Vec<Dual<S>> {
    let mut out = constant(v);
    out[j] = Dual::variable(v[j]);
    out
}

fn lift_inertia<S: Scalar>(i: &RigidInertia<S>) -> RigidInertia<Dual<S>> {
    RigidInertia {
        m: Dual::constant(i.m),
        h: Vec3(i.h.0.map(Dual::constant)),
        i: i.i.map(Dual::constant),
    }
}

/// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics `τ(q, q̇, q̈)`; entry `(i, j)` is `∂τ_i/∂x_j`.
/// (`∂τ/∂q̈ = D`.)
pub fn inverse_dynamics_derivatives<S: Scalar>(
    model: &Model,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    qdd: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let n = model.dof();
    let dual_inertias: Vec<RigidInertia<Dual<S>>> = inertias.iter().map(lift_inertia).collect();
    let (qd_const, qdd_const) = (constant(qd), constant(qdd));
    let mut d_q = DMatrix::from_element(n, n, S::zero());
    for j in 0..n {
        let x = joint_transforms(model, &seeded(q, j));
        let tau = inverse_dynamics(model, &x, &dual_inertias, &qd_const, &qdd_const);
        for (i, t) in tau.iter().enumerate() {
            d_q[(i, j)] = t.tangent;
        }
    }
    let two = S::from_f64(2.0);
    let mut d_qd = coriolis_matrix(model, &joint_transforms(model, q), inertias, qd).map(|c| two * c);
    if !model.joint_terms().kinds.is_empty() {
        for j in 0..n {
            let seeded_qd = seeded(qd, j);
            let joint = joint_term_torques(model, joint_values, &seeded_qd, &seeded_qd, &qdd_const);
            d_qd[(j, j)] = d_qd[(j, j)] + joint[j].tangent;
        }
    }
    (d_q, d_qd)
}

/// `(∂q̈/∂q, ∂q̈/∂q̇)` of forward dynamics `q̈(q, q̇, τ)`. (`∂q̈/∂τ = D⁻¹`.)
pub fn forward_dynamics_derivatives<S: Scalar>(
    model: &Model,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    tau: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let x = joint_transforms(model, q);
    let factor = factor_mass_matrix(model, &x, inertias, joint_values);
    let qdd = forward_dynamics_factored(model, &x, inertias, joint_values, &factor, qd, tau);
    let (d_q, d_qd) = inverse_dynamics_derivatives(model, q, inertias, joint_values, qd, &qdd);
    let minus_solve = |m: DMatrix<S>| factor.solve_matrix(&m.map(|v| -v));
    (minus_solve(d_q), minus_solve(d_qd))
}
