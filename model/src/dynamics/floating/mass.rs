//! The mass matrix (nv × nv) of a floating-base robot by composite rigid bodies, and forward
//! dynamics by its tree factorisation, the base's six coordinates a chain above the roots.
//!
//! With mimic joints `D` is the tree's carried through `G` on its joint rows and columns
//! (`coupling`); with joint-level terms forward dynamics and `D⁻¹` take the armature on the
//! joints' diagonal and the friction and offset in the bias (`joint_terms`), as a fixed base's.

use super::{base_entries, inverse::floating_inverse_dynamics, unit_base_motion, FloatingBase};
use crate::dynamics::coupling::project_both_after;
use crate::dynamics::crba::{composite_inertias, tree_mass_matrix};
use crate::dynamics::joint::joint_motion;
use crate::dynamics::joint_terms::{add_armature_after, with_joint_term_torques};
use crate::dynamics::tree_ldl::{velocity_parents, TreeLdl};
use crate::model::{JointTermValues, Model};
use crate::scalar::Scalar;
use crate::spatial::{Force, RigidInertia, Transform};
use nalgebra::DMatrix;

/// `D(q)`: the base block is the whole robot's composite inertia in the base frame (constant in
/// base coordinates), the base–joint blocks each joint's subtree inertia times its axis carried
/// to the base, the joint block the fixed-base tree's.
pub fn floating_mass_matrix<S: Scalar>(
    model: &Model,
    base_inertia: &RigidInertia<S>,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
) -> DMatrix<S> {
    let n = model.joints().len();
    let composite = composite_inertias(model, x, inertias);
    let mut whole = *base_inertia;
    for (i, joint) in model.joints().iter().enumerate() {
        if joint.parent.is_none() {
            whole = whole + composite[i].to_parent(&x[i]);
        }
    }
    let mut d = DMatrix::from_element(6 + n, 6 + n, S::zero());
    for k in 0..6 {
        let column = base_entries(&whole.mul_motion(&unit_base_motion(k)));
        for (r, value) in column.into_iter().enumerate() {
            d[(r, k)] = value;
        }
    }
    for i in 0..n {
        let mut f: Force<S> = composite[i].mul_motion(&joint_motion(&model.joints()[i], S::one()));
        let mut j = i;
        while let Some(p) = model.joints()[j].parent {
            f = x[j].force_to_parent(&f);
            j = p;
        }
        let on_base = base_entries(&x[j].force_to_parent(&f));
        for (r, value) in on_base.into_iter().enumerate() {
            d[(r, 6 + i)] = value;
            d[(6 + i, r)] = value;
        }
    }
    let tree = tree_mass_matrix(model, x, inertias);
    d.view_mut((6, 6), (n, n)).copy_from(&tree);
    project_both_after(model, d, 6)
}

/// `D` with the armature on the joints' diagonal (`joint_values`, the model's or an identified
/// θ's), factored along the tree (the base's six coordinates the root of every branch).
pub fn factor<S: Scalar>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
) -> TreeLdl<S> {
    let mut d = floating_mass_matrix(model, &base.inertia, x, inertias);
    add_armature_after(model, joint_values, &mut d, 6);
    TreeLdl::factor_tree(velocity_parents(model), &d)
}

/// `C(q, ν) ν + g(q)` plus the joints' friction and offset: inverse dynamics at zero
/// acceleration.
pub fn floating_bias<S: Scalar>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
) -> Vec<S> {
    let zero = vec![S::zero(); model.nv()];
    let rigid = floating_inverse_dynamics(model, base, x, inertias, qd, &zero);
    let joints = (&qd[6..], &qd[6..], &zero[6..]);
    with_joint_term_torques(model, joint_values, rigid, 6, joints)
}

/// Forward dynamics `ν̇ = D⁻¹ (τ − C ν − g)`, `tau` the base wrench and the joint torques.
pub fn floating_forward_dynamics<S: Scalar>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    tau: &[S],
) -> Vec<S> {
    let bias = floating_bias(model, base, x, inertias, joint_values, qd);
    let rhs: Vec<S> = tau.iter().zip(&bias).map(|(&t, &b)| t - b).collect();
    factor(model, base, x, inertias, joint_values).solve(&rhs)
}

/// `D(q)⁻¹`, full and symmetric.
pub fn floating_mass_matrix_inverse<S: Scalar>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
) -> DMatrix<S> {
    factor(model, base, x, inertias, joint_values).inverse()
}

/// [`floating_mass_matrix_inverse`] by sums over common ancestors
/// (`TreeLdl::inverse_by_ancestors`): the same values, other operations.
pub fn floating_mass_matrix_inverse_by_ancestors<S: Scalar>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[Transform<S>],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
) -> DMatrix<S> {
    factor(model, base, x, inertias, joint_values).inverse_by_ancestors()
}
