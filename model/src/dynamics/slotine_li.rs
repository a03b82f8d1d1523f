//! The Slotine–Li recursion (Niemeyer & Slotine 1991, with the body operator of Echeandia &
//! Wensing 2021): `D(q) a + C(q, q̇) v + g(q)` in O(n), with the Christoffel-consistent `C`.
//! Gravity is a special case of it, and so is inverse dynamics (`v = q̇`), which
//! [`super::newton_euler`] computes with fewer operations; its columns at `v = e_j` are those
//! of `C` (computed faster in [`super::coriolis`]).

use super::coupling::{expand, project};
use super::joint::{joint_force, joint_motion};
use super::newton_euler::origin_motions;
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{Force, JointFrame, Motion, RigidInertia, Transform, Vec3};
use dyngen_runtime::PARAMETERS_PER_BODY;

/// Per-body quantities of the forward pass that the torques are linear in.
pub struct BodyMotion<S> {
    /// Real body velocity (from q̇).
    pub vel: Motion<S>,
    /// Reference velocity (from v).
    pub w: Motion<S>,
    /// Reference acceleration (from a and gravity).
    pub wdot: Motion<S>,
}

/// Forward pass: the velocities and reference accelerations of every body, in body frames.
/// `gravity: None` leaves gravity out (for `C` and `D` alone).
pub fn forward_pass<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    qd: &[S],
    v: &[S],
    a: &[S],
    gravity: Option<Vec3<S>>,
) -> Vec<BodyMotion<S>> {
    // Gravity enters as an upward acceleration of the base (Featherstone's trick).
    let base = Motion {
        ang: Vec3::zero(),
        lin: gravity.map_or(Vec3::zero(), |g| -g),
    };
    let world = BodyMotion {
        vel: Motion::zero(),
        w: Motion::zero(),
        wdot: base,
    };
    forward_pass_from(model, x, qd, v, a, &world)
}

/// [`forward_pass`] with the root joints hanging from a base that moves with `root` (in the
/// base's frame, gravity folded into its reference acceleration): a floating base.
pub fn forward_pass_from<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    qd: &[S],
    v: &[S],
    a: &[S],
    root: &BodyMotion<S>,
) -> Vec<BodyMotion<S>> {
    let mut out: Vec<BodyMotion<S>> = Vec::with_capacity(model.joints().len());
    for (i, joint) in model.joints().iter().enumerate() {
        let (vel0, w0, wdot0) = match joint.parent {
            Some(p) => (out[p].vel, out[p].w, out[p].wdot),
            None => (root.vel, root.w, root.wdot),
        };
        let vel = x[i].motion_to_child(&vel0) + joint_motion(joint, qd[i]);
        let sv = joint_motion(joint, v[i]);
        let w = x[i].motion_to_child(&w0) + sv;
        // Ṡ v with Ṡ = vel × S: the derivative of the joint's motion subspace seen from the base.
        let wdot = x[i].motion_to_child(&wdot0) + joint_motion(joint, a[i]) + vel.cross_motion(&sv);
        out.push(BodyMotion { vel, w, wdot });
    }
    out
}

/// The body force `I ẇ + B(I, vel) w`, linear in the inertia.
pub fn body_force<S: Scalar>(inertia: &RigidInertia<S>, m: &BodyMotion<S>) -> Force<S> {
    if m.w == m.vel {
        // `B(I, v) v = v ×* I v` (as `crm(v) v = 0`): the classical RNEA term, about half the
        // operations. Symbolically the two velocities are the same nodes exactly when `v = q̇`
        // (inverse dynamics), a cancellation the simplifier cannot see on its own.
        inertia.mul_motion(&m.wdot) + m.vel.cross_force(&inertia.mul_motion(&m.vel))
    } else {
        inertia.body_force(&m.vel, &m.w, &m.wdot)
    }
}

