//! The joint-space mass matrix `D(q)` by the composite-rigid-body algorithm.

use super::coupling::project_both;
use super::joint::{joint_force, joint_motion};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{CompositeFrame, RigidInertia};
use nalgebra::DMatrix;

/// `D(q)`, full and symmetric, on the coordinates (`Gᵀ D_tree G` with mimic joints).
pub fn mass_matrix<S: Scalar, X: CompositeFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
) -> DMatrix<S> {
    project_both(model, tree_mass_matrix(model, x, inertias))
}

/// The mass matrix of the tree, one row per moving joint.
pub fn tree_mass_matrix<S: Scalar, X: CompositeFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
) -> DMatrix<S> {
    let n = model.joints().len();
    let composite = composite_inertias(model, x, inertias);
    let mut d = DMatrix::from_element(n, n, S::zero());
    for i in 0..n {
        let mut f = composite[i].mul_motion(&joint_motion(&model.joints()[i], S::one()));
        d[(i, i)] = joint_force(&model.joints()[i], &f);
        let mut j = i;
        while let Some(p) = model.joints()[j].parent {
            f = x[j].force_to_parent(&f);
            j = p;
            let dij = joint_force(&model.joints()[j], &f);
            d[(i, j)] = dij;
            d[(j, i)] = dij;
        }
    }
    d
}

/// The composite inertia of each body's subtree, in that body's frame.
pub fn composite_inertias<S: Scalar, X: CompositeFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
) -> Vec<RigidInertia<S>> {
    // Children have larger indices, so one sweep from the leaves up sums every subtree.
    let mut composite = inertias.to_vec();
    for i in (0..model.joints().len()).rev() {
        if let Some(p) = model.joints()[i].parent {
            let up = x[i].inertia_to_parent(&composite[i]);
            composite[p] = composite[p] + up;
        }
    }
    composite
}
