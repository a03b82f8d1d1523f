//! Derivatives of inverse and forward dynamics with respect to `q` and `q̇`, by forward-mode
//! differentiation of the inverse-dynamics recursion itself: it is run on [`Dual`] numbers whose
//! tangents hold [`LANES`] directions at once, one per lane (`q_0 … q_7` in one run, `q̇_0 … q̇_7`
//! in another; more joints take more groups of eight), so the derivatives are the same
//! algorithm, written once.
//!
//! Symbolically (with `S = Expr`) every run's values are the nodes of the plain recursion, and
//! each tangent is one lane-vector node (`f64x8` in generated code). Tangents that the tree makes
//! zero fold away as they are built, and a tangent along a single direction stays a scalar in
//! its lane (joint `j`'s transform moves only with `q_j`); the vectors fill where directions
//! meet (a body's motion depends on every joint above it, a joint's torque on every body below),
//! so one vector operation does the work of up to eight scalar ones. A joint's transform is
//! differentiated along its own coordinate through its motion subspace
//! (`seeded_frame`: `d(X m)/dq = −S × X m`), not through its sines and cosines.
//! Running the directions one at a time instead gives the sparsest scalar program (the flattened cost of the analytical
//! derivatives of Carpentier & Mansard, 2018), but a long and irregular one: the Panda's runs
//! 1.5–2.2× faster in lanes (`BENCHMARKS.md`), the UR5's, already sparse, no faster.
//!
//! Which of the two pays depends on the robot ([`Directions`]): the generator traces both and
//! keeps the cheaper (`generate::trace`); the generic `f64` dynamics use the lanes.
//!
//! The velocity derivative is taken the same way (lanes over `q̇_j`, with the joint-level
//! terms of the model, whose Coulomb friction without smoothing, `sign(q̇)`, has derivative zero
//! where it exists). It could also be `2 C(q, q̇)` (`τ = D q̈ + C q̇ + g` with the
//! Christoffel-consistent `C`, `Γ_ijk = Γ_ikj`), which [`Directions::OneByOne`] uses; next to
//! lanes over `q`, lanes over `q̇` measured a little faster than `2C` on the Panda.
//!
//! Forward dynamics needs no differentiation of its own: with `q̈ = FD(q, q̇, τ)` fixed,
//! `D ∂q̈/∂x = −∂τ/∂x |_{q̈}`, so `∂q̈/∂x = −D⁻¹ ∂ID/∂x` evaluated at that `q̈`, solved with the
//! factors forward dynamics already has, on the lane tangents (all columns of a group at once).

use super::coriolis::coriolis_matrix;
use super::forward_dynamics::{factor_mass_matrix, forward_dynamics_factored};
use super::joint::{joint_factored_transforms, joint_transforms};
use super::joint_terms::joint_term_torques;
use super::newton_euler::inverse_dynamics;
use super::seeded_frame::seeded_frames;
use super::tree_ldl::TreeLdl;
use crate::model::{JointTermValues, Model};
use crate::scalar::Scalar;
use crate::scalar_dual::{seeded, Dual, LaneScalar, LaneTangent, Tangent, LANES};
use crate::spatial::{CompositeFrame, RigidInertia, Vec3};
use nalgebra::DMatrix;

/// How the derivatives carry their directions through the recursion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Directions {
    /// One scalar run per `q_j`, and `∂τ/∂q̇ = 2 C(q, q̇)` (with the joint-level terms'
    /// diagonal from one scalar run each): the sparsest scalar program, best where every
    /// direction's tangents are few (the UR5).
    OneByOne,
    /// `LANES` directions per run, one per lane, for `q` and for `q̇`: fewer, wider
    /// operations, best where the directions' tangents overlap (the Panda).
    Lanes,
}

/// Which joint transforms the derivatives carry their tangents through.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Placements {
    /// Each joint's transform multiplied out (`joint_transforms`).
    Multiplied,
    /// Each joint's placement and own motion one after the other
    /// (`joint_factored_transforms`): cheaper where placements are tilted.
    Factored,
}

/// Inverse dynamics on dual numbers through the joints' frames seeded by `seed` (see
/// [`seeded_frames`]), in the form `placements` says.
fn seeded_inverse_dynamics<S: Scalar, T: Tangent<S>>(
    placements: Placements,
    model: &Model,
    q: &[S],
    seed: impl Fn(usize) -> Option<T>,
    inertias: &[RigidInertia<Dual<S, T>>],
    qd: &[Dual<S, T>],
    qdd: &[Dual<S, T>],
) -> Vec<Dual<S, T>> {
    match placements {
        Placements::Multiplied => {
            let x = seeded_frames(model, q, joint_transforms, seed);
            inverse_dynamics(model, &x, inertias, qd, qdd)
        }
        Placements::Factored => {
            let x = seeded_frames(model, q, joint_factored_transforms, seed);
            inverse_dynamics(model, &x, inertias, qd, qdd)
        }
    }
}

/// A dual number whose tangent holds [`LANES`] directions.
type Lanes<S> = Dual<S, <S as LaneScalar>::Lanes>;

