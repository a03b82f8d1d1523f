//! Derivatives of floating-base inverse and forward dynamics in the tangent space, by
//! forward-mode differentiation of the floating recursion itself, as for a fixed base
//! (`dynamics::derivatives`), [`LANES`] directions per run, one per lane.
//!
//! Directions are Pinocchio's: a configuration moves as `q ⊕ δ` (`nv` columns). The base
//! translation's three columns are zero (nothing but the kinematics sees the base position,
//! and inverse dynamics is written in the base frame); a base rotation `δ_k` turns the base as
//! `R ↦ R exp([δ]×)`; a joint's coordinate moves its transform through its motion subspace
//! (`dynamics::seeded_frame`). A velocity direction seeds its entry of `ν`.
//!
//! Six of the base's directions reach only the base origin's classical acceleration
//! `a₀ = ν̇_v + ω × v − g_b`, through which the weight enters (`g_b = Rᵀ g`, gravity seen in
//! the base frame, as an upward acceleration): a rotation turns `g_b` by `g_b × e_k`, and the
//! base's linear velocity `v` enters nowhere else (bodies' accelerations do not depend on a
//! uniform velocity), moving `a₀` by `ω × e_k`. `τ` is affine in `a₀` with the coefficient it
//! has in `g(q)`, so those columns are the gravity recursion's derivatives along `g_b`
//! (`g_b × e_k` and `e_k × ω`), a recursion without velocities, instead of inverse dynamics'
//! in lanes: there, the six filled a second run that reached every body.
//!
//! Forward dynamics needs no differentiation of its own: with `ν̇ = FD(q, ν, τ)` fixed,
//! `∂ν̇/∂x = −D⁻¹ ∂τ/∂x` at that `ν̇`, solved with the tree factor forward dynamics uses, on
//! the lane tangents (all columns of a run at once). Its six columns through `a₀` need neither:
//! with the torques held the solution keeps `a₀` (`ν̇_v` moves by minus `a₀`'s change, and
//! nothing else moves), so a rotation's column is `[g_b × e_k; 0]` and a linear velocity's
//! `[e_k × ω; 0]`.
//!
//! A joint direction is a coordinate's: with mimic joints it moves every joint that follows it
//! (`seeded_frame`, the multiplier in its seed; the recursion takes `G q̇`). The joint-level
//! friction enters the velocity directions as on a fixed base; it does not see `q`, and the
//! armature only enters forward dynamics' factor.

use super::mass::{factor, floating_forward_dynamics};
use super::{floating_inverse_dynamics, floating_inverse_dynamics_in_field, FloatingBase};
use crate::dynamics::derivatives::{lift_factor, lift_inertia, minus_solved};
use crate::dynamics::joint::joint_transforms;
use crate::dynamics::joint_terms::with_joint_term_torques;
use crate::dynamics::seeded_frame::seeded_frames;
use crate::dynamics::slotine_li::gravity_vector;
use crate::model::{JointTermValues, Model};
use crate::scalar::Scalar;
use crate::scalar_dual::{Dual, LaneScalar, LaneTangent, Tangent, LANES};
use crate::spatial::{Mat3, RigidInertia, Transform, Vec3};
use nalgebra::DMatrix;

/// The base on dual numbers, constant: its directions enter through `ν` and the field
/// ([`run`]), not through its pose.
fn constant_base<S: Scalar, T: Tangent<S>>(base: &FloatingBase<S>) -> FloatingBase<Dual<S, T>> {
    FloatingBase {
        pose: base.pose.map(Dual::constant),
        inertia: lift_inertia(&base.inertia),
    }
}

/// `g_b = Rᵀ g` and the base's angular velocity `ω`, what the six directions through `a₀` turn
/// into columns (module docs).
fn weight_and_spin<S: Scalar>(model: &Model, base: &FloatingBase<S>, v: &[S]) -> (Vec3<S>, Vec3<S>) {
    (
        base.pose.rot.tr_mul_vec(&gravity_vector(model)),
        Vec3([v[3], v[4], v[5]]),
    )
}

