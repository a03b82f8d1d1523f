//! Derivatives of floating-base inverse and forward dynamics in the tangent space, by
//! forward-mode differentiation of the floating recursion itself, as for a fixed base
//! (`dynamics::derivatives`), [`LANES`] directions per run, one per lane.
//!
//! Directions are Pinocchio's: a configuration moves as `q ⊕ δ` (`nv` columns). The base
//! translation's three columns are zero (nothing but the kinematics sees the base position,
//! and inverse dynamics is written in the base frame); a base rotation `δ_k` turns the base as
//! `R ↦ R exp([δ]×)`, so `R` moves by `R [e_k]×` and with it gravity seen in the base frame; a
//! joint's coordinate moves its transform through its motion subspace
//! (`dynamics::seeded_frame`). A velocity direction seeds its entry of `ν`.
//!
//! Gravity is all a base rotation reaches: `τ` is affine in `Rᵀ g`, whose coefficient is the
//! same in `g(q)` (the weight enters as an upward acceleration of the base), so
//! `∂τ/∂δ_k = ∂g/∂δ_k`. Those three columns come from the gravity recursion, which has no
//! velocities, instead of from inverse dynamics in lanes: carried through inverse dynamics,
//! the rotations filled a second run that reached every body.
//!
//! Forward dynamics needs no differentiation of its own: with `ν̇ = FD(q, ν, τ)` fixed,
//! `∂ν̇/∂x = −D⁻¹ ∂τ/∂x` at that `ν̇`, solved with the tree factor forward dynamics uses, on
//! the lane tangents (all columns of a run at once). Its base rotations' columns need neither:
//! `ν̇ = D⁻¹ (τ − h) + [Rᵀ g; 0]` (with the joint torques held, the weight accelerates the
//! base as a whole and moves nothing else), so column `3 + k` is `[Rᵀ g × e_k; 0]`.

use super::mass::{factor, floating_forward_dynamics};
use super::{floating_gravity, floating_inverse_dynamics, FloatingBase};
use crate::dynamics::derivatives::{lift_factor, lift_inertia, minus_solved};
use crate::dynamics::joint::joint_transforms;
use crate::dynamics::seeded_frame::seeded_frames;
use crate::dynamics::slotine_li::gravity_vector;
use crate::model::Model;
use crate::scalar::Scalar;
use crate::scalar_dual::{Dual, LaneScalar, LaneTangent, Tangent, LANES};
use crate::spatial::{Mat3, RigidInertia, Transform, Vec3};
use nalgebra::DMatrix;

/// `ε_ijk`.
fn levi_civita(i: usize, j: usize, k: usize) -> f64 {
    match (i, j, k) {
        (0, 1, 2) | (1, 2, 0) | (2, 0, 1) => 1.0,
        (0, 2, 1) | (2, 1, 0) | (1, 0, 2) => -1.0,
        _ => 0.0,
    }
}

