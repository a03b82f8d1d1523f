//! The derivative rows of a robot with contacts: what the runtime's
//! `constrained_forward_dynamics_derivatives` assembles `∂a/∂x` and `∂λ/∂x` from.
//!
//! At the solution `(a, λ)`, `F = ID(q, ν, a) − Jᵀ λ − τ = 0` and `G = J a + drift = 0` (the
//! Baumgarte terms the runtime adds, `model/src/dynamics/constrained/derivatives.rs` for the
//! method). Along a state direction `x`, with `a` and `λ` held, their tangents `Ḟ` and `Ġ` give
//! the solution's change from the constrained system `M ȧ − Jᵀ λ̇ = −Ḟ`, `J ȧ = −Ġ`. Two rows
//! hold everything of the robot in it:
//! - `contact_forward_dynamics_derivatives`: `Y = −M⁻¹ ∂F/∂x`, the change of
//!   forward dynamics with the forces `λ` held. `∂ID/∂x` is inverse dynamics' own derivative
//!   (the same nodes as its row's), `∂(Jᵀ λ)/∂q` comes from the rows on lane duals, and `M⁻¹`
//!   is applied through the tree factor forward dynamics uses: sparse where a dense `M⁻¹`
//!   would cost `NV³`.
//! - `contact_acceleration_derivatives`: `∂G/∂x`, the rows' acceleration
//!   `J a + drift` on lane duals, [`LANES`] directions per run.
//!
//! What is left is `NC`-sized dense algebra on the solve's factor (`λ̇ = −K⁻¹ (Ġ + J Y)`,
//! `ȧ = Y + M⁻¹ Jᵀ λ̇`), which the runtime does once for every column.

use super::trace_contacts::ContactState;
use crate::dynamics::constrained::{constraint_rows, ConstraintRows, ContactMotion};
use crate::dynamics::derivatives::{lift_factor, minus_solved};
use crate::dynamics::floating::{self as algorithms, FloatingBase};
use crate::dynamics::tree_ldl::TreeLdl;
use crate::dynamics::{self, Directions, FrameMotion, Placements};
use crate::model::{JointTermValues, Model};
use crate::scalar::Scalar;
use crate::scalar_dual::{Dual, LaneTangent, Tangent, LANES};
use crate::spatial::{Mat3, RigidInertia, Transform, Vec3};
use crate::symbolic::{Expr, LaneExpr};
use nalgebra::DMatrix;

/// A scalar with [`LANES`] directions.
type Lanes = Dual<Expr, LaneExpr>;

/// The tree the contacts' frames move with, as each tracer has it.
pub(super) enum Tree<'a> {
    /// A fixed base: the joints' coordinates, the bodies' inertias and joint-level terms.
    Fixed {
        q: &'a [Expr],
        inertias: &'a [RigidInertia<Expr>],
        joint_values: &'a [JointTermValues],
    },
    /// A floating base: its pose and inertia, the joints' coordinates, the bodies' inertias and
    /// joint-level terms.
    Floating {
        base: &'a FloatingBase<Expr>,
        q: &'a [Expr],
        inertias: &'a [RigidInertia<Expr>],
        joint_values: &'a [JointTermValues],
    },
}

/// The outputs of the two derivative rows, each `(∂/∂q, ∂/∂ν)`.
pub(super) struct ContactDerivatives {
    pub forward_dynamics: (DMatrix<Expr>, DMatrix<Expr>),
    pub acceleration: (DMatrix<Expr>, DMatrix<Expr>),
}

/// What one lane differentiates along: a configuration (in the tangent space) or a velocity,
/// by velocity index.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Direction {
    Configuration(usize),
    Velocity(usize),
}

