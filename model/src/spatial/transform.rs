//! Rigid transforms between a parent frame and a child frame, acting on spatial vectors.

use super::{Force, Mat3, Motion, RigidInertia, Vec3};
use crate::scalar::Scalar;

/// The child frame placed in the parent frame: child axes `rot` (columns, parent coordinates)
/// and child origin `pos` (parent coordinates). A point `p` of the child is `rot·p + pos`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform<S> {
    pub rot: Mat3<S>,
    pub pos: Vec3<S>,
}

impl<S: Copy> Transform<S> {
    /// `f` entry by entry (a transform over another scalar type).
    pub fn map<T>(&self, f: impl Fn(S) -> T) -> Transform<T> {
        Transform {
            rot: self.rot.map(&f),
            pos: self.pos.map(&f),
        }
    }
}

impl<S: Scalar> Transform<S> {
    pub fn identity() -> Self {
        Transform {
            rot: Mat3::identity(),
            pos: Vec3::zero(),
        }
    }

    /// `self ∘ child`: `child` is placed in the frame that `self` places.
    pub fn compose(&self, child: &Transform<S>) -> Transform<S> {
        Transform {
            rot: self.rot * child.rot,
            pos: self.rot.mul_vec(&child.pos) + self.pos,
        }
    }

    pub fn transform_point(&self, p: &Vec3<S>) -> Vec3<S> {
        self.rot.mul_vec(p) + self.pos
    }

    /// A motion given in the parent frame, expressed in the child frame.
    pub fn motion_to_child(&self, m: &Motion<S>) -> Motion<S> {
        Motion {
            ang: self.rot.tr_mul_vec(&m.ang),
            lin: self.rot.tr_mul_vec(&(m.lin - self.pos.cross(&m.ang))),
        }
    }

    /// A force given in the child frame, expressed in the parent frame.
    pub fn force_to_parent(&self, f: &Force<S>) -> Force<S> {
        let lin = self.rot.mul_vec(&f.lin);
        Force {
            ang: self.rot.mul_vec(&f.ang) + self.pos.cross(&lin),
            lin,
        }
    }
}

/// What a recursion over the tree does with a joint's transform: carry a motion to the child
/// and a force to the parent. [`Transform`] is the plain one; the derivatives of the dynamics
/// use one that also knows its derivative along its own joint (`dynamics::seeded_frame`).
pub trait JointFrame<S> {
    fn motion_to_child(&self, m: &Motion<S>) -> Motion<S>;
    fn force_to_parent(&self, f: &Force<S>) -> Force<S>;
    /// The child's origin in the parent's coordinates (what the classical Newton–Euler
    /// recursion needs to carry an origin's acceleration to the child).
    fn origin(&self) -> Vec3<S>;
}

impl<S: Scalar> JointFrame<S> for Transform<S> {
    fn motion_to_child(&self, m: &Motion<S>) -> Motion<S> {
        Transform::motion_to_child(self, m)
    }
    fn force_to_parent(&self, f: &Force<S>) -> Force<S> {
        Transform::force_to_parent(self, f)
    }
    fn origin(&self) -> Vec3<S> {
        self.pos
    }
}

impl<S: Scalar> CompositeFrame<S> for Transform<S> {
    fn inertia_to_parent(&self, i: &RigidInertia<S>) -> RigidInertia<S> {
        i.to_parent(self)
    }
}

/// What the composite-rigid-body recursion also does with a joint's transform: carry a
/// subtree's inertia to the parent.
pub trait CompositeFrame<S>: JointFrame<S> {
    fn inertia_to_parent(&self, i: &RigidInertia<S>) -> RigidInertia<S>;
}

/// A transform kept as two factors applied one after the other, `outer ∘ inner`: a joint's
/// constant placement in its parent (`outer`) and its own motion (`inner`).
///
/// Multiplied out, a placement with a tilted rotation (a vendor's `1.5708` for a quarter turn)
/// enters every entry of the product with the joint's rotation, and every vector and inertia
/// carried through the joint pays for a dense rotation. Kept apart, each factor is applied as
/// the sparse rotation it is: the joint's about its axis, the placement's about its own.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FactoredTransform<S> {
    pub outer: Transform<S>,
    pub inner: Transform<S>,
}

impl<S: Scalar> JointFrame<S> for FactoredTransform<S> {
    fn motion_to_child(&self, m: &Motion<S>) -> Motion<S> {
        self.inner.motion_to_child(&self.outer.motion_to_child(m))
    }
    fn force_to_parent(&self, f: &Force<S>) -> Force<S> {
        self.outer.force_to_parent(&self.inner.force_to_parent(f))
    }
    fn origin(&self) -> Vec3<S> {
        self.outer.transform_point(&self.inner.pos)
    }
}

impl<S: Scalar> CompositeFrame<S> for FactoredTransform<S> {
    fn inertia_to_parent(&self, i: &RigidInertia<S>) -> RigidInertia<S> {
        i.to_parent(&self.inner).to_parent(&self.outer)
    }
}
