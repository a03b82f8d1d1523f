//! Inverse dynamics, the Slotine–Li torque, gravity, the Coriolis matrix and the regressor with
//! a floating base (see the module docs of `floating` for the base's recursion).

use super::{base_entries, base_motion, FloatingBase};
use crate::dynamics::joint::joint_force;
use crate::dynamics::slotine_li::{
    body_force, forward_pass_from, gravity_vector, tree_forces, unit_body_force, BodyMotion,
};
use crate::model::{Model, PARAMS_PER_BODY};
use crate::scalar::Scalar;
use crate::spatial::{JointFrame, Mat3, Motion, RigidInertia, Vec3};
use nalgebra::DMatrix;

/// The base body's motion: velocity `ν`, reference velocity `ν_r`, reference acceleration
/// `a_r + ν × ν_r` with gravity (world `g`, seen in the base frame) as an upward acceleration.
fn base_body_motion<S: Scalar>(
    rotation: &Mat3<S>,
    qd: &[S],
    v: &[S],
    a: &[S],
    gravity: Option<Vec3<S>>,
) -> BodyMotion<S> {
    let (vel, w) = (base_motion(qd), base_motion(v));
    let mut wdot = base_motion(a) + vel.cross_motion(&w);
    if let Some(g) = gravity {
        wdot = wdot
            - Motion {
                ang: Vec3::zero(),
                lin: rotation.tr_mul_vec(&g),
            };
    }
    BodyMotion { vel, w, wdot }
}

/// `D(q) a + C(q, ν) v + g(q)` with a floating base (`qd`, `v`, `a` of length nv): the base
/// wrench, then the joint torques.
#[allow(clippy::too_many_arguments)]
pub fn floating_slotine_li<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[X],
    inertias: &[RigidInertia<S>],
    qd: &[S],
    v: &[S],
    a: &[S],
    gravity: Option<Vec3<S>>,
) -> Vec<S> {
    let root = base_body_motion(&base.pose.rot, qd, v, a, gravity);
    let motions = forward_pass_from(model, x, &qd[6..], &v[6..], &a[6..], &root);
    let (tau, f) = tree_forces(model, x, inertias, &motions);
    let mut on_base = body_force(&base.inertia, &root);
    for (i, joint) in model.joints().iter().enumerate() {
        if joint.parent.is_none() {
            on_base = on_base + x[i].force_to_parent(&f[i]);
        }
    }
    let mut out = base_entries(&on_base).to_vec();
    out.extend(tau);
    out
}

/// Inverse dynamics `D(q) ν̇ + C(q, ν) ν + g(q)`: the base wrench that produces the base
/// acceleration, then the joint torques.
pub fn floating_inverse_dynamics<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[X],
    inertias: &[RigidInertia<S>],
    qd: &[S],
    qdd: &[S],
) -> Vec<S> {
    let g = gravity_vector(model);
    floating_slotine_li(model, base, x, inertias, qd, qd, qdd, Some(g))
}

/// The generalised gravity `g(q)`: nonzero base rows are the weight of the whole robot.
pub fn floating_gravity<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[X],
    inertias: &[RigidInertia<S>],
) -> Vec<S> {
    let zero = vec![S::zero(); model.nv()];
    floating_inverse_dynamics(model, base, x, inertias, &zero, &zero)
}

/// The regressor `Y(q, ν, v, a)` (nv × 10·(n + 1)) with `Y θ` the Slotine–Li torque: the base
/// body's ten columns first, then each joint's body's, as Pinocchio orders them.
pub fn floating_regressor<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    rotation: &Mat3<S>,
    x: &[X],
    qd: &[S],
    v: &[S],
    a: &[S],
) -> DMatrix<S> {
    let n = model.joints().len();
    let root = base_body_motion(rotation, qd, v, a, Some(gravity_vector(model)));
    let motions = forward_pass_from(model, x, &qd[6..], &v[6..], &a[6..], &root);
    let mut y = DMatrix::from_element(6 + n, PARAMS_PER_BODY * (n + 1), S::zero());
    let set_base_rows = |y: &mut DMatrix<S>, col: usize, entries: [S; 6]| {
        for (r, e) in entries.into_iter().enumerate() {
            y[(r, col)] = e;
        }
    };
    for k in 0..PARAMS_PER_BODY {
        let f = unit_body_force(k, &root);
        set_base_rows(&mut y, k, base_entries(&f));
    }
    for (i, m) in motions.iter().enumerate() {
        for k in 0..PARAMS_PER_BODY {
            let col = PARAMS_PER_BODY * (i + 1) + k;
            let mut f = unit_body_force(k, m);
            let mut j = i;
            y[(6 + j, col)] = joint_force(&model.joints()[j], &f);
            while let Some(p) = model.joints()[j].parent {
                f = x[j].force_to_parent(&f);
                j = p;
                y[(6 + j, col)] = joint_force(&model.joints()[j], &f);
            }
            set_base_rows(&mut y, col, base_entries(&x[j].force_to_parent(&f)));
        }
    }
    y
}
