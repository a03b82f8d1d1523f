//! Inverse dynamics by the classical Newton–Euler recursion (Luh, Walker & Paul 1980): the
//! forward pass carries each body's angular velocity, angular acceleration and the classical
//! acceleration of its origin; the linear velocity of the origins, which the spatial form
//! carries and then cancels (its classical acceleration is `β + ω × u`), never appears.
//!
//! The child's origin sits at `p` in the parent's coordinates, so its acceleration is the
//! parent's origin's plus `α × p + ω × (ω × p)`, carried to the child as the linear part of a
//! spatial motion; a prismatic joint adds its own acceleration and the Coriolis term
//! `2 ω × S q̇`. The bodies' forces about their origins are the same as the spatial form's, so
//! the backward pass is shared ([`tree_forces`]).

use super::coupling::{expand, project};
use super::joint::joint_motion;
use super::slotine_li::{gravity_vector, tree_forces};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::{Force, JointFrame, Motion, RigidInertia, Vec3};

/// One body's motion in its own frame: angular velocity `ω`, angular acceleration `α` and the
/// classical acceleration of its origin (gravity folded in as an upward acceleration).
#[derive(Clone, Copy)]
pub struct OriginMotion<S> {
    pub omega: Vec3<S>,
    pub alpha: Vec3<S>,
    pub accel: Vec3<S>,
}

/// Inverse dynamics `τ = D q̈ + C q̇ + g` on the coordinates (`Gᵀ` of the tree's at `G q̇`,
/// `G q̈` with mimic joints).
pub fn inverse_dynamics<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    inertias: &[RigidInertia<S>],
    qd: &[S],
    qdd: &[S],
) -> Vec<S> {
    let (qd, qdd) = (expand(model, qd), expand(model, qdd));
    let forces = origin_motions(model, x, &qd, &qdd)
        .iter()
        .zip(inertias)
        .map(|(m, inertia)| m.force(inertia))
        .collect();
    project(model, tree_forces(model, x, forces).0)
}

/// The forward pass at the tree's joint rates `qd` and accelerations `qdd`, gravity on.
pub fn origin_motions<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    qd: &[S],
    qdd: &[S],
) -> Vec<OriginMotion<S>> {
    let base = OriginMotion {
        omega: Vec3::zero(),
        alpha: Vec3::zero(),
        accel: -gravity_vector(model),
    };
    origin_motions_from(model, x, qd, qdd, base)
}

/// [`origin_motions`] with the root joints hanging from a base that moves with `base` (in its
/// own frame, gravity folded into its acceleration): a floating base.
pub fn origin_motions_from<S: Scalar, X: JointFrame<S>>(
    model: &Model,
    x: &[X],
    qd: &[S],
    qdd: &[S],
    base: OriginMotion<S>,
) -> Vec<OriginMotion<S>> {
    let mut motions: Vec<OriginMotion<S>> = Vec::with_capacity(model.joints().len());
    for (i, joint) in model.joints().iter().enumerate() {
        let parent = joint.parent.map_or(base, |p| motions[p]);
        let p = x[i].origin();
        let carried = x[i].motion_to_child(&Motion {
            ang: parent.alpha,
            lin: parent.accel + parent.omega.cross(&parent.omega.cross(&p)),
        });
        // Only the angular part is used: the rest is never emitted.
        let turned = x[i].motion_to_child(&Motion {
            ang: parent.omega,
            lin: Vec3::zero(),
        });
        let (rate, own) = (joint_motion(joint, qd[i]), joint_motion(joint, qdd[i]));
        let omega = turned.ang + rate.ang;
        motions.push(OriginMotion {
            omega,
            alpha: carried.ang + own.ang + omega.cross(&rate.ang),
            accel: carried.lin + own.lin + omega.cross(&rate.lin).scale(S::from_f64(2.0)),
        });
    }
    motions
}

impl<S: Scalar> OriginMotion<S> {
    /// The force about the origin that moves a body of inertia `inertia` so.
    pub fn force(&self, inertia: &RigidInertia<S>) -> Force<S> {
        inertia.origin_force(&self.omega, &self.alpha, &self.accel)
    }
}
