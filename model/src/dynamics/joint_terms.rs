//! The joint-level terms (armature, viscous and Coulomb friction, offset) of a model's
//! [`JointTerms`](crate::model::JointTerms): their regressor columns and their torques.
//!
//! They act at each joint on its own, so they are added to the rigid-body quantities rather
//! than threaded through the recursions: `Y` gets `k·n` columns after the inertial ones,
//! `D` gets the armature on its diagonal, `τ` and the Slotine–Li torque get `Σ column·value`.
//!
//! A model has them only without mimic joints (`Model` refuses both together), so a joint here
//! is a coordinate. On a floating base they act on the joint rows only: the functions taking a
//! `lead` leave that many rows (and columns) before the joints' alone, the base's six rows and
//! the base body's ten parameters.

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
    fill_joint_term_columns_after(model, y, (0, 0), qd, v, a);
}

/// [`fill_joint_term_columns`] into a `y` whose first `lead.0` rows and `lead.1` columns come
/// before the joints' rows and the bodies' columns (a floating base's six rows and its body's
/// ten parameters); `qd`, `v`, `a` the joints' rates.
pub fn fill_joint_term_columns_after<S: Scalar>(
    model: &Model,
    y: &mut DMatrix<S>,
    lead: (usize, usize),
    qd: &[S],
    v: &[S],
    a: &[S],
) {
    for j in 0..model.joints().len() {
        for &kind in &model.joint_terms().kinds {
            if let Some(col) = model.joint_term_index(j, kind) {
                y[(lead.0 + j, lead.1 + col)] = column_entry(model, kind, j, qd, v, a);
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

/// `tau` with the joint-level torques ([`joint_term_torques`] of the joints' rates `qd`, `v`,
/// `a`) added to its entries after the first `lead` (a floating base's six). Without chosen
/// kinds `tau` comes back untouched, so such a model's graph gets no node.
pub fn with_joint_term_torques<S: Scalar>(
    model: &Model,
    values: &[JointTermValues],
    mut tau: Vec<S>,
    lead: usize,
    (qd, v, a): (&[S], &[S], &[S]),
) -> Vec<S> {
    if model.joint_terms().kinds.is_empty() {
        return tau;
    }
    let joint = joint_term_torques(model, values, qd, v, a);
    for (t, j) in tau[lead..].iter_mut().zip(joint) {
        *t = *t + j;
    }
    tau
}

/// Adds the armature to the diagonal of the mass matrix `d` (when it is a chosen kind).
pub fn add_armature<S: Scalar>(model: &Model, values: &[JointTermValues], d: &mut DMatrix<S>) {
    add_armature_after(model, values, d, 0);
}

/// [`add_armature`] to a `d` whose first `lead` rows and columns come before the joints' (a
/// floating base's six).
pub fn add_armature_after<S: Scalar>(
    model: &Model,
    values: &[JointTermValues],
    d: &mut DMatrix<S>,
    lead: usize,
) {
    if !model.joint_terms().has(JointTermKind::Armature) {
        return;
    }
    for (j, value) in values.iter().enumerate().take(model.dof()) {
        let k = lead + j;
        d[(k, k)] = d[(k, k)] + S::from_f64(value.armature);
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
