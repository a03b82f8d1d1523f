//! The rows of a robot with contacts (`ContactDynamics`), traced by either tracer from what it
//! has: the contacts' frame motions at the symbolic state, the factored mass matrix, and (for
//! the derivatives) the tree the motions come from.

use super::quantities::QuantityKind;
use super::trace::{ids, inputs, matrix_ids, pair_ids};
use super::trace_contact_derivatives::{contact_derivatives, Tree};
use crate::dynamics::constrained::{constraint_rows, ContactMotion};
use crate::dynamics::tree_ldl::TreeLdl;
use crate::dynamics::FrameMotion;
use crate::model::Model;
use crate::symbolic::{Expr, Graph, Id, Node};

/// How the contact forces `λ` the derivative rows take are named in the graph: `lambda0`, …
/// They are created here, after every other input, so neither tracer carries them;
/// [`force_inputs`] finds them again.
const FORCE_PREFIX: &str = "lambda";

/// What a tracer hands the contacts' rows: the state's velocity and acceleration inputs, the
/// factored mass matrix at the state, the tree (fixed or floating) the frames move with, and
/// how it traces forward dynamics without contacts (`τ` its own input) with a factored mass
/// matrix: called after every other row is traced, so that rows traced before keep their node
/// ids.
pub(super) struct ContactState<'a> {
    pub qd: &'a [Expr],
    pub a: &'a [Expr],
    pub mass: &'a TreeLdl<Expr>,
    pub tree: Tree<'a>,
    pub free_acceleration: &'a dyn Fn(&TreeLdl<Expr>) -> Vec<Expr>,
}

/// The outputs of each row of [`QuantityKind::CONTACTS`], in that order: the stacked rows
/// `J`, their drift along `qd`, `M⁻¹ Jᵀ` from the factored mass matrix, the derivatives the
/// runtime assembles `∂a/∂x` and `∂λ/∂x` from (`trace_contact_derivatives.rs`), then what the
/// solves read in one call: the Delassus matrix `K = J M⁻¹ Jᵀ` (alone, with `J` and `M⁻¹ Jᵀ`,
/// and with the drift and the free acceleration too). `K` comes from the factors
/// ([`TreeLdl::congruence`]), which share `M⁻¹ Jᵀ`'s operations and follow the rows' sparsity.
/// `motion(frame)` is the motion of `Model::frames()[frame]`.
pub(super) fn contact_outputs(
    model: &Model,
    motion: impl Fn(usize) -> FrameMotion<Expr>,
    state: ContactState<'_>,
) -> Vec<(QuantityKind, Vec<Id>)> {
    let contacts = model.contacts();
    let motions = ContactMotion::of(contacts, motion);
    let rows = constraint_rows(contacts, &motions, state.qd);
    let response = state.mass.solve_matrix(&rows.jacobian.transpose());
    let forces = inputs(FORCE_PREFIX, model.contact_rows());
    let derivatives = contact_derivatives(model, &state, &forces);
    // Traced after the rows above, so that they keep their node ids.
    let (delassus, _) = state.mass.congruence(&rows.jacobian);
    let free_acceleration = (state.free_acceleration)(state.mass);
    let matrices: Vec<Id> = [&rows.jacobian, &response, &delassus]
        .into_iter()
        .flat_map(matrix_ids)
        .collect();
    let system: Vec<Id> = (matrices.iter().copied())
        .chain(ids(&rows.drift))
        .chain(ids(&free_acceleration))
        .collect();
    vec![
        (QuantityKind::ContactJacobian, matrix_ids(&rows.jacobian)),
        (QuantityKind::ContactDrift, ids(&rows.drift)),
        (QuantityKind::ContactResponse, matrix_ids(&response)),
        (
            QuantityKind::ContactForwardDynamicsDerivatives,
            pair_ids(derivatives.forward_dynamics),
        ),
        (
            QuantityKind::ContactAccelerationDerivatives,
            pair_ids(derivatives.acceleration),
        ),
        (QuantityKind::ContactDelassus, matrix_ids(&delassus)),
        (QuantityKind::ContactMatrices, matrices),
        (QuantityKind::ContactSystem, system),
    ]
}

/// The contact forces' inputs of `graph`, in row order (none without contacts).
pub(super) fn force_inputs(graph: &Graph) -> Vec<Id> {
    let names = graph.input_names();
    let mut found: Vec<(usize, Id)> = (0..graph.len())
        .map(|i| Id(i as u32))
        .filter_map(|id| match graph.node(id) {
            Node::Input(k) => {
                let row = names[k as usize].strip_prefix(FORCE_PREFIX)?.parse().ok()?;
                Some((row, id))
            }
            _ => None,
        })
        .collect();
    found.sort_unstable();
    found.into_iter().map(|(_, id)| id).collect()
}
