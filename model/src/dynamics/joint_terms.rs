//! The joint-level terms (armature, viscous and Coulomb friction, offset) of a model's
//! [`JointTerms`](crate::model::JointTerms): their regressor columns and their torques.
//!
//! They act at each joint on its own, so they are added to the rigid-body quantities rather
//! than threaded through the recursions: `Y` gets `k·n` columns after the inertial ones,
//! `D` gets the armature on its diagonal, `τ` and the Slotine–Li torque get `Σ column·value`.
//!
//! A model has them only without mimic joints (`Model` refuses both together), so a joint here
//! is a coordinate.

use crate::model::{JointTermKind, JointTermValues, Model};
use crate::scalar::Scalar;
use nalgebra::DMatrix;

/// `σ(q̇)` of Coulomb friction: `sign(q̇)`, or `tanh(q̇/ε)` with the model's smoothing `ε`.
pub fn coulomb_shape<S: Scalar>(model: &Model, qd: S) -> S {
    match model.joint_terms().coulomb_smoothing {
        None => qd.sign(),
        Some(eps) => (qd * S::from_f64(1.0 / eps)).tanh(),
    }
}

/// The entry of joint `j`'s row for its parameter of kind `kind`.
pub fn column_entry<S: Scalar>(
    model: &Model,
    kind: JointTermKind,
    j: usize,
    qd: &[S],
    v: &[S],
    a: &[S],
) -> S {
    match kind {
        JointTermKind::Armature => a[j],
        JointTermKind::Viscous => v[j],
        JointTermKind::Coulomb => coulomb_shape(model, qd[j]),
        JointTermKind::Offset => S::one(),
    }
}

/// Writes the joint-level columns into `y` (n × P), after the inertial ones: column
/// `10n + j·k + pos` is non-zero in row `j` only.
pub fn fill_joint_term_columns<S: Scalar>(model: &Model, y: &mut DMatrix<S>, qd: &[S], v: &[S], a: &[S]) {
    for j in 0..model.joints().len() {
        for &kind in &model.joint_terms().kinds {
            if let Some(col) = model.joint_term_index(j, kind) {
                y[(j, col)] = column_entry(model, kind, j, qd, v, a);
            }
        }
    }
}

/// The joint-level torque of every joint, `Σ_kind column·value`, with the chosen kinds only.
pub fn joint_term_torques<S: Scalar>(
    model: &Model,
    values: &[JointTermValues],
    qd: &[S],
    v: &[S],
    a: &[S],
) -> Vec<S> {
    (0..model.dof())
        .map(|j| {
            let value = values.get(j).copied().unwrap_or_default();
            model.joint_terms().kinds.iter().fold(S::zero(), |acc, &kind| {
                acc + column_entry(model, kind, j, qd, v, a) * S::from_f64(value.get(kind))
            })
        })
        .collect()
}

/// Adds the armature to the diagonal of the mass matrix `d` (when it is a chosen kind).
pub fn add_armature<S: Scalar>(model: &Model, values: &[JointTermValues], d: &mut DMatrix<S>) {
    if !model.joint_terms().has(JointTermKind::Armature) {
        return;
    }
    for (j, value) in values.iter().enumerate().take(model.dof()) {
        d[(j, j)] = d[(j, j)] + S::from_f64(value.armature);
    }
}

/// Adds `extra` to `base` entry by entry.
pub fn add_torques<S: Scalar>(base: Vec<S>, extra: &[S]) -> Vec<S> {
    base.into_iter().zip(extra).map(|(x, &e)| x + e).collect()
}

/// The joint-level values that act in `model` (chosen kinds only; the others are 0).
pub fn joint_term_values(model: &Model) -> Vec<JointTermValues> {
    (0..model.dof())
        .map(|j| model.joint_terms().effective(j))
        .collect()
}
