//! A frame's Jacobian, its time derivative, velocity and classical acceleration in each of the
//! three reference frames, from its pose and its Jacobian at its origin in base axes.
//!
//! With `J = [J_v; J_ω]` of the frame origin `p` in base axes (`LOCAL_WORLD_ALIGNED`), `R` the
//! frame's rotation, `ṗ = J_v q̇` and `ω = J_ω q̇`:
//! - world (a spatial velocity, at the base origin): `[J_v + p × J_ω; J_ω]`, whose derivative
//!   is `[J̇_v + ṗ × J_ω + p × J̇_ω; J̇_ω]`;
//! - local (in the frame's axes): `[Rᵀ J_v; Rᵀ J_ω]`, whose derivative is `Rᵀ (J̇ − ω × J)`
//!   on each half (since `d(Rᵀ)/dt x = −Rᵀ (ω × x)`).
//!
//! Each `J̇` is the time derivative of the `J` in the same convention, as Pinocchio's
//! `getFrameJacobianTimeVariation` returns it.
//!
//! Some quantities also have a second formulation, with the same values and other operation
//! counts, between which the tracer keeps the cheaper per robot and frame: the local `J`
//! carried back from the frame to each joint ([`local_jacobian`]) rather than turned from base
//! axes, and velocity and acceleration from the forward recursion of body velocities and
//! accelerations ([`FrameRates`]) rather than from `J` and `J̇`. The classical acceleration adds `ω × v` to the
//! linear part of the spatial acceleration `J q̈ + J̇ q̇`; at the frame origin in base axes that
//! sum is the origin's acceleration `p̈` already, so nothing is added there.

use super::coupling::{expand, project_columns};
use super::joint::pose_to_transform;
use super::kinematics::{frame_jacobian, frame_jacobian_dot, frame_pose, set_column};
use super::slotine_li::forward_pass;
use crate::model::{Frame, JointKind, Model};
use crate::scalar::Scalar;
use crate::spatial::{Motion, Transform, Vec3};
use dyngen_runtime::ReferenceFrame;
use nalgebra::DMatrix;

/// What every frame quantity is computed from: the pose, and `J`, `J̇` at the origin in base
/// axes.
pub struct FrameMotion<S> {
    pub pose: Transform<S>,
    pub jacobian: DMatrix<S>,
    pub jacobian_dot: DMatrix<S>,
}

impl<S: Scalar> FrameMotion<S> {
    pub fn new(model: &Model, world: &[Transform<S>], qd: &[S], frame: &Frame) -> Self {
        FrameMotion {
            pose: frame_pose(None, world, frame),
            jacobian: frame_jacobian(model, world, frame),
            jacobian_dot: frame_jacobian_dot(model, world, qd, frame),
        }
    }

    /// `J` in `reference`.
    pub fn jacobian_in(&self, reference: ReferenceFrame) -> DMatrix<S> {
        let (p, r) = (&self.pose.pos, &self.pose.rot);
        map_columns(&self.jacobian, |v, w| match reference {
            ReferenceFrame::LocalWorldAligned => (v, w),
            ReferenceFrame::World => (v + p.cross(&w), w),
            ReferenceFrame::Local => (r.tr_mul_vec(&v), r.tr_mul_vec(&w)),
        })
    }

    /// `J̇` in `reference`: the time derivative of [`FrameMotion::jacobian_in`].
    pub fn jacobian_dot_in(&self, reference: ReferenceFrame, qd: &[S]) -> DMatrix<S> {
        let (p, r) = (&self.pose.pos, &self.pose.rot);
        let (p_dot, omega) = halves(&times(&self.jacobian, qd));
        let n = self.jacobian.ncols();
        let mut out = DMatrix::from_element(6, n, S::zero());
        for c in 0..n {
            let (v, w) = column(&self.jacobian, c);
            let (vd, wd) = column(&self.jacobian_dot, c);
            let (lin, ang) = match reference {
                ReferenceFrame::LocalWorldAligned => (vd, wd),
                ReferenceFrame::World => (vd + p_dot.cross(&w) + p.cross(&wd), wd),
                ReferenceFrame::Local => (
                    r.tr_mul_vec(&(vd - omega.cross(&v))),
                    r.tr_mul_vec(&(wd - omega.cross(&w))),
                ),
            };
            set_column(&mut out, c, lin, ang);
        }
        out
    }

    /// The frame's velocity `J q̇` in `reference`.
    pub fn velocity_in(&self, reference: ReferenceFrame, qd: &[S]) -> [S; 6] {
        times(&self.jacobian_in(reference), qd)
    }

    /// The classical acceleration in `reference` (see the module docs).
    pub fn classical_acceleration_in(&self, reference: ReferenceFrame, qd: &[S], qdd: &[S]) -> [S; 6] {
        let a = times(&self.jacobian_in(reference), qdd);
        let b = times(&self.jacobian_dot_in(reference, qd), qd);
        let mut out: [S; 6] = std::array::from_fn(|k| a[k] + b[k]);
        if reference != ReferenceFrame::LocalWorldAligned {
            let (v, w) = halves(&self.velocity_in(reference, qd));
            let extra = w.cross(&v);
            for (o, e) in out.iter_mut().zip(extra.0) {
                *o = *o + e;
            }
        }
        out
    }
}

