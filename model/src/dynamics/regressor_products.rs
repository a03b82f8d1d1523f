//! `Y θ` and `Yᵀ r` of the Slotine–Li regressor's columns `cols` without forming `Y`: what an
//! adaptive law needs each tick (`τ = Y θ̂ + …`, `θ̂̇ = −Γ Yᵀ r`).
//!
//! Why: `Y` costs one force per column carried up to the base and projected on every joint on
//! the way; both products cost one force per column and no carrying. Column `c` (a parameter
//! of body `j`) is the force `f_c` of body `j` with that unit parameter, projected on the joints
//! above `j`, so
//! - `(Yᵀ r)_c = Σ_{i ≤ j} r_i S_iᵀ X*_{i←j} f_c = w_j · f_c`, with `w_j = Σ_{i ≤ j} X_{j←i} S_i r_i`
//!   the velocity body `j` would have with joint rates `r` (a motion and a force are dual, so
//!   carrying the force down to the joints is carrying the rates up to the body);
//! - `Y θ` is the Slotine–Li torque of the bodies' forces `Σ_c θ_c f_c`: one pass up the tree for
//!   all columns together.
//!
//! A joint-level column (armature, friction, offset) is non-zero in its joint's row only.
//! With mimic joints, `Y = Gᵀ Y_tree`: `Yᵀ r = Y_treeᵀ (G r)` and `Y θ = Gᵀ (Y_tree θ)`.

use super::coupling::{expand, project};
use super::joint::{joint_force, joint_motion};
use super::joint_terms::column_entry;
use super::slotine_li::{forward_pass, gravity_vector, unit_body_force};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{Force, Motion, Transform};
use dyngen_runtime::PARAMETERS_PER_BODY;

/// `(Y θ, Yᵀ r)` of the columns `cols` of the Slotine–Li regressor `Y(q, q̇, v, a)` (`θ` has one
/// entry per column of `cols`, `Yᵀ r` one per column).
#[allow(clippy::too_many_arguments)]
pub fn regressor_products<S: Scalar>(
    model: &Model,
    x: &[Transform<S>],
    qd: &[S],
    v: &[S],
    a: &[S],
    cols: &[usize],
    theta: &[S],
    r: &[S],
) -> (Vec<S>, Vec<S>) {
    let (qd, v, a, r) = (
        expand(model, qd),
        expand(model, v),
        expand(model, a),
        expand(model, r),
    );
    let joints = model.joints();
    let motions = forward_pass(model, x, &qd, &v, &a, Some(gravity_vector(model)));
    // The velocities the joint rates `r` give the bodies.
    let mut w: Vec<Motion<S>> = Vec::with_capacity(joints.len());
    for (i, joint) in joints.iter().enumerate() {
        let up = joint
            .parent
            .map_or(Motion::zero(), |p| x[i].motion_to_child(&w[p]));
        w.push(up + joint_motion(joint, r[i]));
    }
    let inertial = model.inertial_parameter_count();
    let mut forces = vec![Force::zero(); joints.len()];
    let mut joint_torque = vec![S::zero(); joints.len()];
    let mut y_tr_r = Vec::with_capacity(cols.len());
    for (&c, &t) in cols.iter().zip(theta) {
        if c < inertial {
            let (body, k) = (c / PARAMETERS_PER_BODY, c % PARAMETERS_PER_BODY);
            let f = unit_body_force(k, &motions[body]);
            y_tr_r.push(f.power(&w[body]));
            forces[body] = forces[body] + f.scale(t);
        } else {
            let (j, kind) = model.joint_term_of_column(c);
            let e = column_entry(model, kind, j, &qd, &v, &a);
            y_tr_r.push(e * r[j]);
            joint_torque[j] = joint_torque[j] + e * t;
        }
    }
    let mut tau = joint_torque;
    for (i, joint) in joints.iter().enumerate().rev() {
        tau[i] = tau[i] + joint_force(joint, &forces[i]);
        if let Some(p) = joint.parent {
            let up = x[i].force_to_parent(&forces[i]);
            forces[p] = forces[p] + up;
        }
    }
    (project(model, tau), y_tr_r)
}
