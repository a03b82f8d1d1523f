//! The rows of a robot with contacts (`ContactDynamics`), traced by either tracer from what it
//! has: the contacts' frame motions at the symbolic state, the factored mass matrix, and (for
//! the derivatives) the tree the motions come from.

use super::quantities::{Coefficient, QuantityKind};
use super::trace::{ids, inputs, matrix_ids, pair_ids};
use super::trace_contact_derivatives::{contact_derivatives, Tree};
use crate::dynamics::constrained::{constraint_rows, ContactMotion, OriginRates};
use crate::dynamics::tree_ldl::TreeLdl;
use crate::dynamics::FrameMotion;
use crate::model::Model;
use crate::scalar::Scalar;
use crate::symbolic::{Expr, Graph, Id, Node};
use dyngen_runtime::ProximalSettings;
use nalgebra::DMatrix;

/// How the contact forces `λ` the derivative rows take are named in the graph: `lambda0`, …
/// They are created here, after every other input, so neither tracer carries them;
/// [`ContactInputs::of`] finds them again.
const FORCE_PREFIX: &str = "lambda";
/// The proximal iterations `contact_proximal_solve` runs in its code, untested between them.
const UNROLLED_ITERATIONS: usize = ProximalSettings::UNROLLED_ITERATIONS;
/// How the rows' target the one-call solve takes is named in the graph: `target0`, …
const TARGET_PREFIX: &str = "target";

/// A frame's rates at `a = 0` (`Model::frames()[k]`, its motion) as a tracer has them.
pub(super) type RatesAtRest<'a> = dyn Fn(usize, &FrameMotion<Expr>) -> OriginRates<Expr> + 'a;