/// `J` in the frame's own axes, column by column from the frame carried back to each joint on
/// its chain: with the frame's axes `R` and origin `r` in joint `j`'s frame and the joint's axis
/// `a` there, the column is `[Rᵀ (a × r); Rᵀ a]` (revolute) or `[Rᵀ a; 0]` (prismatic).
pub fn local_jacobian<S: Scalar>(model: &Model, x: &[Transform<S>], frame: &Frame) -> DMatrix<S> {
    let mut jac = DMatrix::from_element(6, model.joints().len(), S::zero());
    let mut placed: Transform<S> = pose_to_transform(&frame.placement);
    let mut next = frame.parent;
    while let Some(j) = next {
        let joint = &model.joints()[j];
        let a = Vec3::from_f64([joint.axis.x, joint.axis.y, joint.axis.z]);
        let (lin, ang) = match joint.kind {
            JointKind::Revolute => (
                placed.rot.tr_mul_vec(&a.cross(&placed.pos)),
                placed.rot.tr_mul_vec(&a),
            ),
            JointKind::Prismatic => (placed.rot.tr_mul_vec(&a), Vec3::zero()),
        };
        set_column(&mut jac, j, lin, ang);
        placed = x[j].compose(&placed);
        next = joint.parent;
    }
    project_columns(model, jac)
}

/// A frame's velocity and spatial acceleration in its own axes (Featherstone's `[ω; v]`, `v`
/// at the frame's origin), from the forward recursion over the bodies above it.
pub struct FrameRates<S> {
    pub velocity: Motion<S>,
    pub acceleration: Motion<S>,
}

impl<S: Scalar> FrameRates<S> {
    pub fn new(model: &Model, x: &[Transform<S>], qd: &[S], qdd: &[S], frame: &Frame) -> Self {
        let (qd, qdd) = (expand(model, qd), expand(model, qdd));
        let carrier = frame.parent.expect("Model::new refuses a frame on a fixed base");
        let body = &forward_pass(model, x, &qd, &qd, &qdd, None)[carrier];
        let placement: Transform<S> = pose_to_transform(&frame.placement);
        FrameRates {
            velocity: placement.motion_to_child(&body.vel),
            acceleration: placement.motion_to_child(&body.wdot),
        }
    }

    /// The velocity in `reference`, `[linear; angular]`; `pose` is the frame's.
    pub fn velocity_in(&self, reference: ReferenceFrame, pose: &Transform<S>) -> [S; 6] {
        let (v, w) = (self.velocity.lin, self.velocity.ang);
        let (r, p) = (&pose.rot, &pose.pos);
        match reference {
            ReferenceFrame::Local => join(v, w),
            ReferenceFrame::LocalWorldAligned => join(r.mul_vec(&v), r.mul_vec(&w)),
            ReferenceFrame::World => {
                let w = r.mul_vec(&w);
                join(r.mul_vec(&v) + p.cross(&w), w)
            }
        }
    }

    /// The classical acceleration in `reference` (see the module docs).
    pub fn classical_acceleration_in(&self, reference: ReferenceFrame, pose: &Transform<S>) -> [S; 6] {
        let (v, w) = (self.velocity.lin, self.velocity.ang);
        // The origin's acceleration and the angular one, in the frame's axes.
        let (lin, ang) = (self.acceleration.lin + w.cross(&v), self.acceleration.ang);
        let (r, p) = (&pose.rot, &pose.pos);
        match reference {
            ReferenceFrame::Local => join(lin, ang),
            ReferenceFrame::LocalWorldAligned => join(r.mul_vec(&lin), r.mul_vec(&ang)),
            ReferenceFrame::World => {
                // The body point at the base origin: p̈ + p × ω̇ + ω × (p × ω).
                let (p_ddot, w_dot, w) = (r.mul_vec(&lin), r.mul_vec(&ang), r.mul_vec(&w));
                join(p_ddot + p.cross(&w_dot) + w.cross(&p.cross(&w)), w_dot)
            }
        }
    }
}

fn join<S: Scalar>(lin: Vec3<S>, ang: Vec3<S>) -> [S; 6] {
    [lin.0[0], lin.0[1], lin.0[2], ang.0[0], ang.0[1], ang.0[2]]
}

/// `m x` for a 6×n matrix.
fn times<S: Scalar>(m: &DMatrix<S>, x: &[S]) -> [S; 6] {
    std::array::from_fn(|r| {
        let mut sum = S::zero();
        for (c, xc) in x.iter().enumerate() {
            sum = sum + m[(r, c)] * *xc;
        }
        sum
    })
}

fn halves<S: Scalar>(x: &[S; 6]) -> (Vec3<S>, Vec3<S>) {
    (Vec3([x[0], x[1], x[2]]), Vec3([x[3], x[4], x[5]]))
}

fn column<S: Scalar>(m: &DMatrix<S>, c: usize) -> (Vec3<S>, Vec3<S>) {
    (
        Vec3([m[(0, c)], m[(1, c)], m[(2, c)]]),
        Vec3([m[(3, c)], m[(4, c)], m[(5, c)]]),
    )
}

fn map_columns<S: Scalar>(m: &DMatrix<S>, f: impl Fn(Vec3<S>, Vec3<S>) -> (Vec3<S>, Vec3<S>)) -> DMatrix<S> {
    let mut out = DMatrix::from_element(6, m.ncols(), S::zero());
    for c in 0..m.ncols() {
        let (v, w) = column(m, c);
        let (lin, ang) = f(v, w);
        set_column(&mut out, c, lin, ang);
    }
    out
}
