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
//! Forward dynamics needs no differentiation of its own: with `ν̇ = FD(q, ν, τ)` fixed,
//! `∂ν̇/∂x = −D⁻¹ ∂τ/∂x` at that `ν̇`, solved with the tree factor forward dynamics uses, on
//! the lane tangents (all columns of a group at once).

use super::mass::{factor, floating_forward_dynamics};
use super::{floating_inverse_dynamics, FloatingBase};
use crate::dynamics::derivatives::{columns, minus_solved_columns, Group};
use crate::dynamics::joint::joint_transforms;
use crate::dynamics::seeded_frame::seeded_frames;
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

fn lift_inertia<S: Scalar, T: Tangent<S>>(i: &RigidInertia<S>) -> RigidInertia<Dual<S, T>> {
    RigidInertia {
        m: Dual::constant(i.m),
        h: Vec3(i.h.0.map(Dual::constant)),
        i: i.i.map(Dual::constant),
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

/// The tangents of inverse dynamics along the configuration directions `seed` gives (velocity
/// indices: `3..6` the base rotation, `6 + j` joint `j`), and along the velocity directions
/// `velocity_seed` gives.
#[allow(clippy::too_many_arguments)]
fn tangents<S: Scalar, T: Tangent<S>>(
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<S>],
    v: &[S],
    a: &[S],
    seed: impl Fn(usize) -> Option<T>,
    velocity_seed: impl Fn(usize) -> Option<T>,
) -> (Vec<T>, Vec<T>) {
    let inertias: Vec<RigidInertia<Dual<S, T>>> = inertias.iter().map(lift_inertia).collect();
    let constant = |x: &[S]| -> Vec<Dual<S, T>> { x.iter().map(|&x| Dual::constant(x)).collect() };
    let (v_const, a_const) = (constant(v), constant(a));
    let seeded = seeded_base(base, &seed);
    let x = seeded_frames(model, q, |j| seed(6 + j));
    let by_configuration = floating_inverse_dynamics(model, &seeded, &x, &inertias, &v_const, &a_const);
    let no_seed = |_: usize| None;
    let fixed = seeded_base(base, &no_seed);
    let x_const = joint_transforms(model, &constant(q));
    let v_seeded: Vec<Dual<S, T>> = (v.iter().enumerate())
        .map(|(k, &x)| Dual {
            value: x,
            tangent: velocity_seed(k).unwrap_or_else(T::zero),
        })
        .collect();
    let by_velocity = floating_inverse_dynamics(model, &fixed, &x_const, &inertias, &v_seeded, &a_const);
    let tangent = |tau: Vec<Dual<S, T>>| tau.into_iter().map(|d| d.tangent).collect();
    (tangent(by_configuration), tangent(by_velocity))
}

/// `(∂τ/∂q, ∂τ/∂ν)` of floating inverse dynamics at `(q, ν, ν̇ = a)`, `q` the joints' coordinates
/// (the base enters through `base`), both `nv × nv`; entry `(i, c)` is `∂τ_i/∂x_c`.
///
/// In lanes only: every direction reaches the base rows, so the lanes fill, and generated
/// code ran faster than one direction per run (Solo-12's `∂τ/∂x`: 2,962 scalar and 4,792 lane
/// operations in 1.46 µs, against 10,861 scalar ones in 2.27 µs; `BENCHMARKS.md`).
pub fn floating_inverse_dynamics_derivatives<S: LaneScalar>(
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<S>],
    v: &[S],
    a: &[S],
) -> (DMatrix<S>, DMatrix<S>) {
    let groups = lane_groups(model, base, q, inertias, v, a);
    let nv = model.nv();
    (
        columns(nv, &groups, |g| &g.d_q),
        columns(nv, &groups, |g| &g.d_qd),
    )
}

/// The tangents of inverse dynamics in groups of [`LANES`] directions (direction `first + k`
/// in lane `k`, for the configuration and for the velocity).
fn lane_groups<S: LaneScalar>(
    model: &Model,
    base: &FloatingBase<S>,
    q: &[S],
    inertias: &[RigidInertia<S>],
    v: &[S],
    a: &[S],
) -> Vec<Group<S::Lanes>> {
    (0..model.nv())
        .step_by(LANES)
        .map(|first| {
            let lane = |k: usize| {
                (first..first + LANES)
                    .contains(&k)
                    .then(|| S::Lanes::unit(k - first, S::one()))
            };
            // The base translation's directions are zero: not seeded.
            let rotation_or_joint = |k: usize| lane(k).filter(|_| k >= 3);
            let (d_q, d_qd) = tangents(model, base, q, inertias, v, a, rotation_or_joint, lane);
            Group { first, d_q, d_qd }
        })
        .collect()
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
    let groups = lane_groups(model, base, q, inertias, v, &a);
    minus_solved_columns(&factor(model, base, &x, inertias), model.nv(), groups)
}