fn constant<S: LaneScalar>(v: &[S]) -> Vec<Lanes<S>> {
    v.iter().map(|&x| Dual::constant(x)).collect()
}

/// `i` on dual numbers of zero tangent.
pub fn lift_inertia<S: Scalar, T: Tangent<S>>(i: &RigidInertia<S>) -> RigidInertia<Dual<S, T>> {
    RigidInertia {
        m: Dual::constant(i.m),
        h: Vec3(i.h.0.map(Dual::constant)),
        i: i.i.map(Dual::constant),
    }
}

/// The tangents of `τ` along `q_j` and along `q̇_j`, for the group of directions starting at
/// coordinate `first` (direction `first + k` in lane `k`).
struct Group<T> {
    first: usize,
    d_q: Vec<T>,
    d_qd: Vec<T>,
}

/// Inverse dynamics (with the model's joint-level terms) on lane duals, one group of
/// [`LANES`] directions at a time.
fn tangent_groups<S: LaneScalar>(
    placements: Placements,
    model: &Model,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    qdd: &[S],
) -> Vec<Group<S::Lanes>> {
    let n = model.dof();
    let dual_inertias: Vec<RigidInertia<Lanes<S>>> = inertias.iter().map(lift_inertia).collect();
    let (qd_const, qdd_const) = (constant(qd), constant(qdd));
    let has_joint_terms = !model.joint_terms().kinds.is_empty();
    (0..n)
        .step_by(LANES)
        .map(|first| {
            // Joint-level terms depend on q̇ and q̈ only.
            let seed = |c| {
                (first..first + LANES)
                    .contains(&c)
                    .then(|| S::Lanes::unit(c - first, S::one()))
            };
            let d_q =
                seeded_inverse_dynamics(placements, model, q, seed, &dual_inertias, &qd_const, &qdd_const);
            let qd_seeded = seeded(qd, first, LANES);
            let mut d_qd = seeded_inverse_dynamics(
                placements,
                model,
                q,
                |_| None,
                &dual_inertias,
                &qd_seeded,
                &qdd_const,
            );
            if has_joint_terms {
                let joint = joint_term_torques(model, joint_values, &qd_seeded, &qd_seeded, &qdd_const);
                d_qd = d_qd.into_iter().zip(joint).map(|(r, j)| r + j).collect();
            }
            let tangents = |tau: Vec<Lanes<S>>| tau.into_iter().map(|t| t.tangent).collect();
            Group {
                first,
                d_q: tangents(d_q),
                d_qd: tangents(d_qd),
            }
        })
        .collect()
}

/// The `n × n` matrix whose column `first + k` is lane `k` of the groups' tangents.
fn columns<S: LaneScalar>(
    n: usize,
    groups: &[Group<S::Lanes>],
    pick: impl Fn(&Group<S::Lanes>) -> &Vec<S::Lanes>,
) -> DMatrix<S> {
    let mut m = DMatrix::from_element(n, n, S::zero());
    for g in groups {
        for (i, t) in pick(g).iter().enumerate() {
            for j in g.first..n.min(g.first + LANES) {
                m[(i, j)] = t.lane(j - g.first);
            }
        }
    }
    m
}

/// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics `τ(q, q̇, q̈)`; entry `(i, j)` is `∂τ_i/∂x_j`.
/// (`∂τ/∂q̈ = D`.)
pub fn inverse_dynamics_derivatives<S: LaneScalar>(
    model: &Model,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    qdd: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    inverse_dynamics_derivatives_by(
        Directions::Lanes,
        Placements::Multiplied,
        model,
        q,
        inertias,
        joint_values,
        qd,
        qdd,
    )
}

/// `inverse_dynamics_derivatives` with the directions carried as `directions` says, through
/// the transforms `placements` says.
#[allow(clippy::too_many_arguments)]
pub fn inverse_dynamics_derivatives_by<S: LaneScalar>(
    directions: Directions,
    placements: Placements,
    model: &Model,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    qdd: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let n = model.dof();
    match directions {
        Directions::OneByOne => one_by_one(placements, model, q, inertias, joint_values, qd, qdd),
        Directions::Lanes => {
            let groups = tangent_groups(placements, model, q, inertias, joint_values, qd, qdd);
            (columns(n, &groups, |g| &g.d_q), columns(n, &groups, |g| &g.d_qd))
        }
    }
}

/// `v` with the derivative taken along its entry `j` (one direction).
fn seeded_one<S: Scalar>(v: &[S], j: usize) -> Vec<Dual<S>> {
    v.iter()
        .enumerate()
        .map(|(i, &x)| match i == j {
            true => Dual::variable(x),
            false => Dual::constant(x),
        })
        .collect()
}

