//! Demo settings for the committed robots: a start posture away from singularities and joint
//! limits, and the joint torque limits from the datasheets.

use nalgebra::SVector;

/// Start posture (rad) and torque limits (N·m) for the demo, by robot name.
pub fn preset<const N: usize>(robot: &str) -> Option<(SVector<f64, N>, SVector<f64, N>)> {
    let (q, tau): (&[f64], &[f64]) = match robot {
        // KUKA LBR iiwa 14 R820 limits.
        "arm7" => (
            &[0.0, 0.6, 0.0, -1.3, 0.0, 1.0, 0.0],
            &[320.0, 320.0, 176.0, 176.0, 110.0, 40.0, 40.0],
        ),
        // Franka Emika Panda limits.
        "panda" => (
            &[0.0, -0.1, 0.0, -2.0, 0.0, 1.9, 0.785],
            &[87.0, 87.0, 87.0, 87.0, 12.0, 12.0, 12.0],
        ),
        // UR5 limits.
        "ur5" => (
            &[0.0, -1.3, 1.6, -1.87, -1.57, 0.0],
            &[150.0, 150.0, 150.0, 28.0, 28.0, 28.0],
        ),
        _ => return None,
    };
    (q.len() == N).then(|| (SVector::from_column_slice(q), SVector::from_column_slice(tau)))
}
