//! One quantity as a generated function: planned, then emitted in one piece or in chunks.

use super::body::whole;
use super::chunks::chunked;
use super::header::{Emitted, Header};
use super::leaves::Leaves;
use super::plan::{Form, Plan};
use super::sizes::Sizes;
use crate::generate::quantities::QuantityKind;
use crate::generate::trace::{Quantity, SymbolicRobot};
use crate::symbolic::Id;
use proc_macro2::TokenStream;

/// `q` in `form`, its velocity-space arguments of `n` entries: in one piece where it computes at
/// most [`Sizes::chunk_values`] values and has no first stage to compile apart, else in chunks.
pub(super) fn function(
    robot: &SymbolicRobot,
    leaves: &Leaves,
    q: &Quantity,
    n: usize,
    form: Form,
    sizes: &Sizes,
) -> Emitted {
    let mut plan = Plan::new(robot, leaves, &q.outputs, form);
    let stage_end = first_stage(q, &plan, sizes).map(|stage| plan.put_first(&stage));
    let header = Header::new(&plan, q, n, sizes);
    let mut used = Vec::new();
    let atoms: Vec<TokenStream> = q.outputs.iter().map(|&o| plan.atom(o, &mut used)).collect();
    match plan.order.len() <= sizes.chunk_values && stage_end.is_none() {
        true => whole(&plan, q, &header, &atoms, used, sizes),
        false => chunked(&plan, q, &header, &atoms, used, stage_end, sizes),
    }
}

/// The values `q` computes in a first stage that is best compiled apart, if it has one: the
/// derivatives of forward dynamics first compute `q̈` (forward dynamics itself, the same nodes
/// as that function's outputs where both take the same form of the joint transforms), and only
/// then the tangents of inverse dynamics at that `q̈` and their solves. Compiled as one
/// function, LLVM interleaved the two, and the xArm's `∂q̈/∂x` ran slower than forward dynamics
/// and `∂τ/∂x` called one after the other (`BENCHMARKS.md`). Only where the tangents are lane
/// vectors (the UR5's, one direction at a time in scalars, ran slower split) and the function
/// would otherwise be whole (Solo-12's, in chunks anyway, ran slower with the stage as a chunk
/// of its own).
fn first_stage(q: &Quantity, plan: &Plan, sizes: &Sizes) -> Option<Vec<Id>> {
    let robot = plan.robot;
    let g = &robot.graph;
    let in_lanes = plan.order.iter().any(|&id| g.node(id).is_lanes());
    let whole = plan.order.len() <= sizes.chunk_values;
    if q.kind != QuantityKind::ForwardDynamicsDerivatives || plan.form != Form::Scalar || !in_lanes || !whole
    {
        return None;
    }
    let forward =
        (robot.quantities.iter()).find(|f| f.kind == QuantityKind::ForwardDynamics && !f.composed)?;
    let computed = |id: &Id| plan.names.contains_key(id);
    forward
        .outputs
        .iter()
        .all(computed)
        .then(|| forward.outputs.clone())
}
