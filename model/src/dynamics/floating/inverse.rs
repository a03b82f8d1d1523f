//! Inverse dynamics, the Slotine–Li torque, gravity, the Coriolis matrix and the regressor with
//! a floating base (see the module docs of `floating` for the base's recursion).
//!
//! With mimic joints the tree runs at the joints' rates `G q̇` and its torques come back as
//! `Gᵀ τ` (`coupling`); the base's six entries are not a tree joint's and pass untouched.

use super::{base_entries, base_motion, FloatingBase};
use crate::dynamics::coupling::{expand, project, project_rows_after};
use crate::dynamics::joint::joint_force;
use crate::dynamics::joint_terms::fill_joint_term_columns_after;
use crate::dynamics::newton_euler::{origin_motions_from, OriginMotion};
use crate::dynamics::slotine_li::{
    body_force, forward_pass_from, gravity_vector, tree_forces, unit_forces, BodyMotion,
};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{Force, JointFrame, Mat3, Motion, RigidInertia, Vec3};
use dyngen_runtime::PARAMETERS_PER_BODY;
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
    let (jqd, jv, ja) = (
        expand(model, &qd[6..]),
        expand(model, &v[6..]),
        expand(model, &a[6..]),
    );
    let motions = forward_pass_from(model, x, &jqd, &jv, &ja, &root);
    let forces = motions
        .iter()
        .zip(inertias)
        .map(|(m, i)| body_force(i, m))
        .collect();
    base_and_joint_forces(model, x, body_force(&base.inertia, &root), forces)
}

/// The base body's motion for the classical Newton–Euler recursion (`newton_euler`): the
/// angular velocity and acceleration of `ν` and `ν̇`, and its origin's classical acceleration
/// `β + ω × u − Rᵀ g` (gravity, world `g` seen in the base frame, as an upward acceleration).
fn base_origin_motion<S: Scalar>(
    rotation: &Mat3<S>,
    qd: &[S],
    qdd: &[S],
    gravity: Vec3<S>,
) -> OriginMotion<S> {
    let (twist, rates) = (base_motion(qd), base_motion(qdd));
    OriginMotion {
        omega: twist.ang,
        alpha: rates.ang,
        accel: rates.lin + twist.ang.cross(&twist.lin) - rotation.tr_mul_vec(&gravity),
    }
}

/// The base's motion and every body's at `ν̇ = 0` in the model's field, as
/// [`floating_inverse_dynamics`] computes them for the bias (`qdd = 0`), operation for
/// operation: a tracer that asks for both gets one set of values.
pub fn floating_motions_at_rest<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    base: &FloatingBase<S>,
    x: &[X],
    qd: &[S],
) -> (OriginMotion<S>, Vec<OriginMotion<S>>) {
    let zero = vec![S::zero(); model.nv()];
    let root = base_origin_motion(&base.pose.rot, qd, &zero, gravity_vector(model));
    let (jqd, jqdd) = (expand(model, &qd[6..]), expand(model, &zero[6..]));
    let motions = origin_motions_from(model, x, &jqd, &jqdd, root);
    (root, motions)
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
    floating_inverse_dynamics_in_field(model, base, gravity_vector(model), x, inertias, qd, qdd)
}

/// [`floating_inverse_dynamics`] in the uniform field `gravity` (in the world's frame) instead of
/// the model's. The derivatives take the base orientation's effect, and the base linear
/// velocity's, through it.
pub fn floating_inverse_dynamics_in_field<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    base: &FloatingBase<S>,
    gravity: Vec3<S>,
    x: &[X],
    inertias: &[RigidInertia<S>],
    qd: &[S],
    qdd: &[S],
) -> Vec<S> {
    let root = base_origin_motion(&base.pose.rot, qd, qdd, gravity);
    let (jqd, jqdd) = (expand(model, &qd[6..]), expand(model, &qdd[6..]));
    let motions = origin_motions_from(model, x, &jqd, &jqdd, root);
    let forces = motions.iter().zip(inertias).map(|(m, i)| m.force(i)).collect();
    base_and_joint_forces(model, x, root.force(&base.inertia), forces)
}

/// The base wrench (the base body's own force `on_base` plus what each root's subtree exerts
/// on it), then the joint torques, from every body's own force.
fn base_and_joint_forces<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    mut on_base: Force<S>,
    forces: Vec<Force<S>>,
) -> Vec<S> {
    let (tau, f) = tree_forces(model, x, forces);
    for (i, joint) in model.joints().iter().enumerate() {
        if joint.parent.is_none() {
            on_base = on_base + x[i].force_to_parent(&f[i]);
        }
    }
    let mut out = base_entries(&on_base).to_vec();
    out.extend(project(model, tau));
    out
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

/// The regressor `Y(q, ν, v, a)` (nv × P) with `Y θ` the Slotine–Li torque: the base body's ten
/// columns first, then each joint's body's, as Pinocchio orders them, then the joint-level
/// columns of the model's chosen kinds (`joint_terms`, on the joint rows).
pub fn floating_regressor<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    rotation: &Mat3<S>,
    x: &[X],
    qd: &[S],
    v: &[S],
    a: &[S],
) -> DMatrix<S> {
    let n = model.joints().len();
    // The spatial forward pass also in torque form: the classical Newton–Euler pass
    // (`newton_euler`) saves a few operations on Solo-12's torque-form regressors but made them
    // slower in both builds (`docs/performance-notes.md`, *What did not help*).
    let root = base_body_motion(rotation, qd, v, a, Some(gravity_vector(model)));
    let (jqd, jv, ja) = (
        expand(model, &qd[6..]),
        expand(model, &v[6..]),
        expand(model, &a[6..]),
    );
    let motions = forward_pass_from(model, x, &jqd, &jv, &ja, &root);
    let (on_base, forces): (_, Vec<_>) = (unit_forces(&root), motions.iter().map(unit_forces).collect());
    let columns = PARAMETERS_PER_BODY + model.parameter_count();
    let mut y = DMatrix::from_element(6 + n, columns, S::zero());
    let set_base_rows = |y: &mut DMatrix<S>, col: usize, entries: [S; 6]| {
        for (r, e) in entries.into_iter().enumerate() {
            y[(r, col)] = e;
        }
    };
    for (k, f) in on_base.iter().enumerate() {
        set_base_rows(&mut y, k, base_entries(f));
    }
    for (i, unit) in forces.iter().enumerate() {
        for (k, mut f) in unit.iter().copied().enumerate() {
            let col = PARAMETERS_PER_BODY * (i + 1) + k;
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
    let mut y = project_rows_after(model, y, 6);
    fill_joint_term_columns_after(model, &mut y, (6, PARAMETERS_PER_BODY), &jqd, &jv, &ja);
    y
}
