//! How far a held frame is from its anchor, in the contact's axes: the position error that
//! Baumgarte stabilisation feeds back.

use super::kind::ContactKind;
use crate::{Pose, ReferenceFrame};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3, Vector6};

/// The error `e` a contact's rows feed back (`−K_p e`), as Pinocchio defines it: for a point
/// `−c₁Mc₂.translation`, for a frame `−log₆(c₁Mc₂)` (linear first), `c₁Mc₂` the anchor seen
/// from the frame; rotated into world axes for `LocalWorldAligned`. A point's error is the
/// first three entries (the rest zero).
pub fn placement_error(
    kind: ContactKind,
    reference: ReferenceFrame,
    frame: &Pose,
    anchor: &Pose,
) -> Vector6<f64> {
    let rotation = &frame.rotation;
    let relative_rotation = rotation.transpose() * anchor.rotation;
    let relative_translation = rotation.transpose() * (anchor.translation - frame.translation);
    let (linear, angular) = match kind {
        ContactKind::Point => (-relative_translation, Vector3::zeros()),
        ContactKind::Frame => {
            let (v, w) = log6(&relative_rotation, &relative_translation);
            (-v, -w)
        }
    };
    let (linear, angular) = match reference {
        ReferenceFrame::LocalWorldAligned => (rotation * linear, rotation * angular),
        _ => (linear, angular),
    };
    Vector6::new(linear.x, linear.y, linear.z, angular.x, angular.y, angular.z)
}

/// `log₆` of a rigid transform: the twist `(v, ω)` whose exponential it is.
fn log6(rotation: &Matrix3<f64>, translation: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let omega =
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(*rotation)).scaled_axis();
    let theta = omega.norm();
    // V⁻¹ p = α p − ½ ω × p + β (ω·p) ω, with series near θ = 0.
    let (alpha, beta) = if theta < 1e-4 {
        let t2 = theta * theta;
        (1.0 - t2 / 12.0 - t2 * t2 / 720.0, 1.0 / 12.0 + t2 / 720.0)
    } else {
        let (s, c) = (libm::sin(theta), libm::cos(theta));
        let alpha = theta * s / (2.0 * (1.0 - c));
        (alpha, (1.0 - alpha) / (theta * theta))
    };
    let v = alpha * translation - 0.5 * omega.cross(translation) + beta * omega.dot(translation) * omega;
    (v, omega)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `exp₆` of a twist, written independently of `log6` (Rodrigues and the left Jacobian).
    fn exp6(v: &Vector3<f64>, w: &Vector3<f64>) -> (Matrix3<f64>, Vector3<f64>) {
        let theta = w.norm();
        let k = w.cross_matrix();
        let (s, c) = theta.sin_cos();
        let r = Matrix3::identity() + (s / theta) * k + ((1.0 - c) / (theta * theta)) * k * k;
        let jl = Matrix3::identity()
            + ((1.0 - c) / (theta * theta)) * k
            + ((theta - s) / (theta * theta * theta)) * k * k;
        (r, jl * v)
    }

    #[test]
    fn log6_inverts_exp6_from_small_to_large_angles() {
        // The reference exp₆ loses digits to cancellation at small angles ((θ − sin θ)/θ³).
        for (scale, tolerance) in [(1e-3, 1e-12), (0.3, 1e-13), (2.5, 1e-12)] {
            let v = Vector3::new(0.4, -1.2, 0.7) * scale;
            let w = Vector3::new(-0.5, 0.3, 0.8).normalize() * scale;
            let (r, p) = exp6(&v, &w);
            let (v2, w2) = log6(&r, &p);
            assert!(
                (v2 - v).amax() < tolerance && (w2 - w).amax() < tolerance,
                "scale {scale}"
            );
        }
    }

    #[test]
    fn a_frame_at_its_anchor_has_no_error_and_a_shifted_one_points_back() {
        let rotation = Rotation3::from_euler_angles(0.3, -0.2, 1.1).into_inner();
        let frame = Pose {
            rotation,
            translation: Vector3::new(0.1, 0.2, 0.3),
        };
        for kind in [ContactKind::Point, ContactKind::Frame] {
            let e = placement_error(kind, ReferenceFrame::Local, &frame, &frame);
            assert!(e.amax() < 1e-15);
        }
        // The anchor 1 cm along world x: the world-aligned error is −1 cm along x.
        let shifted = Pose {
            rotation,
            translation: frame.translation + Vector3::new(0.01, 0.0, 0.0),
        };
        let e = placement_error(
            ContactKind::Point,
            ReferenceFrame::LocalWorldAligned,
            &frame,
            &shifted,
        );
        assert!((e[0] + 0.01).abs() < 1e-15 && e[1].abs() < 1e-15 && e[2].abs() < 1e-15);
    }
}
