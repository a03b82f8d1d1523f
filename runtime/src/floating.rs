//! The configuration of a free-flying base: its pose as a position and a unit quaternion, and
//! how a base twist moves it (`integrate`) or relates two poses (`difference`).
//!
//! Pinocchio's conventions (`JointModelFreeFlyer`): the configuration of a floating-base robot
//! is `[x, y, z, qx, qy, qz, qw, q_joints…]` (`nq = n + 7`), its velocity
//! `[v_x, v_y, v_z, ω_x, ω_y, ω_z, q̇_joints…]` (`nv = n + 6`), with the base's linear and
//! angular velocity in the **base body's own frame**. Integration moves the base along the
//! screw of that twist (the SE(3) exponential), so `difference(a, integrate(a, v, 1)) = v`.

use libm::{cos, sin, sqrt};
use nalgebra::{Matrix3, Vector3};

/// How far a quaternion's norm may be from one before it is refused: a quaternion normalised
/// in single precision is within 1e-7; anything farther is not meant as a rotation.
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-6;

/// A base quaternion whose norm is not one ([`BasePose::new`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonUnitQuaternion {
    /// The quaternion's norm.
    pub norm: f64,
}

impl core::fmt::Display for NonUnitQuaternion {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(
            f,
            "the base quaternion (q[3..7], ordered x, y, z, w) has norm {}, not 1 (tolerance {:e})",
            self.norm, QUATERNION_NORM_TOLERANCE
        )
    }
}

/// The pose of a free-flying base in the world: `p_world = rotation · p_base + position`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BasePose {
    /// The base body's origin in world coordinates.
    pub position: Vector3<f64>,
    /// The quaternion `[x, y, z, w]` of the base orientation, as given (unit to within
    /// [`QUATERNION_NORM_TOLERANCE`]; the rotation is that of its normalised form).
    pub quaternion: [f64; 4],
    /// The base body's axes in world coordinates (columns), from the quaternion.
    pub rotation: Matrix3<f64>,
}

impl BasePose {
    /// The pose with `position` and the quaternion `[x, y, z, w]` (Pinocchio's `q[0..7]`). A
    /// quaternion within [`QUATERNION_NORM_TOLERANCE`] of unit norm gives the rotation of its
    /// normalised form; any other is refused.
    pub fn new(position: [f64; 3], quaternion: [f64; 4]) -> Result<BasePose, NonUnitQuaternion> {
        let squared: f64 = quaternion.iter().map(|x| x * x).sum();
        // |‖q‖ − 1| ≤ tol, without the square root on the path every control tick takes:
        // ‖q‖² − 1 = (‖q‖ − 1)(‖q‖ + 1). A NaN compares false, so it is refused too.
        let tolerance = QUATERNION_NORM_TOLERANCE;
        let unit = (squared - 1.0).abs() <= tolerance * (2.0 - tolerance);
        if !unit {
            return Err(NonUnitQuaternion { norm: sqrt(squared) });
        }
        Ok(BasePose {
            position: Vector3::from(position),
            quaternion,
            rotation: rotation_of(&quaternion, squared),
        })
    }

    /// The pose stored in the first seven entries of a configuration `q`.
    pub fn from_configuration(q: &[f64]) -> Result<BasePose, NonUnitQuaternion> {
        BasePose::new([q[0], q[1], q[2]], [q[3], q[4], q[5], q[6]])
    }

    /// The seven configuration entries `[x, y, z, qx, qy, qz, qw]`.
    pub fn configuration(&self) -> [f64; 7] {
        let (p, q) = (&self.position, &self.quaternion);
        [p.x, p.y, p.z, q[0], q[1], q[2], q[3]]
    }

    /// The pose reached by moving with the base twist `twist = [v; ω]` (base frame) for time
    /// `dt`: `M · exp(dt·twist)`.
    pub fn integrate(&self, twist: &[f64; 6], dt: f64) -> BasePose {
        let v = Vector3::new(twist[0], twist[1], twist[2]) * dt;
        let w = Vector3::new(twist[3], twist[4], twist[5]) * dt;
        let position = self.position + self.rotation * (left_jacobian(&w) * v);
        let quaternion = normalised(multiply(&self.quaternion, &exp_quaternion(&w)));
        BasePose {
            position,
            quaternion,
            rotation: rotation_of(&quaternion, 1.0),
        }
    }

    /// The base twist that moves this pose to `other` in unit time: `log(M⁻¹ · M_other)`, so
    /// that `self.integrate(&self.difference(other), 1.0)` is `other`.
    pub fn difference(&self, other: &BasePose) -> [f64; 6] {
        let relative = self.rotation.transpose() * other.rotation;
        let w = log_rotation(&relative);
        let v = inverse_left_jacobian(&w) * (self.rotation.transpose() * (other.position - self.position));
        [v.x, v.y, v.z, w.x, w.y, w.z]
    }
}

