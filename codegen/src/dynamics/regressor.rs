//! The Slotine–Li regressor `Y(q, q̇, v, a)` with `Y θ = D a + C v + g`.

use super::joint::joint_force;
use super::slotine_li::{body_force, forward_pass, gravity_vector};
use crate::model::{Model, PARAMS_PER_BODY};
use crate::scalar::Scalar;
use crate::spatial::{RigidInertia, Transform};
use nalgebra::DMatrix;

/// `Y` (n × 10·n): column block `i` belongs to body `i`'s standard parameters.
///
/// The body force is linear in the body's inertia, so column `k` of a body's block is the
/// body force with unit parameter `k`, carried up the tree and projected on each ancestor joint.
pub fn regressor<S: Scalar>(model: &Model, x: &[Transform<S>], qd: &[S], v: &[S], a: &[S]) -> DMatrix<S> {
    let n = model.dof();
    let motions = forward_pass(model, x, qd, v, a, Some(gravity_vector(model)));
    let mut y = DMatrix::from_element(n, PARAMS_PER_BODY * n, S::zero());
    for (i, m) in motions.iter().enumerate() {
        for k in 0..PARAMS_PER_BODY {
            let col = PARAMS_PER_BODY * i + k;
            let mut f = body_force(&RigidInertia::unit(k), m);
            let mut j = i;
            y[(j, col)] = joint_force(&model.joints()[j], &f);
            while let Some(p) = model.joints()[j].parent {
                f = x[j].force_to_parent(&f);
                j = p;
                y[(j, col)] = joint_force(&model.joints()[j], &f);
            }
        }
    }
    y
}