/// The directions that act through `a₀` alone: the base rotations and linear velocities.
const FIELD_DIRECTIONS: [Direction; 6] = [
    Direction::Configuration(3),
    Direction::Configuration(4),
    Direction::Configuration(5),
    Direction::Velocity(0),
    Direction::Velocity(1),
    Direction::Velocity(2),
];

/// How direction `d` moves the field `g_b`, if it acts through `a₀` (module docs): a base
/// rotation by `g_b × e_k`, a base linear velocity by `e_k × ω` (the field is minus `a₀`).
fn field_rate<S: Scalar>(d: Direction, weight: &Vec3<S>, spin: &Vec3<S>) -> Option<Vec3<S>> {
    let unit = |k: usize| Mat3::identity().column(k);
    match d {
        Direction::Configuration(c @ 3..6) => Some(weight.cross(&unit(c - 3))),
        Direction::Velocity(c @ 0..3) => Some(unit(c).cross(spin)),
        _ => None,
    }
}

/// What one lane of a run differentiates along: the configuration moving as `q ⊕ e_c`, or the
/// velocity as `ν + e_c` (`c` a velocity index).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Direction {
    Configuration(usize),
    Velocity(usize),
}

/// One run of the recursion on lane duals: the direction of each lane, and `τ`'s tangents.
struct Run<T> {
    directions: Vec<Direction>,
    tangent: Vec<T>,
}

/// The directions of each run, at most [`LANES`] a run. A direction's tangents live on the
/// bodies it moves: a base angular velocity's on every body, a joint's on its subtree (and on
/// `τ`'s rows above it). So the base's three angular velocities come first, in a whole-tree run
/// whose free lanes then take joint directions at no extra cost; the other joints' directions
/// follow in depth-first order, a subtree that fits in one run kept in one run, so that each
/// later run's tangents are zero on all but a few branches and fold away there (Solo-12: one leg
/// per run, where lanes taken in the order of the velocity indices put every leg in every run).
/// The six directions through `a₀` are not planned here ([`with_field_directions`]; the base
/// translations' columns are zero).
fn plan(parents: &[Option<usize>]) -> Vec<Vec<Direction>> {
    let base: Vec<Direction> = (3..6).map(Direction::Velocity).collect();
    let mut runs: Vec<Vec<Direction>> = base.chunks(LANES).map(<[Direction]>::to_vec).collect();
    let mut free = LANES - runs.last().map_or(LANES, Vec::len);
    for block in subtree_blocks(parents) {
        let mut directions: Vec<Direction> = block
            .iter()
            .flat_map(|&j| [Direction::Configuration(6 + j), Direction::Velocity(6 + j)])
            .collect();
        if free > 0 {
            // The last base run: any direction rides along.
            let taken = directions.len().min(free);
            runs.last_mut()
                .expect("the base has runs")
                .extend(directions.drain(..taken));
            free -= taken;
        }
        if directions.is_empty() {
            continue;
        }
        // The last run is a full base run or a run of joints, which the block joins if it fits.
        match runs.last_mut() {
            Some(run) if run.len() + directions.len() <= LANES => run.extend(directions),
            _ => runs.push(directions),
        }
    }
    runs
}

/// `runs` with the six directions through `a₀` (the base rotations and linear velocities) in
/// the free lanes of the first run with room for them, or in a run of their own: their columns
/// come from the gravity recursion ([`run`]), whatever else the run carries.
fn with_field_directions(mut runs: Vec<Vec<Direction>>) -> Vec<Vec<Direction>> {
    match runs
        .iter_mut()
        .find(|run| run.len() + FIELD_DIRECTIONS.len() <= LANES)
    {
        Some(run) => run.extend(FIELD_DIRECTIONS),
        None => runs.push(FIELD_DIRECTIONS.to_vec()),
    }
    runs
}

