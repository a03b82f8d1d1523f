//! The rows of a robot with contacts (`ContactDynamics`), traced by either tracer from what it
//! has: the contacts' frame motions at the symbolic state and the factored mass matrix.

use super::quantities::QuantityKind;
use super::trace::{ids, matrix_ids};
use crate::dynamics::constrained::{constraint_rows, ContactMotion};
use crate::dynamics::tree_ldl::TreeLdl;
use crate::dynamics::FrameMotion;
use crate::model::Model;
use crate::symbolic::{Expr, Id};

/// The outputs of each row of [`QuantityKind::CONTACTS`], in that order: the stacked rows
/// `J`, their drift along `qd`, and `M⁻¹ Jᵀ` from the factored mass matrix `mass`.
/// `motion(frame)` is the motion of `Model::frames()[frame]`.
pub(super) fn contact_outputs(
    model: &Model,
    motion: impl Fn(usize) -> FrameMotion<Expr>,
    qd: &[Expr],
    mass: &TreeLdl<Expr>,
) -> Vec<(QuantityKind, Vec<Id>)> {
    let contacts = model.contacts();
    let motions = ContactMotion::of(contacts, motion);
    let rows = constraint_rows(contacts, &motions, qd);
    let response = mass.solve_matrix(&rows.jacobian.transpose());
    vec![
        (QuantityKind::ContactJacobian, matrix_ids(&rows.jacobian)),
        (QuantityKind::ContactDrift, ids(&rows.drift)),
        (QuantityKind::ContactResponse, matrix_ids(&response)),
    ]
}
