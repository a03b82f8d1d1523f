//! Joint transforms and motion subspaces: where the joint variables enter.

use crate::model::{exact_sin_cos, CoordinateMap, Joint, JointKind, Model, Pose};
use crate::scalar::Scalar;
use crate::spatial::{FactoredTransform, Force, Mat3, Motion, Transform, Vec3};

pub(crate) fn pose_to_transform<S: Scalar>(p: &Pose) -> Transform<S> {
    let r = &p.rotation;
    Transform {
        rot: Mat3::from_f64(std::array::from_fn(|i| std::array::from_fn(|j| r[(i, j)]))),
        pos: Vec3::from_f64([p.translation.x, p.translation.y, p.translation.z]),
    }
}

fn axis<S: Scalar>(joint: &Joint) -> Vec3<S> {
    Vec3::from_f64([joint.axis.x, joint.axis.y, joint.axis.z])
}

/// Rotation by the angle with sine `s` and cosine `c` about the unit axis `a`, written as
/// `a aᵀ + c (1 − a aᵀ) + s [a]×` so that a coordinate axis folds to the textbook
/// elementary rotation (no `c + (1 − c)` left for the simplifier to find).
fn axis_rotation<S: Scalar>(a: [f64; 3], s: S, c: S) -> Mat3<S> {
    let k = |x: f64| S::from_f64(x);
    let skew = [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
    Mat3(std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let aa = a[i] * a[j];
            let delta = if i == j { 1.0 } else { 0.0 };
            k(aa) + c * k(delta - aa) + s * k(skew[i][j])
        })
    }))
}

/// The child frame of `joint` in its parent frame at position `q`.
pub fn joint_transform<S: Scalar>(joint: &Joint, q: S) -> Transform<S> {
    let origin = pose_to_transform::<S>(&joint.origin);
    match joint.kind {
        JointKind::Revolute => {
            let a = [joint.axis.x, joint.axis.y, joint.axis.z];
            Transform {
                rot: origin.rot * axis_rotation(a, q.sin(), q.cos()),
                pos: origin.pos,
            }
        }
        JointKind::Prismatic => Transform {
            rot: origin.rot,
            pos: origin.pos + origin.rot.mul_vec(&axis::<S>(joint).scale(q)),
        },
    }
}

/// A mimic joint's transform from its master's position `q`: `q_j = m·q + o`.
///
/// With `m = ±1` a revolute joint's sine and cosine come from those of `q` by the angle-sum
/// identities (`sin(±q + o) = ±sin q cos o + cos q sin o`, `cos(±q + o) = cos q cos o ∓ sin q sin o`),
/// so generated code reuses the master's precomputed `JointTrig` entries and takes no new
/// sine; any other multiplier takes `sin(m·q + o)` and `cos(m·q + o)` of its own.
fn mimic_transform<S: Scalar>(joint: &Joint, q: S, map: &CoordinateMap) -> Transform<S> {
    let (m, o) = (map.multiplier, map.offset);
    let k = |x: f64| S::from_f64(x);
    if joint.kind == JointKind::Revolute && m.abs() == 1.0 {
        let (so, co) = exact_sin_cos(o);
        let (s, c) = (k(m) * q.sin(), q.cos());
        let origin = pose_to_transform::<S>(&joint.origin);
        let a = [joint.axis.x, joint.axis.y, joint.axis.z];
        return Transform {
            rot: origin.rot * axis_rotation(a, s * k(co) + c * k(so), c * k(co) - s * k(so)),
            pos: origin.pos,
        };
    }
    joint_transform(joint, k(m) * q + k(o))
}

/// Every joint's transform at the coordinates `q` (mimic joints from their master's
/// coordinate): the only place where sines and cosines are taken.
pub fn joint_transforms<S: Scalar>(model: &Model, q: &[S]) -> Vec<Transform<S>> {
    model
        .joints()
        .iter()
        .zip(model.coordinate_maps())
        .zip(model.mimics())
        .map(|((j, map), mimic)| match mimic {
            None => joint_transform(j, q[map.coordinate]),
            Some(_) => mimic_transform(j, q[map.coordinate], map),
        })
        .collect()
}

/// Every joint's transform at the coordinates `q` as its two factors, the constant placement
/// and the joint's own motion ([`FactoredTransform`]): the same transforms as
/// [`joint_transforms`], for the algorithms that apply them one factor after the other.
pub fn joint_factored_transforms<S: Scalar>(model: &Model, q: &[S]) -> Vec<FactoredTransform<S>> {
    model
        .joints()
        .iter()
        .zip(model.coordinate_maps())
        .zip(model.mimics())
        .map(|((joint, map), mimic)| {
            let q = q[map.coordinate];
            let inner = match mimic {
                None => own_motion(joint, q),
                Some(_) => mimic_own_motion(joint, q, map),
            };
            FactoredTransform {
                outer: pose_to_transform(&joint.origin),
                inner,
            }
        })
        .collect()
}

/// A joint's own motion at position `q`, from its frame at zero.
fn own_motion<S: Scalar>(joint: &Joint, q: S) -> Transform<S> {
    match joint.kind {
        JointKind::Revolute => own_rotation(joint, q.sin(), q.cos()),
        JointKind::Prismatic => Transform {
            rot: Mat3::identity(),
            pos: axis::<S>(joint).scale(q),
        },
    }
}

fn own_rotation<S: Scalar>(joint: &Joint, s: S, c: S) -> Transform<S> {
    Transform {
        rot: axis_rotation([joint.axis.x, joint.axis.y, joint.axis.z], s, c),
        pos: Vec3::zero(),
    }
}

/// [`own_motion`] of a mimic joint from its master's position, with the sines and cosines of
/// [`mimic_transform`].
fn mimic_own_motion<S: Scalar>(joint: &Joint, q: S, map: &CoordinateMap) -> Transform<S> {
    let (m, o) = (map.multiplier, map.offset);
    let k = |x: f64| S::from_f64(x);
    if joint.kind == JointKind::Revolute && m.abs() == 1.0 {
        let (so, co) = exact_sin_cos(o);
        let (s, c) = (k(m) * q.sin(), q.cos());
        return own_rotation(joint, s * k(co) + c * k(so), c * k(co) - s * k(so));
    }
    own_motion(joint, k(m) * q + k(o))
}

/// `S·x`: the spatial motion of the joint's body for joint rate `x`, in the joint frame.
pub(crate) fn joint_motion<S: Scalar>(joint: &Joint, x: S) -> Motion<S> {
    let v = axis::<S>(joint).scale(x);
    match joint.kind {
        JointKind::Revolute => Motion {
            ang: v,
            lin: Vec3::zero(),
        },
        JointKind::Prismatic => Motion {
            ang: Vec3::zero(),
            lin: v,
        },
    }
}

/// `Sᵀ·f`: the generalized force on the joint from a spatial force on its body.
pub(crate) fn joint_force<S: Scalar>(joint: &Joint, f: &Force<S>) -> S {
    match joint.kind {
        JointKind::Revolute => axis::<S>(joint).dot(&f.ang),
        JointKind::Prismatic => axis::<S>(joint).dot(&f.lin),
    }
}