/// [`body_force`] of the unit inertia of parameter `k`: regressor column `k` of the body.
/// Always in the expanded form: with one parameter set, the Newton–Euler definition's
/// cancelling pairs are most of its terms (torque-form regressors 6–7% fewer operations),
/// while for a body's whole inertia the definition's shared `I v` makes it as cheap.
pub fn unit_body_force<S: Scalar>(k: usize, m: &BodyMotion<S>) -> Force<S> {
    let unit = RigidInertia::unit(k);
    if m.w == m.vel {
        unit.newton_euler_force(&m.vel, &m.wdot)
    } else {
        unit.body_force(&m.vel, &m.w, &m.wdot)
    }
}

/// A body's forces with each of its ten unit inertias: column `k` of its regressor block
/// before it is carried up the tree.
pub type UnitForces<S> = [Force<S>; PARAMETERS_PER_BODY];

/// Every body's [`UnitForces`] at the tree's rates, gravity on: by the Slotine–Li pass
/// ([`unit_body_force`]), or in torque form (`v` the same nodes as `q̇`) by the classical
/// Newton–Euler pass, which never forms the origins' linear velocities (`newton_euler`).
pub fn unit_body_forces<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    qd: &[S],
    v: &[S],
    a: &[S],
) -> Vec<UnitForces<S>> {
    if qd == v {
        let motions = origin_motions(model, x, qd, a);
        return motions
            .iter()
            .map(|m| std::array::from_fn(|k| m.force(&RigidInertia::unit(k))))
            .collect();
    }
    forward_pass(model, x, qd, v, a, Some(gravity_vector(model)))
        .iter()
        .map(unit_forces)
        .collect()
}

/// One body's [`UnitForces`] in motion `m`, by the Slotine–Li pass ([`unit_body_force`]).
pub fn unit_forces<S: Scalar>(m: &BodyMotion<S>) -> UnitForces<S> {
    std::array::from_fn(|k| unit_body_force(k, m))
}

/// `D(q) a + C(q, q̇) v + g(q)` (gravity optional): the Slotine–Li reference torque, on the
/// coordinates (`Gᵀ` of the tree's at `G q̇, G v, G a` with mimic joints).
pub fn slotine_li<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
    qd: &[S],
    v: &[S],
    a: &[S],
    gravity: Option<Vec3<S>>,
) -> Vec<S> {
    let (qd, v, a) = (expand(model, qd), expand(model, v), expand(model, a));
    project(model, tree_slotine_li(model, x, inertias, &qd, &v, &a, gravity))
}

/// The Slotine–Li torque of every moving joint of the tree, rates per moving joint.
fn tree_slotine_li<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
    qd: &[S],
    v: &[S],
    a: &[S],
    gravity: Option<Vec3<S>>,
) -> Vec<S> {
    let motions = forward_pass(model, x, qd, v, a, gravity);
    let forces = motions
        .iter()
        .zip(inertias)
        .map(|(m, i)| body_force(i, m))
        .collect();
    tree_forces(model, x, forces).0
}

/// The backward pass from every body's own force `f` (in its frame): every tree joint's
/// torque, and the force each body's subtree exerts on its joint (in the body's frame; a
/// root's is what a floating base feels from it).
pub fn tree_forces<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    mut f: Vec<Force<S>>,
) -> (Vec<S>, Vec<Force<S>>) {
    let mut tau = vec![S::zero(); model.joints().len()];
    for (i, joint) in model.joints().iter().enumerate().rev() {
        tau[i] = joint_force(joint, &f[i]);
        if let Some(p) = joint.parent {
            let up = x[i].force_to_parent(&f[i]);
            f[p] = f[p] + up;
        }
    }
    (tau, f)
}

pub fn gravity_vector<S: Scalar>(model: &Model) -> Vec3<S> {
    Vec3::from_f64([model.gravity().x, model.gravity().y, model.gravity().z])
}

/// Generalized gravity `g(q)`.
pub fn gravity_torque<S: Scalar>(model: &Model, x: &[Transform<S>], inertias: &[RigidInertia<S>]) -> Vec<S> {
    let zero = vec![S::zero(); model.dof()];
    slotine_li(
        model,
        x,
        inertias,
        &zero,
        &zero,
        &zero,
        Some(gravity_vector(model)),
    )
}
