//! World poses of the bodies and a frame's Jacobian and its time derivative with a floating
//! base: the base columns first, then the tree's.
//!
//! A unit base velocity `e_k` moves the world like a prismatic joint along the base's `k`-th
//! axis (`k < 3`) or a revolute joint about its `k − 3`-th axis through the base origin, and
//! those axes turn with the base: so the base columns are those joints' columns, and their
//! derivatives those joints' derivatives with the base's own angular velocity. With mimic joints
//! the tree's columns are carried through `G` (`J G`, `J̇(G q̇) G`: `coupling`).

use super::base_motion;
use crate::dynamics::coupling::{expand, project_columns};
use crate::dynamics::kinematics::{frame_pose, set_column, tree_jacobian, tree_jacobian_dot, MovingBase};
use crate::model::{Frame, Model};
use crate::scalar::Scalar;
use crate::spatial::{Transform, Vec3};
use nalgebra::DMatrix;

/// Each body's frame in the world, the roots placed on the base.
pub fn floating_body_poses<S: Scalar>(
    model: &Model,
    base: &Transform<S>,
    x: &[Transform<S>],
) -> Vec<Transform<S>> {
    let mut world: Vec<Transform<S>> = Vec::with_capacity(model.joints().len());
    for (i, joint) in model.joints().iter().enumerate() {
        let parent = match joint.parent {
            Some(p) => world[p],
            None => *base,
        };
        world.push(parent.compose(&x[i]));
    }
    world
}

/// The Jacobian (6 × nv, rows `[linear; angular]`, world axes at the frame origin: Pinocchio's
/// `LOCAL_WORLD_ALIGNED`) of `frame`, `world` from [`floating_body_poses`].
pub fn floating_frame_jacobian<S: Scalar>(
    model: &Model,
    base: &Transform<S>,
    world: &[Transform<S>],
    frame: &Frame,
) -> DMatrix<S> {
    let pe = frame_pose(Some(base), world, frame).pos;
    let tree = project_columns(model, tree_jacobian(model, world, frame, pe));
    let mut jac = DMatrix::from_element(6, 6 + tree.ncols(), S::zero());
    for k in 0..3 {
        let axis = base.rot.column(k);
        set_column(&mut jac, k, axis, Vec3::zero());
        set_column(&mut jac, 3 + k, axis.cross(&(pe - base.pos)), axis);
    }
    jac.columns_mut(6, tree.ncols()).copy_from(&tree);
    jac
}

/// `J̇` of [`floating_frame_jacobian`] along the velocity `v` (nv entries).
pub fn floating_frame_jacobian_dot<S: Scalar>(
    model: &Model,
    base: &Transform<S>,
    world: &[Transform<S>],
    v: &[S],
    frame: &Frame,
) -> DMatrix<S> {
    let nu = base_motion(v);
    let moving = MovingBase {
        omega: base.rot.mul_vec(&nu.ang),
        origin_velocity: base.rot.mul_vec(&nu.lin),
        origin: base.pos,
    };
    let pe = frame_pose(Some(base), world, frame).pos;
    let joint_rates = expand(model, &v[6..]);
    let tree = project_columns(
        model,
        tree_jacobian_dot(model, world, &joint_rates, frame, pe, Some(&moving)),
    );
    let jac = floating_frame_jacobian(model, base, world, frame);
    let pe_dot = Vec3(std::array::from_fn(|r| {
        (1..v.len()).fold(jac[(r, 0)] * v[0], |acc, c| acc + jac[(r, c)] * v[c])
    }));
    let mut jd = DMatrix::from_element(6, 6 + tree.ncols(), S::zero());
    for k in 0..3 {
        let axis = base.rot.column(k);
        let turning = moving.omega.cross(&axis);
        set_column(&mut jd, k, turning, Vec3::zero());
        let lin = turning.cross(&(pe - base.pos)) + axis.cross(&(pe_dot - moving.origin_velocity));
        set_column(&mut jd, 3 + k, lin, turning);
    }
    jd.columns_mut(6, tree.ncols()).copy_from(&tree);
    jd
}