/// The base on dual numbers: the rotation's tangent is `Σ_k seed(3 + k) · R [e_k]×` (the base
/// rotations of this run), the position and the inertia constant.
fn seeded_base<S: Scalar, T: Tangent<S>>(
    base: &FloatingBase<S>,
    seed: &impl Fn(usize) -> Option<T>,
) -> FloatingBase<Dual<S, T>> {
    let r = &base.pose.rot;
    let rot = Mat3(std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let mut tangent = T::zero();
            for k in 0..3 {
                let Some(s) = seed(3 + k) else { continue };
                // (R [e_k]×)_ij = Σ_m R_im ε_mkj: one entry of R, signed, or none.
                for m in 0..3 {
                    match levi_civita(m, k, j) {
                        1.0 => tangent = tangent + s.scale(r.0[i][m]),
                        -1.0 => tangent = tangent - s.scale(r.0[i][m]),
                        _ => {}
                    }
                }
            }
            Dual {
                value: r.0[i][j],
                tangent,
            }
        })
    }));
    FloatingBase {
        pose: Transform {
            rot,
            pos: Vec3(base.pose.pos.0.map(Dual::constant)),
        },
        inertia: lift_inertia(&base.inertia),
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
/// bodies it moves: a base velocity's on every body, a joint's on its subtree (and on `τ`'s
/// rows above it). So the base's six velocities come first, filling a whole-tree run whose free
/// lanes then take joint directions at no extra cost; the other joints' directions follow in
/// depth-first order, a subtree that fits in one run kept in one run, so that each later run's
/// tangents are zero on all but a few branches and fold away there (Solo-12: one leg per run,
/// where lanes taken in the order of the velocity indices put every leg in every run). The base
/// rotations are not planned here ([`with_base_rotations`]; the translations' columns are zero).
fn plan(parents: &[Option<usize>]) -> Vec<Vec<Direction>> {
    let base: Vec<Direction> = (0..6).map(Direction::Velocity).collect();
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

/// `runs` with the base rotations in the free lanes of the first run with room for all three:
/// their columns come from gravity ([`run`]), whatever else the run carries.
fn with_base_rotations(mut runs: Vec<Vec<Direction>>) -> Vec<Vec<Direction>> {
    let rotations: Vec<Direction> = (3..6).map(Direction::Configuration).collect();
    match runs.iter_mut().find(|run| run.len() + rotations.len() <= LANES) {
        Some(run) => run.extend(rotations),
        None => runs.push(rotations),
    }
    runs
}

/// Each joint's parent, as [`plan`] takes them.
fn parents(model: &Model) -> Vec<Option<usize>> {
    model.joints().iter().map(|j| j.parent).collect()
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
fn run<S: LaneScalar>(
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<Dual<S, S::Lanes>>],
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
    let v: Vec<Dual<S, S::Lanes>> = (v.iter().enumerate())
        .map(|(c, &value)| Dual {
            value,
            tangent: lane_of(Direction::Velocity(c)).unwrap_or_else(S::Lanes::zero),
        })
        .collect();
    let a: Vec<Dual<S, S::Lanes>> = a.iter().map(|&x| Dual::constant(x)).collect();
    let unturned = seeded_base(base, &|_| None);
    let mut tangent: Vec<S::Lanes> = floating_inverse_dynamics(model, &unturned, &x, inertias, &v, &a)
        .into_iter()
        .map(|d| d.tangent)
        .collect();
    let rotation = |c: usize| lane_of(Direction::Configuration(c));
    if (3..6).any(|c| rotation(c).is_some()) {
        // `∂τ/∂δ_k = ∂g/∂δ_k` (module docs): gravity at the joints' configuration, held fixed.
        let turned = seeded_base(base, &rotation);
        let fixed = seeded_frames(model, q, joint_transforms, |_| None);
        let gravity = floating_gravity(model, &turned, &fixed, inertias);
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
    v: &[S],
    a: &[S],
) -> Vec<Run<S::Lanes>> {
    let inertias: Vec<RigidInertia<Dual<S, S::Lanes>>> = inertias.iter().map(lift_inertia).collect();
    (planned.iter())
        .map(|directions| run(model, base, q, &inertias, v, a, directions))
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
/// In lanes only ([`plan`]): every direction reaches the base rows, so the lanes fill, and
/// generated code ran faster than one direction per run (`BENCHMARKS.md`).
pub fn floating_inverse_dynamics_derivatives<S: LaneScalar>(
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<S>],
    v: &[S],
    a: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let planned = with_base_rotations(plan(&parents(model)));
    matrices(model.nv(), &runs(&planned, model, base, q, inertias, v, a))
}

/// `(∂ν̇/∂q, ∂ν̇/∂ν)` of floating forward dynamics at `(q, ν, τ)` (`∂ν̇/∂τ = D⁻¹`).
pub fn floating_forward_dynamics_derivatives<S: LaneScalar>(
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<S>],
    v: &[S],
    tau: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let x = joint_transforms(model, q);
    let a = floating_forward_dynamics(model, base, &x, inertias, v, tau);
    let lifted = lift_factor(&factor(model, base, &x, inertias));
    let solved: Vec<Run<S::Lanes>> = runs(&plan(&parents(model)), model, base, q, inertias, v, &a)
        .into_iter()
        .map(|r| Run {
            tangent: minus_solved(&lifted, &r.tangent),
            directions: r.directions,
        })
        .collect();
    let (mut d_q, d_v) = matrices(model.nv(), &solved);
    // The base rotations' columns (module docs): `[g_b × e_k; 0]`, `g_b` gravity in the base frame.
    let g_b = base.pose.rot.tr_mul_vec(&gravity_vector(model));
    for k in 0..3 {
        let column = g_b.cross(&Mat3::identity().column(k));
        for (i, &entry) in column.0.iter().enumerate() {
            d_q[(i, 3 + k)] = entry;
        }
    }
    (d_q, d_v)
}

#[cfg(test)]
mod tests {
    use super::{plan, with_base_rotations, Direction, LANES};

    /// Every direction once (the base translation's configuration columns, zero, in none), at
    /// most `LANES` a run.
    fn check_complete(parents: &[Option<usize>]) -> Vec<Vec<Direction>> {
        let runs = with_base_rotations(plan(parents));
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
    fn a_quadruped_gets_one_leg_per_run_after_the_base() {
        // Four legs of three joints, as Solo-12.
        let parents: Vec<Option<usize>> = (0..12)
            .map(|j| if j % 3 == 0 { None } else { Some(j - 1) })
            .collect();
        let runs = check_complete(&parents);
        // Six base velocities and 24 joint directions: one whole-tree run (the base velocities
        // and two directions of the first leg), the rest of the first leg with the three base
        // rotations, then three legs.
        assert_eq!(runs.len(), 5);
        let base_velocity = |d: &Direction| matches!(*d, Direction::Velocity(c) if c < 6);
        assert_eq!(runs[0].iter().filter(|d| base_velocity(d)).count(), 6);
        assert!(runs[1..].iter().flatten().all(|d| !base_velocity(d)));
        assert!((3..6).all(|c| runs[1].contains(&Direction::Configuration(c))));
        for run in &runs[2..] {
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