/// Each coordinate's parent, as [`plan`] takes them: the joint's, or with mimic joints, whose
/// coordinates move joints on several branches, the coordinate before (a chain).
fn parents(model: &Model) -> Vec<Option<usize>> {
    match model.has_mimics() {
        false => model.joints().iter().map(|j| j.parent).collect(),
        true => (0..model.dof()).map(|k| k.checked_sub(1)).collect(),
    }
}

/// The joints in depth-first order, cut into blocks of whole subtrees of at most `LANES / 2`
/// joints (two directions each); a joint whose subtree is larger is a block of its own.
fn subtree_blocks(parents: &[Option<usize>]) -> Vec<Vec<usize>> {
    let mut children = vec![Vec::new(); parents.len()];
    let mut size = vec![1; parents.len()];
    // Children have larger indices than their parents.
    for j in (0..parents.len()).rev() {
        if let Some(p) = parents[j] {
            children[p].insert(0, j);
            size[p] += size[j];
        }
    }
    fn preorder(j: usize, children: &[Vec<usize>], out: &mut Vec<usize>) {
        out.push(j);
        for &c in &children[j] {
            preorder(c, children, out);
        }
    }
    fn visit(j: usize, children: &[Vec<usize>], size: &[usize], blocks: &mut Vec<Vec<usize>>) {
        if 2 * size[j] <= LANES {
            let mut block = Vec::new();
            preorder(j, children, &mut block);
            blocks.push(block);
        } else {
            blocks.push(vec![j]);
            for &c in &children[j] {
                visit(c, children, size, blocks);
            }
        }
    }
    let mut blocks = Vec::new();
    for root in (0..parents.len()).filter(|&j| parents[j].is_none()) {
        visit(root, &children, &size, &mut blocks);
    }
    blocks
}

/// `τ`'s tangents along `directions` (direction `k` in lane `k`), configuration and velocity
/// directions in one run.
#[allow(clippy::too_many_arguments)]
fn run<S: LaneScalar>(
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<Dual<S, S::Lanes>>],
    joint_values: &[JointTermValues],
    v: &[S],
    a: &[S],
    directions: &[Direction],
) -> Run<S::Lanes> {
    let lane_of = |wanted: Direction| {
        (directions.iter().position(|&d| d == wanted)).map(|k| S::Lanes::unit(k, S::one()))
    };
    let x = seeded_frames(model, q, joint_transforms, |j| {
        lane_of(Direction::Configuration(6 + j))
    });
    let seeded_v: Vec<Dual<S, S::Lanes>> = (v.iter().enumerate())
        .map(|(c, &value)| Dual {
            value,
            tangent: (lane_of(Direction::Velocity(c)))
                .filter(|_| !FIELD_DIRECTIONS.contains(&Direction::Velocity(c)))
                .unwrap_or_else(S::Lanes::zero),
        })
        .collect();
    let a: Vec<Dual<S, S::Lanes>> = a.iter().map(|&x| Dual::constant(x)).collect();
    let constant = constant_base(base);
    let rigid = floating_inverse_dynamics(model, &constant, &x, inertias, &seeded_v, &a);
    let joints = (&seeded_v[6..], &seeded_v[6..], &a[6..]);
    let tau = with_joint_term_torques(model, joint_values, rigid, 6, joints);
    let mut tangent: Vec<S::Lanes> = tau.into_iter().map(|d| d.tangent).collect();
    if directions.iter().any(|d| FIELD_DIRECTIONS.contains(d)) {
        // The gravity recursion under `g_b` moving as the run's field directions say, seen from
        // an upright base (module docs).
        let (weight, spin) = weight_and_spin(model, base, v);
        let mut field = Vec3(weight.0.map(Dual::constant));
        for (k, &d) in directions.iter().enumerate() {
            let Some(rate) = field_rate(d, &weight, &spin) else {
                continue;
            };
            let lane = S::Lanes::unit(k, S::one());
            for (f, r) in field.0.iter_mut().zip(rate.0) {
                f.tangent = f.tangent + lane.scale(r);
            }
        }
        let upright = FloatingBase {
            pose: Transform::identity(),
            inertia: constant.inertia,
        };
        let fixed = seeded_frames(model, q, joint_transforms, |_| None);
        let rest = vec![Dual::constant(S::zero()); v.len()];
        let gravity =
            floating_inverse_dynamics_in_field(model, &upright, field, &fixed, inertias, &rest, &rest);
        for (t, g) in tangent.iter_mut().zip(gravity) {
            *t = *t + g.tangent;
        }
    }
    Run {
        directions: directions.to_vec(),
        tangent,
    }
}