/// Both rows (module docs), `forces` the inputs `λ`.
pub(super) fn contact_derivatives(
    model: &Model,
    state: &ContactState<'_>,
    forces: &[Expr],
) -> ContactDerivatives {
    let nv = state.qd.len();
    let rows = model.contact_rows();
    let (mut id_q, id_v) = inverse_dynamics_derivatives(model, state);
    let mut g_q = DMatrix::from_element(rows, nv, <Expr as Scalar>::zero());
    let mut g_v = DMatrix::from_element(rows, nv, <Expr as Scalar>::zero());
    let lambda: Vec<Lanes> = forces.iter().map(|&f| Dual::constant(f)).collect();
    let a: Vec<Lanes> = state.a.iter().map(|&x| Dual::constant(x)).collect();
    let runs = (0..nv).step_by(LANES).flat_map(|first| {
        let lanes = first..nv.min(first + LANES);
        [
            lanes.clone().map(Direction::Configuration).collect::<Vec<_>>(),
            lanes.map(Direction::Velocity).collect(),
        ]
    });
    for directions in runs {
        let r = rows_along(model, state, &directions);
        let configuration = matches!(directions[0], Direction::Configuration(_));
        for (k, &direction) in directions.iter().enumerate() {
            let c = match direction {
                Direction::Configuration(c) | Direction::Velocity(c) => c,
            };
            for row in 0..rows {
                // `G = J a + drift`: `J` moves with the configuration only.
                let mut g = r.drift[row];
                if configuration {
                    g = (0..nv).fold(g, |acc, i| acc + r.jacobian[(row, i)] * a[i]);
                }
                match configuration {
                    true => g_q[(row, c)] = g.tangent.lane(k),
                    false => g_v[(row, c)] = g.tangent.lane(k),
                }
            }
            if configuration {
                // `F` loses `∂(Jᵀ λ)/∂q`.
                for i in 0..nv {
                    let force = (0..rows).fold(Lanes::constant(<Expr as Scalar>::zero()), |acc, row| {
                        acc + r.jacobian[(row, i)] * lambda[row]
                    });
                    id_q[(i, c)] = id_q[(i, c)] - force.tangent.lane(k);
                }
            }
        }
    }
    let lifted = lift_factor(state.mass);
    ContactDerivatives {
        forward_dynamics: (
            minus_solved_columns(&lifted, &id_q),
            minus_solved_columns(&lifted, &id_v),
        ),
        acceleration: (g_q, g_v),
    }
}

/// `Y` with `M Y = −m`, [`LANES`] columns per solve: each group's columns packed into the
/// lanes of one vector per row, solved through `lifted` (`M`'s tree factor on lane duals) as
/// forward dynamics' derivatives are.
fn minus_solved_columns(lifted: &TreeLdl<Lanes>, m: &DMatrix<Expr>) -> DMatrix<Expr> {
    let mut y = m.clone();
    for first in (0..m.ncols()).step_by(LANES) {
        let columns = first..m.ncols().min(first + LANES);
        let packed: Vec<LaneExpr> = (0..m.nrows())
            .map(|i| {
                (columns.clone()).fold(LaneExpr::zero(), |acc, c| {
                    acc + LaneExpr::unit(c - first, m[(i, c)])
                })
            })
            .collect();
        for (i, solved) in minus_solved(lifted, &packed).into_iter().enumerate() {
            for c in columns.clone() {
                y[(i, c)] = solved.lane(c - first);
            }
        }
    }
    y
}

/// `(∂τ/∂q, ∂τ/∂ν)` of inverse dynamics at `(ν, a)`: the functions of inverse dynamics'
/// derivative row, on the same inputs (so the same nodes).
fn inverse_dynamics_derivatives(model: &Model, state: &ContactState<'_>) -> (DMatrix<Expr>, DMatrix<Expr>) {
    let (qd, a) = (state.qd, state.a);
    match state.tree {
        Tree::Fixed {
            q,
            inertias,
            joint_values,
        } => dynamics::inverse_dynamics_derivatives_by(
            Directions::Lanes,
            Placements::Multiplied,
            model,
            q,
            inertias,
            joint_values,
            qd,
            a,
        ),
        Tree::Floating {
            base,
            q,
            inertias,
            joint_values,
        } => algorithms::floating_inverse_dynamics_derivatives(model, base, q, inertias, joint_values, qd, a),
    }
}