/// What a tracer hands the contacts' rows: the state's velocity and acceleration inputs, the
/// factored mass matrix at the state, the tree (fixed or floating) the frames move with, and
/// how it traces the force forward dynamics solves for without contacts, `τ − b` (`τ` its own
/// input, `b` the bias with the joint-level terms, as forward dynamics computes it): called
/// after every other row is traced, so that rows traced before keep their node ids. Where the tracer can take a frame's rates at `a = 0` from the bias pass that forward
/// dynamics runs anyway (`rates_at_rest(frame, motion)`), the drift costs a few operations per
/// contact instead of a `J̇` along its chain.
pub(super) struct ContactState<'a> {
    pub qd: &'a [Expr],
    pub a: &'a [Expr],
    pub mass: &'a TreeLdl<Expr>,
    pub tree: Tree<'a>,
    pub free_force: &'a dyn Fn() -> Vec<Expr>,
    pub rates_at_rest: Option<&'a RatesAtRest<'a>>,
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
    let mut motions = ContactMotion::of(contacts, motion);
    if let Some(rates) = state.rates_at_rest {
        for (m, c) in motions.iter_mut().zip(contacts) {
            let to = (c.to.zip(m.to.as_ref())).map(|(k, to)| rates(k, to));
            m.rates = Some((rates(c.frame, &m.frame), to));
        }
    }
    let rows = constraint_rows(contacts, &motions, state.qd);
    let response = state.mass.solve_matrix(&rows.jacobian.transpose());
    let forces = inputs(FORCE_PREFIX, model.contact_rows());
    let derivatives = contact_derivatives(model, &state, &forces);
    // Traced after the rows above, so that they keep their node ids.
    let (delassus, _) = state.mass.congruence(&rows.jacobian);
    // `M⁻¹ = L⁻¹ Δ⁻¹ L⁻ᵀ` (`TreeLdl`): with `z = L⁻ᵀ (τ − b)` and the rows' `Y = L⁻ᵀ Jᵀ`
    // (`K`'s own), `J a_free = Yᵀ Δ⁻¹ z` and `a_free + M⁻¹ Jᵀ λ = L⁻¹ Δ⁻¹ (z + Y λ)`: one
    // half-solve of each kind where a solve for `a_free` and another for `M⁻¹ Jᵀ λ` take two.
    let half = state.mass.solve_transposed_factor(&(state.free_force)());
    let free_acceleration = state.mass.finish_solve(&half);
    let y: Vec<Vec<Expr>> = (0..rows.jacobian.nrows())
        .map(|r| {
            (state.mass).solve_transposed_factor(&rows.jacobian.row(r).iter().copied().collect::<Vec<_>>())
        })
        .collect();
    let scaled_half: Vec<Expr> = (half.iter().zip(state.mass.inv_pivot()))
        .map(|(&z, &inv)| z * inv)
        .collect();
    let matrices: Vec<Id> = [&rows.jacobian, &response, &delassus]
        .into_iter()
        .flat_map(matrix_ids)
        .collect();
    let system: Vec<Id> = (matrices.iter().copied())
        .chain(ids(&rows.drift))
        .chain(ids(&free_acceleration))
        .collect();
    // The solves in one call, their settings inputs created after every row above.
    let target = inputs(TARGET_PREFIX, model.contact_rows());
    let [kd, mu, damping, restitution] = [
        Coefficient::VelocityGain,
        Coefficient::Regularisation,
        Coefficient::Damping,
        Coefficient::Restitution,
    ]
    .map(|c| Expr::input(c.name()));
    let jacobian = &rows.jacobian;
    let velocity = product(jacobian, state.qd);
    let free_rows: Vec<Expr> = (y.iter())
        .map(|row| (row.iter().zip(&scaled_half)).fold(Expr::zero(), |sum, (&a, &b)| sum + a * b))
        .collect();
    let rhs: Vec<Expr> = (0..target.len())
        .map(|i| target[i] - rows.drift[i] - kd * velocity[i] - free_rows[i])
        .collect();
    let regularised = dense_factor(&delassus, mu);
    // `L⁻¹ Δ⁻¹ (from + Y λ)`: `a_free + M⁻¹ Jᵀ λ` from `z`, `M⁻¹ Jᵀ λ` from zero.
    let moved_by = |from: &[Expr], lambda: &[Expr]| {
        let sum: Vec<Expr> = (0..from.len())
            .map(|k| (y.iter().zip(lambda)).fold(from[k], |sum, (row, &l)| sum + row[k] * l))
            .collect();
        state.mass.finish_solve(&sum)
    };
    // `steps` proximal iterations from `start` (zero forces if `None`), `(K + μ I) λ_{k+1} =
    // rhs + μ λ_k`, then the velocity or acceleration `moved(λ)`: the outputs of a
    // `ContactStep`.
    let steps = |moved: &dyn Fn(&[Expr]) -> Vec<Expr>, rhs: &[Expr], start: Option<&[Expr]>, steps: usize| {
        let zero = vec![Expr::zero(); rhs.len()];
        let (mut previous, mut lambda) = (zero.clone(), start.unwrap_or(&zero).to_vec());
        for _ in 0..steps {
            previous = lambda;
            let shifted: Vec<Expr> = rhs.iter().zip(&previous).map(|(&r, &l)| r + mu * l).collect();
            lambda = regularised.solve(&shifted);
        }
        (ids(&moved(&lambda)).into_iter())
            .chain(ids(&lambda))
            .chain(ids(&previous))
            .chain(matrix_ids(&delassus))
            .chain(ids(&regularised.pivots))
            .chain(ids(rhs))
            .collect::<Vec<Id>>()
    };
    let accelerated = |lambda: &[Expr]| moved_by(&half, lambda);
    let solve = steps(&accelerated, &rhs, Some(&forces), 1);
    let proximal = steps(&accelerated, &rhs, Some(&forces), UNROLLED_ITERATIONS);
    let impact: Vec<Expr> = velocity
        .iter()
        .map(|&v| -(Expr::one() + restitution) * v)
        .collect();
    let zero = vec![Expr::zero(); half.len()];
    let impacted = |lambda: &[Expr]| {
        let change = moved_by(&zero, lambda);
        (state.qd.iter().zip(&change))
            .map(|(&v, &d)| v + d)
            .collect::<Vec<Expr>>()
    };
    let impulse = steps(&impacted, &impact, None, 1);
    // Given forces need no `Y`: `L⁻¹ Δ⁻¹ (z + L⁻ᵀ Jᵀ λ)`, one leaves-up half for `Jᵀ λ`.
    let applied = state
        .mass
        .solve_transposed_factor(&transposed_product(jacobian, &forces));
    let pushed: Vec<Expr> = half.iter().zip(&applied).map(|(&z, &f)| z + f).collect();
    let forward = state.mass.finish_solve(&pushed);
    let damped = dense_factor(&delassus, damping);
    let inertia: Vec<Id> = (matrix_ids(&damped.inverse_by_ancestors()).into_iter())
        .chain(ids(&damped.pivots))
        .chain((0..delassus.nrows()).map(|i| delassus[(i, i)].id()))
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
        (QuantityKind::ContactSolve, solve),
        (QuantityKind::ContactProximalSolve, proximal),
        (QuantityKind::ContactImpulse, impulse),
        (QuantityKind::ContactForwardDynamics, ids(&forward)),
        (QuantityKind::ContactInertia, inertia),
    ]
}

