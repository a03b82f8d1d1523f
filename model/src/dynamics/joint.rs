//! Joint transforms and motion subspaces: where the joint variables enter.

use crate::model::{exact_sin_cos, CoordinateMap, Joint, JointKind, Model, Pose};
use crate::scalar::Scalar;
use crate::spatial::{FactoredTransform, Force, Mat3, Motion, Transform, Vec3};

pub fn pose_to_transform<S: Scalar>(p: &Pose) -> Transform<S> {
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
fn mimic_transform<S: Scalar>(joint: &Joint, q: S, map: &CoordinateMap) -> Transform<S> {
    match mimic_position(joint, q, map) {
        MimicPosition::SinCos(s, c) => {
            let origin = pose_to_transform::<S>(&joint.origin);
            let a = [joint.axis.x, joint.axis.y, joint.axis.z];
            Transform {
                rot: origin.rot * axis_rotation(a, s, c),
                pos: origin.pos,
            }
        }
        MimicPosition::Value(x) => joint_transform(joint, x),
    }
}

/// Where a mimic joint is, from its master's position `q` (`q_j = m·q + o`).
enum MimicPosition<S> {
    /// A revolute joint with `m = ±1`: its sine and cosine from those of `q` by the angle-sum
    /// identities (`sin(±q + o) = ±sin q cos o + cos q sin o`, `cos(±q + o) = cos q cos o ∓
    /// sin q sin o`), so generated code reuses the master's precomputed `JointTrig` entries and
    /// takes no new sine.
    SinCos(S, S),
    /// Any other: `m·q + o` itself, whose sine and cosine are its own.
    Value(S),
}

fn mimic_position<S: Scalar>(joint: &Joint, q: S, map: &CoordinateMap) -> MimicPosition<S> {
    let (m, o) = (map.multiplier, map.offset);
    let k = |x: f64| S::from_f64(x);
    if joint.kind == JointKind::Revolute && m.abs() == 1.0 {
        let (so, co) = exact_sin_cos(o);
        let (s, c) = (k(m) * q.sin(), q.cos());
        return MimicPosition::SinCos(s * k(co) + c * k(so), c * k(co) - s * k(so));
    }
    MimicPosition::Value(k(m) * q + k(o))
}

/// Every joint's transform at the coordinates `q` (mimic joints from their master's
/// coordinate): the only place where sines and cosines are taken.
pub fn joint_transforms<S: Scalar>(model: &Model, q: &[S]) -> Vec<Transform<S>> {
    per_joint(model, q, |joint, q, map| match map {
        None => joint_transform(joint, q),
        Some(map) => mimic_transform(joint, q, map),
    })
}

/// `f(joint, its coordinate's value, the map from that coordinate if the joint mimics it)` for
/// every joint, in joint order.
fn per_joint<S: Scalar, T>(
    model: &Model,
    q: &[S],
    f: impl Fn(&Joint, S, Option<&CoordinateMap>) -> T,
) -> Vec<T> {
    model
        .joints()
        .iter()
        .zip(model.coordinate_maps())
        .zip(model.mimics())
        .map(|((joint, map), mimic)| f(joint, q[map.coordinate], mimic.as_ref().map(|_| map)))
        .collect()
}

/// Every joint's transform at the coordinates `q` as its two factors, the constant placement
/// and the joint's own motion ([`FactoredTransform`]): the same transforms as
/// [`joint_transforms`], for the algorithms that apply them one factor after the other.
pub fn joint_factored_transforms<S: Scalar>(model: &Model, q: &[S]) -> Vec<FactoredTransform<S>> {
    per_joint(model, q, |joint, q, map| FactoredTransform {
        outer: pose_to_transform(&joint.origin),
        inner: match map {
            None => own_motion(joint, q),
            Some(map) => mimic_own_motion(joint, q, map),
        },
    })
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

/// [`own_motion`] of a mimic joint from its master's position.
fn mimic_own_motion<S: Scalar>(joint: &Joint, q: S, map: &CoordinateMap) -> Transform<S> {
    match mimic_position(joint, q, map) {
        MimicPosition::SinCos(s, c) => own_rotation(joint, s, c),
        MimicPosition::Value(x) => own_motion(joint, x),
    }
}

/// `S·x`: the spatial motion of the joint's body for joint rate `x`, in the joint frame.
pub fn joint_motion<S: Scalar>(joint: &Joint, x: S) -> Motion<S> {
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
pub fn joint_force<S: Scalar>(joint: &Joint, f: &Force<S>) -> S {
    match joint.kind {
        JointKind::Revolute => axis::<S>(joint).dot(&f.ang),
        JointKind::Prismatic => axis::<S>(joint).dot(&f.lin),
    }
}
