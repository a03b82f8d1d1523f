//! World poses of the bodies and of any frame, a frame's geometric Jacobian and its derivative
//! (the end-effector's by default).

use super::coupling::{expand, project_columns};
use super::joint::pose_to_transform;
use crate::model::{Frame, JointKind, Model};
use crate::scalar::Scalar;
use crate::spatial::{Transform, Vec3};
use nalgebra::DMatrix;

/// Each body's frame in the base frame.
pub fn body_poses<S: Scalar>(model: &Model, x: &[Transform<S>]) -> Vec<Transform<S>> {
    let mut world: Vec<Transform<S>> = Vec::with_capacity(model.joints().len());
    for (i, joint) in model.joints().iter().enumerate() {
        let pose = match joint.parent {
            Some(p) => world[p].compose(&x[i]),
            None => x[i],
        };
        world.push(pose);
    }
    world
}

/// The end-effector frame in the base frame.
pub fn end_effector_pose<S: Scalar>(model: &Model, world: &[Transform<S>]) -> Transform<S> {
    frame_pose(None, world, model.end_effector())
}

/// A frame in the base frame; on a floating base in the world, `base` the base body's pose
/// (only a floating base carries frames itself).
pub fn frame_pose<S: Scalar>(
    base: Option<&Transform<S>>,
    world: &[Transform<S>],
    frame: &Frame,
) -> Transform<S> {
    let body = match (frame.parent, base) {
        (Some(p), _) => &world[p],
        (None, Some(base)) => base,
        (None, None) => unreachable!("Model::new refuses a frame on a fixed base"),
    };
    body.compose(&pose_to_transform(&frame.placement))
}

/// Unit axis of joint `j` in world coordinates.
fn world_axis<S: Scalar>(model: &Model, world: &[Transform<S>], j: usize) -> Vec3<S> {
    let a = model.joints()[j].axis;
    world[j].rot.mul_vec(&Vec3::from_f64([a.x, a.y, a.z]))
}

/// Column `j` of a 6-row Jacobian: `[lin; ang]`.
pub(super) fn set_column<S: Scalar>(m: &mut DMatrix<S>, j: usize, lin: Vec3<S>, ang: Vec3<S>) {
    for r in 0..3 {
        m[(r, j)] = lin.0[r];
        m[(r + 3, j)] = ang.0[r];
    }
}

/// Geometric Jacobian (6×n) of the end-effector frame origin: rows `[v; ω]` in world axes;
/// `J_tree G` with mimic joints.
pub fn jacobian<S: Scalar>(model: &Model, world: &[Transform<S>]) -> DMatrix<S> {
    frame_jacobian(model, world, model.end_effector())
}

/// [`jacobian`] of any frame (Pinocchio's `LOCAL_WORLD_ALIGNED`).
pub fn frame_jacobian<S: Scalar>(model: &Model, world: &[Transform<S>], frame: &Frame) -> DMatrix<S> {
    let origin = frame_pose(None, world, frame).pos;
    project_columns(model, tree_jacobian(model, world, frame, origin))
}

/// The joints that move `frame`, base first (none for a frame on a floating base body).
fn chain_of(model: &Model, frame: &Frame) -> Vec<usize> {
    frame.parent.map_or_else(Vec::new, |body| model.chain_to(body))
}

/// The Jacobian with one column per moving joint of the tree; `pe` the frame's origin.
pub fn tree_jacobian<S: Scalar>(
    model: &Model,
    world: &[Transform<S>],
    frame: &Frame,
    pe: Vec3<S>,
) -> DMatrix<S> {
    let n = model.joints().len();
    let mut jac = DMatrix::from_element(6, n, S::zero());
    for j in chain_of(model, frame) {
        let z = world_axis(model, world, j);
        match model.joints()[j].kind {
            JointKind::Revolute => set_column(&mut jac, j, z.cross(&(pe - world[j].pos)), z),
            JointKind::Prismatic => set_column(&mut jac, j, z, Vec3::zero()),
        }
    }
    jac
}

/// Time derivative `J̇(q, q̇)` of [`jacobian`].
///
/// A joint axis fixed in body `j` turns at that body's angular velocity: `ż = ω_j × z`; the
/// lever arm `p_e − p_j` changes at the difference of the two points' velocities.
///
/// With mimic joints, `J̇_tree(G q̇) G` (`G` is constant).
pub fn jacobian_dot<S: Scalar>(model: &Model, world: &[Transform<S>], qd: &[S]) -> DMatrix<S> {
    frame_jacobian_dot(model, world, qd, model.end_effector())
}

/// [`jacobian_dot`] of any frame.
pub fn frame_jacobian_dot<S: Scalar>(
    model: &Model,
    world: &[Transform<S>],
    qd: &[S],
    frame: &Frame,
) -> DMatrix<S> {
    let origin = frame_pose(None, world, frame).pos;
    project_columns(
        model,
        tree_jacobian_dot(model, world, &expand(model, qd), frame, origin, None),
    )
}

/// The motion of a floating base, for the kinematics of the tree it carries: its angular
/// velocity and origin velocity in world axes, and its origin.
#[derive(Clone, Copy, Debug)]
pub struct MovingBase<S> {
    pub omega: Vec3<S>,
    pub origin_velocity: Vec3<S>,
    pub origin: Vec3<S>,
}

/// `J̇` with one column per moving joint of the tree, `qd` one rate per moving joint, `pe` the
/// frame's origin; the roots hang from a fixed base (`None`) or from a moving one.
pub fn tree_jacobian_dot<S: Scalar>(
    model: &Model,
    world: &[Transform<S>],
    qd: &[S],
    frame: &Frame,
    pe: Vec3<S>,
    base: Option<&MovingBase<S>>,
) -> DMatrix<S> {
    let n = model.joints().len();
    let Some(last) = frame.parent else {
        return DMatrix::from_element(6, n, S::zero());
    };
    let chain = model.chain_to(last);
    // World angular velocity and origin velocity of every body on the chain.
    let mut omega = vec![Vec3::zero(); n];
    let mut pdot = vec![Vec3::zero(); n];
    for &i in &chain {
        let (w0, v0) = match model.joints()[i].parent {
            Some(p) => (omega[p], pdot[p] + omega[p].cross(&(world[i].pos - world[p].pos))),
            None => match base {
                None => (Vec3::zero(), Vec3::zero()),
                Some(b) => (
                    b.omega,
                    b.origin_velocity + b.omega.cross(&(world[i].pos - b.origin)),
                ),
            },
        };
        let z = world_axis(model, world, i).scale(qd[i]);
        (omega[i], pdot[i]) = match model.joints()[i].kind {
            JointKind::Revolute => (w0 + z, v0),
            JointKind::Prismatic => (w0, v0 + z),
        };
    }
    let pe_dot = pdot[last] + omega[last].cross(&(pe - world[last].pos));
    let mut jd = DMatrix::from_element(6, n, S::zero());
    for &j in &chain {
        let z = world_axis(model, world, j);
        let zd = omega[j].cross(&z);
        match model.joints()[j].kind {
            JointKind::Revolute => {
                let lin = zd.cross(&(pe - world[j].pos)) + z.cross(&(pe_dot - pdot[j]));
                set_column(&mut jd, j, lin, zd)
            }
            JointKind::Prismatic => set_column(&mut jd, j, zd, Vec3::zero()),
        }
    }
    jd
}
