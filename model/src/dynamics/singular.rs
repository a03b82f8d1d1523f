//! Joints whose mass matrix pivot vanishes: the joint moves no mass or inertia in its own
//! direction (a massless last link, a point mass on its revolute axis, a rod along it), so `D` is
//! singular and forward dynamics and `D⁻¹` do not exist. Found numerically, from the pivots of
//! the tree factorisation at random configurations, because what counts is the whole subtree
//! seen through the joint's axis, not any one body's parameters.

use super::forward_dynamics::factor_mass_matrix;
use super::{body_inertias, joint_term_values, joint_transforms};
use crate::model::Model;
use dyngen_runtime::SplitMix64;

/// Configurations tried; a pivot that is zero at all of them is zero by structure.
const STATES: usize = 8;

/// A pivot below this fraction of the largest diagonal entry of `D` counts as zero (rounding of
/// an exact zero is ~1e-16 of it; real small links are far above).
const REL_TOL: f64 = 1e-12;

/// Indices (in [`Model::joints`]) of the joints whose pivot vanishes at every tried
/// configuration; with mimic joints, the joints whose coordinate's pivot does (the pivots of
/// the dense factorisation of the coupled `D`, coordinates in order).
pub fn singular_joints(model: &Model) -> Vec<usize> {
    let n = model.dof();
    let inertias = body_inertias::<f64>(model);
    // The armature alone can make a pivot non-zero.
    let joint_values = joint_term_values(model);
    let mut rng = SplitMix64::new(0x5eed_f0d1);
    let mut singular = vec![true; n];
    for _ in 0..STATES {
        let q: Vec<f64> = (0..n).map(|_| rng.uniform((-3.0, 3.0))).collect();
        let x = joint_transforms(model, &q);
        let factor = factor_mass_matrix(model, &x, &inertias, &joint_values);
        // Below a zero pivot the elimination produces NaN or garbage: only finite pivots count,
        // so the ancestors of a singular joint are not blamed for it.
        let finite = factor.pivots.iter().filter(|p| p.is_finite());
        let scale = finite.fold(0.0_f64, |m, p| m.max(p.abs()));
        for (s, p) in singular.iter_mut().zip(&factor.pivots) {
            *s &= p.is_finite() && p.abs() <= REL_TOL * scale;
        }
    }
    let joints = model.coordinate_joints();
    (0..n).filter(|&k| singular[k]).map(|k| joints[k]).collect()
}
