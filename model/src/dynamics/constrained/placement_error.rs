//! How far a contact's frame is from its anchor, in the contact's axes: the position error
//! Baumgarte stabilisation feeds back. Numeric only: `log₆` needs `atan2`, which the traced
//! algorithms do not, so generated code takes this error as an input.

use super::contact::{Anchor, ContactKind};
use dyngen_runtime::ReferenceFrame;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// The error `e` the rows of a contact feed back (`−K_p e`), as Pinocchio defines it: for a
/// point `−c₁Mc₂.translation`, for a frame `−log₆(c₁Mc₂)` (linear first), `c₁Mc₂` the anchor
/// seen from the frame; rotated into world axes for `LOCAL_WORLD_ALIGNED`.
pub fn placement_error(
    kind: ContactKind,
    reference: ReferenceFrame,
    frame: (&Matrix3<f64>, &Vector3<f64>),
    anchor: &Anchor,
) -> Vec<f64> {
    let (rotation, translation) = frame;
    let relative_rotation = rotation.transpose() * anchor.rotation;
    let relative_translation = rotation.transpose() * (anchor.translation - translation);
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
    let mut out: Vec<f64> = linear.iter().copied().collect();
    if kind == ContactKind::Frame {
        out.extend(angular.iter());
    }
    out
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
        let (s, c) = theta.sin_cos();
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
        let translation = Vector3::new(0.1, 0.2, 0.3);
        let at = Anchor {
            rotation,
            translation,
        };
        for kind in [ContactKind::Point, ContactKind::Frame] {
            let e = placement_error(kind, ReferenceFrame::Local, (&rotation, &translation), &at);
            assert!(e.iter().all(|x| x.abs() < 1e-15));
        }
        // The anchor 1 cm along world x: the world-aligned error is −1 cm along x.
        let shifted = Anchor {
            rotation,
            translation: translation + Vector3::new(0.01, 0.0, 0.0),
        };
        let e = placement_error(
            ContactKind::Point,
            ReferenceFrame::LocalWorldAligned,
            (&rotation, &translation),
            &shifted,
        );
        assert!((e[0] + 0.01).abs() < 1e-15 && e[1].abs() < 1e-15 && e[2].abs() < 1e-15);
    }
}
