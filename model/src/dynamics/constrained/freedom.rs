//! How many degrees of freedom a model's contacts leave: the velocity coordinates less the rank
//! of the rows at a configuration chosen to be no special one. Counting rows instead would
//! refuse redundant sets that still move (a planar loop held as a point has a row of zeros)
//! and let through sets that hold more than they have rows for.

use super::rows::{constraint_rows, ContactMotion};
use crate::dynamics::frames::FrameMotion;
use crate::dynamics::{body_poses, FloatingDynamics, NumericDynamics};
use crate::model::Model;

/// `nv − rank J` at a generic configuration, `nv` for a model without contacts.
pub fn free_degrees(model: &Model) -> usize {
    let contacts = model.contacts();
    if contacts.is_empty() {
        return model.nv();
    }
    // Joint angles without a pattern, away from zero and the quarter turns.
    let joints: Vec<f64> = (0..model.dof()).map(|k| (1.3 * k as f64 + 0.7).sin()).collect();
    let velocity = vec![0.0; model.nv()];
    let motions = match FloatingDynamics::new(model) {
        Some(dynamics) => {
            let (x, y, z, w) = (0.1, -0.2, 0.3, 0.9);
            let norm = f64::sqrt(x * x + y * y + z * z + w * w);
            let mut q = vec![0.2, -0.1, 0.4, x / norm, y / norm, z / norm, w / norm];
            q.extend_from_slice(&joints);
            // A unit quaternion by construction: the fallback is never taken.
            let Ok(state) = dynamics.state(&q) else {
                return model.nv();
            };
            ContactMotion::of(contacts, |k| dynamics.frame_motion(&state, &velocity, k))
        }
        None => {
            let dynamics = NumericDynamics::new(model);
            let world = body_poses(model, &dynamics.configuration(&joints).transforms);
            ContactMotion::of(contacts, |k| {
                FrameMotion::new(model, &world, &velocity, &model.frames()[k])
            })
        }
    };
    let jacobian = constraint_rows(contacts, &motions, &velocity).jacobian;
    let singular = jacobian.singular_values();
    let largest = singular.max().max(1.0);
    let rank = singular.iter().filter(|s| **s > 1e-9 * largest).count();
    model.nv() - rank
}