/// The rotation of the quaternion `q` of squared norm `squared`, as of `q / ‖q‖` (the `2/‖q‖²`
/// scaling makes it exactly orthonormal for a quaternion a hair off unit, with one division
/// and no square root).
fn rotation_of(q: &[f64; 4], squared: f64) -> Matrix3<f64> {
    let [x, y, z, w] = *q;
    let s = 2.0 / squared;
    Matrix3::new(
        1.0 - s * (y * y + z * z),
        s * (x * y - z * w),
        s * (x * z + y * w),
        s * (x * y + z * w),
        1.0 - s * (x * x + z * z),
        s * (y * z - x * w),
        s * (x * z - y * w),
        s * (y * z + x * w),
        1.0 - s * (x * x + y * y),
    )
}

/// `a ⊗ b`, both `[x, y, z, w]`.
fn multiply(a: &[f64; 4], b: &[f64; 4]) -> [f64; 4] {
    let [ax, ay, az, aw] = *a;
    let [bx, by, bz, bw] = *b;
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

fn normalised(q: [f64; 4]) -> [f64; 4] {
    let norm = sqrt(q.iter().map(|x| x * x).sum());
    q.map(|x| x / norm)
}

/// The unit quaternion of the rotation by the vector `w` (angle `|w|` about `w/|w|`).
fn exp_quaternion(w: &Vector3<f64>) -> [f64; 4] {
    let angle = sqrt(w.dot(w));
    // sin(θ/2)/θ by its series near zero, where the quotient loses every digit.
    let k = match angle < 1e-4 {
        true => 0.5 - angle * angle / 48.0,
        false => sin(angle / 2.0) / angle,
    };
    [w.x * k, w.y * k, w.z * k, cos(angle / 2.0)]
}

fn skew(w: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -w.z, w.y, w.z, 0.0, -w.x, -w.y, w.x, 0.0)
}

/// SO(3)'s left Jacobian `V(w) = 1 + (1 − cos θ)/θ² [w] + (θ − sin θ)/θ³ [w]²`: the
/// translation of `exp([v; w])` is `V(w) v`.
fn left_jacobian(w: &Vector3<f64>) -> Matrix3<f64> {
    let t = sqrt(w.dot(w));
    let (a, b) = match t < 1e-4 {
        true => (0.5 - t * t / 24.0, 1.0 / 6.0 - t * t / 120.0),
        false => ((1.0 - cos(t)) / (t * t), (t - sin(t)) / (t * t * t)),
    };
    let k = skew(w);
    Matrix3::identity() + k * a + k * k * b
}

/// `V(w)⁻¹ = 1 − [w]/2 + (1/θ² − (1 + cos θ)/(2 θ sin θ)) [w]²`.
fn inverse_left_jacobian(w: &Vector3<f64>) -> Matrix3<f64> {
    let t = sqrt(w.dot(w));
    let c = match t < 1e-4 {
        true => 1.0 / 12.0 + t * t / 720.0,
        false => 1.0 / (t * t) - (1.0 + cos(t)) / (2.0 * t * sin(t)),
    };
    let k = skew(w);
    Matrix3::identity() - k * 0.5 + k * k * c
}

/// The rotation vector of `r` (angle in `[0, π]`), from the quaternion of `r` so that angles
/// near π keep their digits.
fn log_rotation(r: &Matrix3<f64>) -> Vector3<f64> {
    let q = quaternion_of(r);
    let [x, y, z, w] = match q[3] < 0.0 {
        true => q.map(|c| -c),
        false => q,
    };
    let s = sqrt(x * x + y * y + z * z);
    // θ = 2 atan2(s, w); θ / s by its series near zero.
    let k = match s < 1e-8 {
        true => 2.0 / w,
        false => 2.0 * libm::atan2(s, w) / s,
    };
    Vector3::new(x * k, y * k, z * k)
}