/// The contacts' rows with the state moved along `directions` (direction `k` in lane `k`).
fn rows_along(model: &Model, state: &ContactState<'_>, directions: &[Direction]) -> ConstraintRows<Lanes> {
    let lane_of = |wanted: Direction| {
        (directions.iter().position(|&d| d == wanted)).map(|k| LaneExpr::unit(k, Expr::one()))
    };
    let seeded = |x: &[Expr], direction: fn(usize) -> Direction, offset: usize| -> Vec<Lanes> {
        (x.iter().enumerate())
            .map(|(c, &value)| Dual {
                value,
                tangent: lane_of(direction(c + offset)).unwrap_or_else(LaneExpr::zero),
            })
            .collect()
    };
    let v = seeded(state.qd, Direction::Velocity, 0);
    let motion: Box<dyn Fn(usize) -> FrameMotion<Lanes>> = match state.tree {
        Tree::Fixed { q, .. } => {
            let x = dynamics::joint_transforms(model, &seeded(q, Direction::Configuration, 0));
            let world = dynamics::body_poses(model, &x);
            let v = v.clone();
            Box::new(move |k| FrameMotion::new(model, &world, &v, &model.frames()[k]))
        }
        Tree::Floating { base, q, .. } => {
            let pose = seeded_pose(&base.pose, |k| lane_of(Direction::Configuration(k)));
            let x = dynamics::joint_transforms(model, &seeded(q, Direction::Configuration, 6));
            let world = algorithms::floating_body_poses(model, &pose, &x);
            let v = v.clone();
            Box::new(move |k| {
                let frame = &model.frames()[k];
                FrameMotion {
                    pose: dynamics::kinematics::frame_pose(Some(&pose), &world, frame),
                    jacobian: algorithms::floating_frame_jacobian(model, &pose, &world, frame),
                    jacobian_dot: algorithms::floating_frame_jacobian_dot(model, &pose, &world, &v, frame),
                }
            })
        }
    };
    let motions = ContactMotion::of(model.contacts(), motion);
    constraint_rows(model.contacts(), &motions, &v)
}

/// A floating base's pose moved along its six tangent directions (`q ⊕ δ`), direction `k` in
/// the lane `lane(k)` gives: `p + ε R e_k` (`k < 3`), `R (I + ε [e_{k−3}]×)` (`3 ≤ k < 6`).
fn seeded_pose(pose: &Transform<Expr>, lane: impl Fn(usize) -> Option<LaneExpr>) -> Transform<Lanes> {
    let r = &pose.rot.0;
    let sum = |terms: &mut dyn Iterator<Item = LaneExpr>| terms.fold(LaneExpr::zero(), |acc, t| acc + t);
    // `R [e]×` has column `j` equal to `R (e × e_j)`: entry `(i, j)` is `Σ_l R_il ε_{l e j}`.
    let rot = Mat3(std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let tangent = sum(&mut (0..3).filter_map(|e| {
                let lane = lane(3 + e)?;
                let entry = (0..3)
                    .map(|l| (l, levi_civita(l, e, j)))
                    .filter(|&(_, s)| s != 0.0)
                    .fold(<Expr as Scalar>::zero(), |acc, (l, s)| {
                        acc + Expr::from_f64(s) * r[i][l]
                    });
                Some(lane.scale(entry))
            }));
            Dual {
                value: r[i][j],
                tangent,
            }
        })
    }));
    let pos = Vec3(std::array::from_fn(|i| Dual {
        value: pose.pos.0[i],
        tangent: sum(&mut (0..3).filter_map(|k| Some(lane(k)?.scale(r[i][k])))),
    }));
    Transform { rot, pos }
}

/// `ε_{l k j}`: entry `(l, j)` of `[e_k]×`.
fn levi_civita(l: usize, k: usize, j: usize) -> f64 {
    match (l, k, j) {
        (0, 1, 2) | (1, 2, 0) | (2, 0, 1) => 1.0,
        (0, 2, 1) | (1, 0, 2) | (2, 1, 0) => -1.0,
        _ => 0.0,
    }
}
