//! A joint's transform for forward-mode derivatives along joint coordinates: its value is the
//! plain transform, and its derivative along its own coordinate comes from the motion
//! subspace `S` instead of from the derivatives of its sines and cosines.
//!
//! A joint moves its child frame by `q` along `S`, so `X(q + dq) = (I − dq S×) X(q)`:
//! - `d(X m)/dq = −S × (X m)`: the transformed motion, crossed with the axis;
//! - `d(Xᵀ f)/dq = Xᵀ (S ×* f)`: the force crossed with the axis, then transformed.
//!
//! Both reuse what the recursion computes anyway (`X m`, the force before it is carried), and a
//! cross product with an axis is a few copies and negations, where differentiating the
//! rotation entries (`d cos q = −sin q`, …) cost a multiplication and an addition per entry and
//! built each tangent from single-lane pieces: fewer lane operations and less machine code.

use super::joint::{joint_motion, pose_to_transform};
use crate::model::Model;
use crate::scalar::Scalar;
use crate::scalar_dual::{Dual, Tangent};
use crate::spatial::{Force, JointFrame, Motion, Vec3};

/// One joint's transform on [`Dual`] numbers (in either form, [`Transform`] or
/// [`FactoredTransform`](crate::spatial::FactoredTransform)), with the tangent `seed` of its
/// own coordinate (the unit direction, times the mimic multiplier), or none if the derivative
/// is not taken along it.
#[derive(Clone, Copy, Debug)]
pub struct SeededFrame<S, T, X> {
    x: X,
    axis: Motion<S>,
    /// How fast the child's origin moves in the parent along the joint's coordinate: a
    /// prismatic joint's axis in the parent's coordinates; zero for a revolute joint.
    origin_rate: Vec3<S>,
    seed: Option<T>,
}

/// Every joint's frame at the coordinates `q`, its transform built by `transforms` (one of
/// `joint_transforms`, `joint_factored_transforms`); `seed(c)` is the tangent of coordinate
/// `c` (none: not a direction of this run).
pub fn seeded_frames<S: Scalar, T: Tangent<S>, X>(
    model: &Model,
    q: &[S],
    transforms: impl Fn(&Model, &[Dual<S, T>]) -> Vec<X>,
    seed: impl Fn(usize) -> Option<T>,
) -> Vec<SeededFrame<S, T, X>> {
    let constant: Vec<Dual<S, T>> = q.iter().map(|&x| Dual::constant(x)).collect();
    transforms(model, &constant)
        .into_iter()
        .zip(model.joints())
        .zip(model.coordinate_maps().iter().zip(model.mimics()))
        .map(|((x, joint), (map, mimic))| {
            let multiplier = if mimic.is_some() { map.multiplier } else { 1.0 };
            let axis = joint_motion(joint, S::one());
            SeededFrame {
                x,
                axis,
                origin_rate: pose_to_transform::<S>(&joint.origin).rot.mul_vec(&axis.lin),
                seed: seed(map.coordinate).map(|t| t.scale(S::from_f64(multiplier))),
            }
        })
        .collect()
}

fn values<S: Copy, T: Copy>(v: &Vec3<Dual<S, T>>) -> Vec3<S> {
    Vec3(v.0.map(|d| d.value))
}

/// `v` with `seed · delta` added to its tangent.
fn with_tangent<S: Scalar, T: Tangent<S>>(
    v: &Vec3<Dual<S, T>>,
    seed: T,
    delta: &Vec3<S>,
) -> Vec3<Dual<S, T>> {
    Vec3(std::array::from_fn(|k| Dual {
        value: v.0[k].value,
        tangent: v.0[k].tangent + seed.scale(delta.0[k]),
    }))
}

impl<S: Scalar, T: Tangent<S>, X: JointFrame<Dual<S, T>>> JointFrame<Dual<S, T>> for SeededFrame<S, T, X> {
    fn motion_to_child(&self, m: &Motion<Dual<S, T>>) -> Motion<Dual<S, T>> {
        let y = self.x.motion_to_child(m);
        let Some(seed) = self.seed else { return y };
        let turned = self.axis.cross_motion(&Motion {
            ang: values(&y.ang),
            lin: values(&y.lin),
        });
        let seed = -seed;
        Motion {
            ang: with_tangent(&y.ang, seed, &turned.ang),
            lin: with_tangent(&y.lin, seed, &turned.lin),
        }
    }

    fn force_to_parent(&self, f: &Force<Dual<S, T>>) -> Force<Dual<S, T>> {
        let Some(seed) = self.seed else {
            return self.x.force_to_parent(f);
        };
        let turned = self.axis.cross_force(&Force {
            ang: values(&f.ang),
            lin: values(&f.lin),
        });
        self.x.force_to_parent(&Force {
            ang: with_tangent(&f.ang, seed, &turned.ang),
            lin: with_tangent(&f.lin, seed, &turned.lin),
        })
    }

    /// A prismatic joint moves its child's origin along its axis; a revolute one turns about it.
    fn origin(&self) -> Vec3<Dual<S, T>> {
        let p = self.x.origin();
        match self.seed {
            Some(seed) if self.origin_rate != Vec3::zero() => with_tangent(&p, seed, &self.origin_rate),
            _ => p,
        }
    }
}
