//! Minimal 3-D and spatial (6-D) algebra over any [`Scalar`].
//!
//! Hand-written rather than nalgebra so that every arithmetic operation is explicit: run on
//! symbolic values, each one becomes a node of the expression graph, and constants that are
//! 0 or ±1 (fixed geometry) vanish there. Spatial vectors use Featherstone's order,
//! angular part first.

mod inertia;
mod transform;
mod vec3;

pub use inertia::RigidInertia;
pub use transform::{CompositeFrame, FactoredTransform, JointFrame, Transform};
pub use vec3::{Mat3, Vec3};

use crate::scalar::Scalar;
use std::ops::{Add, Neg, Sub};

/// A spatial motion vector (velocity, acceleration): `[ω; v]`, `v` at the frame origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Motion<S> {
    pub ang: Vec3<S>,
    pub lin: Vec3<S>,
}

/// A spatial force vector: `[n; f]`, moment `n` about the frame origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Force<S> {
    pub ang: Vec3<S>,
    pub lin: Vec3<S>,
}

impl<S: Copy> Motion<S> {
    /// `f` entry by entry (a motion over another scalar type).
    pub fn map<T>(&self, f: impl Fn(S) -> T) -> Motion<T> {
        Motion {
            ang: self.ang.map(&f),
            lin: self.lin.map(&f),
        }
    }
}

impl<S: Copy> Force<S> {
    /// `f` entry by entry (a force over another scalar type).
    pub fn map<T>(&self, f: impl Fn(S) -> T) -> Force<T> {
        Force {
            ang: self.ang.map(&f),
            lin: self.lin.map(&f),
        }
    }
}

impl<S: Scalar> Motion<S> {
    pub fn zero() -> Self {
        Motion {
            ang: Vec3::zero(),
            lin: Vec3::zero(),
        }
    }
    pub fn scale(&self, k: S) -> Self {
        Motion {
            ang: self.ang.scale(k),
            lin: self.lin.scale(k),
        }
    }
    /// Motion cross product `self × m` (Featherstone's `crm(self) m`).
    pub fn cross_motion(&self, m: &Motion<S>) -> Motion<S> {
        Motion {
            ang: self.ang.cross(&m.ang),
            lin: self.ang.cross(&m.lin) + self.lin.cross(&m.ang),
        }
    }
    /// Force cross product `self ×* f` (Featherstone's `crf(self) f`).
    pub fn cross_force(&self, f: &Force<S>) -> Force<S> {
        Force {
            ang: self.ang.cross(&f.ang) + self.lin.cross(&f.lin),
            lin: self.ang.cross(&f.lin),
        }
    }
}

impl<S: Scalar> Force<S> {
    pub fn zero() -> Self {
        Force {
            ang: Vec3::zero(),
            lin: Vec3::zero(),
        }
    }
    pub fn scale(&self, k: S) -> Self {
        Force {
            ang: self.ang.scale(k),
            lin: self.lin.scale(k),
        }
    }
    /// The power `mᵀ f` of this force on a motion.
    pub fn power(&self, m: &Motion<S>) -> S {
        self.ang.dot(&m.ang) + self.lin.dot(&m.lin)
    }
}

macro_rules! spatial_ops {
    ($t:ident) => {
        impl<S: Scalar> Add for $t<S> {
            type Output = Self;
            fn add(self, o: Self) -> Self {
                $t {
                    ang: self.ang + o.ang,
                    lin: self.lin + o.lin,
                }
            }
        }
        impl<S: Scalar> Sub for $t<S> {
            type Output = Self;
            fn sub(self, o: Self) -> Self {
                $t {
                    ang: self.ang - o.ang,
                    lin: self.lin - o.lin,
                }
            }
        }
        impl<S: Scalar> Neg for $t<S> {
            type Output = Self;
            fn neg(self) -> Self {
                $t {
                    ang: -self.ang,
                    lin: -self.lin,
                }
            }
        }
    };
}
spatial_ops!(Motion);
spatial_ops!(Force);