/// [`Directions::OneByOne`].
fn one_by_one<S: Scalar>(
    placements: Placements,
    model: &Model,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    qdd: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let n = model.dof();
    let dual_inertias: Vec<RigidInertia<Dual<S>>> = inertias.iter().map(lift_inertia).collect();
    let constant = |v: &[S]| -> Vec<Dual<S>> { v.iter().map(|&x| Dual::constant(x)).collect() };
    let (qd_const, qdd_const) = (constant(qd), constant(qdd));
    let mut d_q = DMatrix::from_element(n, n, S::zero());
    for j in 0..n {
        let seed = |c| (c == j).then(S::one);
        let tau = seeded_inverse_dynamics(placements, model, q, seed, &dual_inertias, &qd_const, &qdd_const);
        for (i, t) in tau.iter().enumerate() {
            d_q[(i, j)] = t.tangent;
        }
    }
    let two = S::from_f64(2.0);
    let mut d_qd = coriolis_matrix(model, &joint_transforms(model, q), inertias, qd).map(|c| two * c);
    if !model.joint_terms().kinds.is_empty() {
        for j in 0..n {
            let seeded_qd = seeded_one(qd, j);
            let joint = joint_term_torques(model, joint_values, &seeded_qd, &seeded_qd, &qdd_const);
            d_qd[(j, j)] = d_qd[(j, j)] + joint[j].tangent;
        }
    }
    (d_q, d_qd)
}

/// `(∂q̈/∂q, ∂q̈/∂q̇)` of forward dynamics `q̈(q, q̇, τ)`. (`∂q̈/∂τ = D⁻¹`.)
pub fn forward_dynamics_derivatives<S: LaneScalar>(
    model: &Model,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    tau: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    forward_dynamics_derivatives_by(
        Directions::Lanes,
        Placements::Multiplied,
        model,
        q,
        inertias,
        joint_values,
        qd,
        tau,
    )
}

/// `forward_dynamics_derivatives` with the directions carried as `directions` says, through
/// the transforms `placements` says.
#[allow(clippy::too_many_arguments)]
pub fn forward_dynamics_derivatives_by<S: LaneScalar>(
    directions: Directions,
    placements: Placements,
    model: &Model,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    qd: &[S],
    tau: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let at = ForwardAt {
        directions,
        placements,
        model,
        q,
        inertias,
        joint_values,
        qd,
        tau,
    };
    match placements {
        Placements::Multiplied => at.through(&joint_transforms(model, q)),
        Placements::Factored => at.through(&joint_factored_transforms(model, q)),
    }
}

/// The arguments of [`forward_dynamics_derivatives_by`].
struct ForwardAt<'a, S> {
    directions: Directions,
    placements: Placements,
    model: &'a Model,
    q: &'a [S],
    inertias: &'a [RigidInertia<S>],
    joint_values: &'a [JointTermValues],
    qd: &'a [S],
    tau: &'a [S],
}

impl<S: LaneScalar> ForwardAt<'_, S> {
    /// The derivatives with `x` the joint transforms in the form `placements` says.
    fn through<X: CompositeFrame<S>>(&self, x: &[X]) -> (DMatrix<S>, DMatrix<S>) {
        let (model, q, qd) = (self.model, self.q, self.qd);
        let (inertias, joint_values, placements) = (self.inertias, self.joint_values, self.placements);
        let n = model.dof();
        let factor = factor_mass_matrix(model, x, inertias, joint_values);
        let qdd = forward_dynamics_factored(model, x, inertias, joint_values, &factor, qd, self.tau);
        if self.directions == Directions::OneByOne {
            let (d_q, d_qd) = one_by_one(placements, model, q, inertias, joint_values, qd, &qdd);
            let minus_solve = |m: DMatrix<S>| factor.solve_matrix(&m.map(|v| -v));
            return (minus_solve(d_q), minus_solve(d_qd));
        }
        // `D y = −t` for every lane of a group at once.
        let lifted = lift_factor(&factor);
        let groups: Vec<Group<S::Lanes>> =
            tangent_groups(placements, model, q, inertias, joint_values, qd, &qdd)
                .into_iter()
                .map(|g| Group {
                    first: g.first,
                    d_q: minus_solved(&lifted, &g.d_q),
                    d_qd: minus_solved(&lifted, &g.d_qd),
                })
                .collect();
        (columns(n, &groups, |g| &g.d_q), columns(n, &groups, |g| &g.d_qd))
    }
}

/// `factor` on lane duals, for [`minus_solved`].
pub fn lift_factor<S: LaneScalar>(factor: &TreeLdl<S>) -> TreeLdl<Lanes<S>> {
    factor.map(Dual::<S, S::Lanes>::constant)
}

/// `y` with `D y = −t` in every lane at once, `lifted` being `D`'s factor on lane duals: the
/// solve on duals of value zero whose tangents are the right-hand sides (the values fold away
/// symbolically).
pub fn minus_solved<S: LaneScalar>(lifted: &TreeLdl<Lanes<S>>, t: &[S::Lanes]) -> Vec<S::Lanes> {
    let b: Vec<Lanes<S>> = t
        .iter()
        .map(|&t| Dual {
            value: S::zero(),
            tangent: -t,
        })
        .collect();
    lifted.solve(&b).into_iter().map(|y| y.tangent).collect()
}