/// `K + μ I` factored as `L Δ Lᵀ`, a dense factor (a chain, every row the parent of the next):
/// no square root, so the symbolic engine's four operations suffice, and each pivot inverted
/// once.
fn dense_factor(delassus: &DMatrix<Expr>, mu: Expr) -> TreeLdl<Expr> {
    let n = delassus.nrows();
    let mut regularised = delassus.clone();
    for i in 0..n {
        regularised[(i, i)] = regularised[(i, i)] + mu;
    }
    TreeLdl::factor_tree((0..n).map(|k| k.checked_sub(1)).collect(), &regularised)
}

/// `J x`, the zeros of `J` folding away.
fn product(jacobian: &DMatrix<Expr>, x: &[Expr]) -> Vec<Expr> {
    (0..jacobian.nrows())
        .map(|r| (0..x.len()).fold(Expr::zero(), |sum, c| sum + jacobian[(r, c)] * x[c]))
        .collect()
}

/// `Jᵀ λ`.
fn transposed_product(jacobian: &DMatrix<Expr>, lambda: &[Expr]) -> Vec<Expr> {
    (0..jacobian.ncols())
        .map(|c| (0..lambda.len()).fold(Expr::zero(), |sum, r| sum + jacobian[(r, c)] * lambda[r]))
        .collect()
}

/// The inputs the contacts' rows create after every other, found again by their names: the
/// forces `λ` and the rows' target in row order, and the solves' coefficients (empty without
/// contacts).
#[derive(Clone, Debug, Default)]
pub struct ContactInputs {
    pub forces: Vec<Id>,
    pub target: Vec<Id>,
    pub coefficients: Vec<(Coefficient, Id)>,
}

impl ContactInputs {
    pub(super) fn of(graph: &Graph) -> ContactInputs {
        let names = graph.input_names();
        let inputs = (0..graph.len())
            .map(|i| Id(i as u32))
            .filter_map(|id| match graph.node(id) {
                Node::Input(k) => Some((names[k as usize].as_str(), id)),
                _ => None,
            });
        let mut found = ContactInputs::default();
        let (mut forces, mut target) = (Vec::new(), Vec::new());
        for (name, id) in inputs {
            let row = |prefix: &str| name.strip_prefix(prefix)?.parse::<usize>().ok();
            if let Some(row) = row(FORCE_PREFIX) {
                forces.push((row, id));
            } else if let Some(row) = row(TARGET_PREFIX) {
                target.push((row, id));
            } else if let Some(c) = Coefficient::ALL.into_iter().find(|c| c.name() == name) {
                found.coefficients.push((c, id));
            }
        }
        forces.sort_unstable();
        target.sort_unstable();
        found.forces = forces.into_iter().map(|(_, id)| id).collect();
        found.target = target.into_iter().map(|(_, id)| id).collect();
        found
    }

    /// The input of coefficient `c`, if the graph has one.
    pub fn coefficient(&self, c: Coefficient) -> Option<Id> {
        self.coefficients.iter().find(|(k, _)| *k == c).map(|&(_, id)| id)
    }
}
