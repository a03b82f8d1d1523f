//! Start postures: for the committed robots, postures away from singularities and joint limits
//! with the end-effector above a table; for any other robot, one given by the user or taken
//! from the description.

use dyngen_runtime::Kinematics;
use nalgebra::SVector;

/// The demo's start posture (rad) for a committed robot, by name.
pub fn start_posture<const N: usize>(robot: &str) -> Option<SVector<f64, N>> {
    let q: &[f64] = match robot {
        "arm7" | "arm7_friction" => &[0.0, 0.6, 0.0, -1.3, 0.0, 1.0, 0.0],
        "panda" | "panda_rounded" => &[0.0, -0.1, 0.0, -2.0, 0.0, 1.9, 0.785],
        "ur5" => &[0.0, -1.3, 1.6, -1.87, -1.57, 0.0],
        _ => return None,
    };
    (q.len() == N).then(|| SVector::from_column_slice(q))
}

/// The start posture of robot `R`: `given` (one value per joint) if any, else the committed
/// preset for its name, else the middle of each joint's position limits from the description
/// (which the demo refuses, with the reason, if it is singular for the task).
pub fn start_posture_for<R: Kinematics<N>, const N: usize>(
    given: Option<&[f64]>,
) -> Result<SVector<f64, N>, String> {
    if let Some(q) = given {
        if q.len() != N {
            return Err(format!(
                "--start has {} values; {} has {N} joints",
                q.len(),
                R::NAME
            ));
        }
        return Ok(SVector::from_column_slice(q));
    }
    if let Some(q) = start_posture::<N>(R::NAME) {
        return Ok(q);
    }
    match R::JOINT_NAMES
        .iter()
        .zip(R::JOINT_LIMITS.iter())
        .find(|(_, l)| !(l.lower.is_finite() && l.upper.is_finite()))
    {
        Some((name, _)) => Err(format!(
            "no start posture for {}: joint '{name}' has no position limits to take the middle of; give one with --start",
            R::NAME
        )),
        None => Ok(SVector::from_fn(|i, _| {
            0.5 * (R::JOINT_LIMITS[i].lower + R::JOINT_LIMITS[i].upper)
        })),
    }
}