/// The unit quaternion `[x, y, z, w]` of a rotation matrix (Shepperd's method: the largest
/// of the four squared components first).
fn quaternion_of(r: &Matrix3<f64>) -> [f64; 4] {
    let trace = r[(0, 0)] + r[(1, 1)] + r[(2, 2)];
    let candidates = [r[(0, 0)], r[(1, 1)], r[(2, 2)], trace];
    let (k, _) =
        candidates.iter().enumerate().fold(
            (0, f64::NEG_INFINITY),
            |best, (i, &v)| if v > best.1 { (i, v) } else { best },
        );
    let q = match k {
        3 => {
            let s = sqrt(1.0 + trace) * 2.0;
            [
                (r[(2, 1)] - r[(1, 2)]) / s,
                (r[(0, 2)] - r[(2, 0)]) / s,
                (r[(1, 0)] - r[(0, 1)]) / s,
                s / 4.0,
            ]
        }
        0 => {
            let s = sqrt(1.0 + r[(0, 0)] - r[(1, 1)] - r[(2, 2)]) * 2.0;
            [
                s / 4.0,
                (r[(0, 1)] + r[(1, 0)]) / s,
                (r[(0, 2)] + r[(2, 0)]) / s,
                (r[(2, 1)] - r[(1, 2)]) / s,
            ]
        }
        1 => {
            let s = sqrt(1.0 + r[(1, 1)] - r[(0, 0)] - r[(2, 2)]) * 2.0;
            [
                (r[(0, 1)] + r[(1, 0)]) / s,
                s / 4.0,
                (r[(1, 2)] + r[(2, 1)]) / s,
                (r[(0, 2)] - r[(2, 0)]) / s,
            ]
        }
        _ => {
            let s = sqrt(1.0 + r[(2, 2)] - r[(0, 0)] - r[(1, 1)]) * 2.0;
            [
                (r[(0, 2)] + r[(2, 0)]) / s,
                (r[(1, 2)] + r[(2, 1)]) / s,
                s / 4.0,
                (r[(1, 0)] - r[(0, 1)]) / s,
            ]
        }
    };
    normalised(q)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pose(seed: f64) -> BasePose {
        let q = [0.3 * seed, -0.7, 0.2 + seed, 0.5];
        let n = sqrt(q.iter().map(|x| x * x).sum());
        BasePose::new([seed, -0.5, 2.0], q.map(|x| x / n)).unwrap()
    }

    #[test]
    fn rotation_is_orthonormal_with_unit_determinant() {
        let r = pose(0.4).rotation;
        assert!((r.transpose() * r - Matrix3::identity()).amax() < 1e-15);
        let det = r.column(0).dot(&r.column(1).cross(&r.column(2)));
        assert!((det - 1.0).abs() < 1e-15);
    }

    #[test]
    fn difference_inverts_integrate_for_small_and_large_twists() {
        for scale in [1e-9, 1e-3, 0.5, 2.5] {
            let a = pose(0.1);
            let twist = [0.3, -1.2, 0.8, 0.4, 0.9, -0.6].map(|x| x * scale);
            let b = a.integrate(&twist, 1.0);
            let back = a.difference(&b);
            for k in 0..6 {
                assert!(
                    (back[k] - twist[k]).abs() < 1e-12 * (1.0 + scale),
                    "{scale}: {back:?}"
                );
            }
        }
    }

    #[test]
    fn integrate_moves_along_the_body_frame_twist() {
        // A pure translation along the base's own x axis moves it along its first column.
        let a = pose(0.7);
        let b = a.integrate(&[2.0, 0.0, 0.0, 0.0, 0.0, 0.0], 0.25);
        let expected = a.position + a.rotation.column(0) * 0.5;
        assert!((b.position - expected).amax() < 1e-15);
        assert_eq!(b.rotation, a.rotation);
        // A small rotation turns the axes by R [ω dt]×, to first order.
        let w = Vector3::new(0.3, -0.2, 0.5);
        let h = 1e-6;
        let c = a.integrate(&[0.0, 0.0, 0.0, w.x, w.y, w.z], h);
        let rate = (c.rotation - a.rotation) / h;
        assert!((rate - a.rotation * skew(&w)).amax() < 1e-5);
    }

    #[test]
    fn non_unit_quaternions_are_refused_and_near_unit_ones_normalised() {
        assert!(BasePose::new([0.0; 3], [0.0, 0.0, 0.0, 1.0 + 1e-3]).is_err());
        assert!(BasePose::new([0.0; 3], [0.0; 4]).is_err());
        assert!(BasePose::new([0.0; 3], [f64::NAN, 0.0, 0.0, 1.0]).is_err());
        let near = BasePose::new([0.0; 3], [0.0, 0.0, 0.0, 1.0 + 1e-8]).unwrap();
        assert_eq!(near.rotation, Matrix3::identity());
        let unit = normalised([0.3, -0.1, 0.5, 0.8]);
        let tilted = BasePose::new([0.0; 3], unit.map(|x| x * (1.0 + 5e-7))).unwrap();
        assert!((tilted.rotation - BasePose::new([0.0; 3], unit).unwrap().rotation).amax() < 1e-15);
        let r = tilted.rotation;
        assert!((r.transpose() * r - Matrix3::identity()).amax() < 1e-15);
        assert!(BasePose::new([0.0; 3], [0.0, 0.0, 0.0, 1.0 + 2e-6]).is_err());
        assert!(BasePose::new([0.0; 3], [0.0, 0.0, 0.0, 1.0 - 2e-6]).is_err());
    }

    #[test]
    fn log_of_a_half_turn_keeps_its_angle() {
        let a = BasePose::new([0.0; 3], [0.0, 0.0, 0.0, 1.0]).unwrap();
        let b = BasePose::new([0.0; 3], [1.0, 0.0, 0.0, 0.0]).unwrap();
        let d = a.difference(&b);
        assert!((d[3].abs() - core::f64::consts::PI).abs() < 1e-12, "{d:?}");
    }
}
