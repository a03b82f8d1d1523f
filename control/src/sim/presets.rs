//! Start postures for the demo on the committed robots: away from singularities and joint
//! limits, with the end-effector above a table. Any other robot is started with `--start`.

use nalgebra::SVector;

/// The demo's start posture (rad) for a committed robot, by name.
pub fn start_posture<const N: usize>(robot: &str) -> Option<SVector<f64, N>> {
    let q: &[f64] = match robot {
        "arm7" => &[0.0, 0.6, 0.0, -1.3, 0.0, 1.0, 0.0],
        "panda" => &[0.0, -0.1, 0.0, -2.0, 0.0, 1.9, 0.785],
        "ur5" => &[0.0, -1.3, 1.6, -1.87, -1.57, 0.0],
        _ => return None,
    };
    (q.len() == N).then(|| SVector::from_column_slice(q))
}