/// The runs `planned`: `τ`'s tangents along every direction.
#[allow(clippy::too_many_arguments)]
fn runs<S: LaneScalar>(
    planned: &[Vec<Direction>],
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    v: &[S],
    a: &[S],
) -> Vec<Run<S::Lanes>> {
    let inertias: Vec<RigidInertia<Dual<S, S::Lanes>>> = inertias.iter().map(lift_inertia).collect();
    (planned.iter())
        .map(|directions| run(model, base, q, &inertias, joint_values, v, a, directions))
        .collect()
}

/// `(∂/∂q, ∂/∂ν)`, `nv × nv` each, from the runs' tangents; the base translation's columns of
/// `∂/∂q` are zero.
fn matrices<S: LaneScalar>(nv: usize, runs: &[Run<S::Lanes>]) -> (DMatrix<S>, DMatrix<S>) {
    let mut d_q = DMatrix::from_element(nv, nv, S::zero());
    let mut d_v = DMatrix::from_element(nv, nv, S::zero());
    for run in runs {
        for (k, direction) in run.directions.iter().enumerate() {
            let (m, c) = match *direction {
                Direction::Configuration(c) => (&mut d_q, c),
                Direction::Velocity(c) => (&mut d_v, c),
            };
            for (i, t) in run.tangent.iter().enumerate() {
                m[(i, c)] = t.lane(k);
            }
        }
    }
    (d_q, d_v)
}

/// `(∂τ/∂q, ∂τ/∂ν)` of floating inverse dynamics at `(q, ν, ν̇ = a)`, `q` the joints' coordinates
/// (the base enters through `base`), both `nv × nv`; entry `(i, c)` is `∂τ_i/∂x_c`.
///
/// In lanes only (`plan`): every direction reaches the base rows, so the lanes fill, and
/// generated code ran faster than one direction per run (`docs/performance-notes.md`).
pub fn floating_inverse_dynamics_derivatives<S: LaneScalar>(
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    v: &[S],
    a: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let planned = with_field_directions(plan(&parents(model)));
    matrices(
        model.nv(),
        &runs(&planned, model, base, q, inertias, joint_values, v, a),
    )
}

/// `(∂ν̇/∂q, ∂ν̇/∂ν)` of floating forward dynamics at `(q, ν, τ)` (`∂ν̇/∂τ = D⁻¹`).
pub fn floating_forward_dynamics_derivatives<S: LaneScalar>(
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<S>],
    joint_values: &[JointTermValues],
    v: &[S],
    tau: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let x = joint_transforms(model, q);
    let a = floating_forward_dynamics(model, base, &x, inertias, joint_values, v, tau);
    let lifted = lift_factor(&factor(model, base, &x, inertias, joint_values));
    let planned = plan(&parents(model));
    let solved: Vec<Run<S::Lanes>> = runs(&planned, model, base, q, inertias, joint_values, v, &a)
        .into_iter()
        .map(|r| Run {
            tangent: minus_solved(&lifted, &r.tangent),
            directions: r.directions,
        })
        .collect();
    let (mut d_q, mut d_v) = matrices(model.nv(), &solved);
    // The six columns through `a₀` (module docs): `ν̇_v` moves by the field's rate.
    let (weight, spin) = weight_and_spin(model, base, v);
    for d in FIELD_DIRECTIONS {
        let rate = field_rate(d, &weight, &spin).expect("a direction through the base acceleration");
        let (m, c) = match d {
            Direction::Configuration(c) => (&mut d_q, c),
            Direction::Velocity(c) => (&mut d_v, c),
        };
        for (i, &entry) in rate.0.iter().enumerate() {
            m[(i, c)] = entry;
        }
    }
    (d_q, d_v)
}

#[cfg(test)]
mod tests {
    use super::{plan, with_field_directions, Direction, LANES};

    /// Every direction once (the base translation's configuration columns, zero, in none), at
    /// most `LANES` a run.
    fn check_complete(parents: &[Option<usize>]) -> Vec<Vec<Direction>> {
        let runs = with_field_directions(plan(parents));
        let nv = 6 + parents.len();
        let mut seen: Vec<Direction> = runs.iter().flatten().copied().collect();
        assert!(runs.iter().all(|r| !r.is_empty() && r.len() <= LANES));
        seen.sort_by_key(|d| match *d {
            Direction::Configuration(c) => c,
            Direction::Velocity(c) => nv + c,
        });
        let expected: Vec<Direction> = (3..nv)
            .map(Direction::Configuration)
            .chain((0..nv).map(Direction::Velocity))
            .collect();
        assert_eq!(seen, expected);
        runs
    }

    /// The root joint of joint `j`'s branch.
    fn branch(parents: &[Option<usize>], mut j: usize) -> usize {
        while let Some(p) = parents[j] {
            j = p;
        }
        j
    }

    #[test]
    fn a_quadruped_has_one_whole_tree_run_then_runs_by_leg() {
        // Four legs of three joints, as Solo-12.
        let parents: Vec<Option<usize>> = (0..12)
            .map(|j| if j % 3 == 0 { None } else { Some(j - 1) })
            .collect();
        let runs = check_complete(&parents);
        // Three base angular velocities and 24 joint directions: one whole-tree run (the angular
        // velocities and five directions of the first leg), the first leg's last direction with
        // the second leg, the third and fourth legs, and the six directions through the base
        // acceleration in a run of their own.
        assert_eq!(runs.len(), 5);
        let base = |d: &Direction| match *d {
            Direction::Configuration(c) | Direction::Velocity(c) => c < 6,
        };
        assert_eq!(runs[0].iter().filter(|d| base(d)).count(), 3);
        assert!(runs[1..4].iter().flatten().all(|d| !base(d)));
        assert_eq!(runs[4], super::FIELD_DIRECTIONS);
        for run in &runs[2..4] {
            let legs: Vec<usize> = run
                .iter()
                .map(|d| match *d {
                    Direction::Configuration(c) | Direction::Velocity(c) => branch(&parents, c - 6),
                })
                .collect();
            assert!(legs.iter().all(|&l| l == legs[0]), "{run:?} spans legs");
        }
    }

    #[test]
    fn long_branches_and_single_joints_are_planned_completely() {
        // A humanoid's shape: two legs of six, a waist of three carrying two arms of seven.
        let mut parents = Vec::new();
        for _ in 0..2 {
            let first = parents.len();
            parents.extend((0..6).map(|k| if k == 0 { None } else { Some(first + k - 1) }));
        }
        let waist = parents.len();
        parents.extend([None, Some(waist), Some(waist + 1)]);
        for _ in 0..2 {
            let first = parents.len();
            parents.extend((0..7).map(|k| {
                if k == 0 {
                    Some(waist + 2)
                } else {
                    Some(first + k - 1)
                }
            }));
        }
        check_complete(&parents);
        check_complete(&[None]);
        check_complete(&[]);
        check_complete(&(0..30usize).map(|j| j.checked_sub(1)).collect::<Vec<_>>());
    }
}
