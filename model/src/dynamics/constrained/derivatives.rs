//! The derivatives of constrained forward dynamics with respect to `q` (in the tangent space,
//! `q ⊕ δ`, as Pinocchio's `computeConstraintDynamicsDerivatives`), `ν` and `τ`.
//!
//! At the solution `(a, λ)` the equations of constrained motion leave nothing:
//! `F = ID(q, ν, a) − J(q)ᵀ λ − τ = 0` and `G = J(q) a + drift(q, ν) + K_p e(q) + K_d J(q) ν = 0`.
//! Along a direction `ẋ` of the state, with `a` and `λ` held, they change by `Ḟ` and `Ġ`,
//! which forward-mode dual numbers give from the same generic algorithms the generator
//! traces (inverse dynamics, the frames' motion, the contact rows). The solution's own
//! change then solves the same constrained system as forward dynamics,
//! `M ȧ − Jᵀ λ̇ = −Ḟ`, `J ȧ = −Ġ`, with the runtime's solve: `ȧ = M⁻¹(−Ḟ) + M⁻¹ Jᵀ λ̇`.

use crate::model::Contact;
use crate::scalar::Scalar;
use crate::scalar_dual::Dual;
use crate::spatial::{Mat3, Transform, Vec3};
use dyngen_runtime::{ContactKind, ReferenceFrame};
use nalgebra::Dyn;

/// A dual number with one tangent: one direction per evaluation.
pub(super) type D1 = Dual<f64, f64>;

/// `(∂a/∂x, ∂λ/∂x)` for `x` each of `q` (tangent space), `ν` and `τ`: the runtime's, in
/// dynamic sizes.
pub type ConstrainedDerivatives = dyngen_runtime::ConstrainedDerivatives<Dyn, Dyn>;

/// `F` and `G` at one state on dual numbers (module docs).
pub(super) struct Residual {
    pub motion: Vec<D1>,
    pub rows: Vec<D1>,
}

/// `x` with the tangent `1` at `k` (none if `k` is past it).
pub(super) fn seeded(x: &[f64], k: Option<usize>) -> Vec<D1> {
    (x.iter().enumerate())
        .map(|(i, &value)| Dual {
            value,
            tangent: if Some(i) == k { 1.0 } else { 0.0 },
        })
        .collect()
}

pub(super) fn constant(x: &[f64]) -> Vec<D1> {
    seeded(x, None)
}

/// A floating base's pose moved along base direction `k` of the tangent space: `p + ε R e_k`
/// (`k < 3`), `R (I + ε [e_{k−3}]×)` (`3 ≤ k < 6`), fixed otherwise.
pub(super) fn seeded_pose(pose: &Transform<f64>, k: usize) -> Transform<D1> {
    let r = &pose.rot.0;
    let rot = Mat3(std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let tangent = match k {
                3..6 => {
                    // (R [e]×)_ij = Σ_l R_il [e]×_lj, with [e]× e_j = e × e_j.
                    let e = k - 3;
                    (0..3).map(|l| r[i][l] * cross_entry(e, l, j)).sum()
                }
                _ => 0.0,
            };
            Dual {
                value: r[i][j],
                tangent,
            }
        })
    }));
    let pos = Vec3(std::array::from_fn(|i| Dual {
        value: pose.pos.0[i],
        tangent: if k < 3 { r[i][k] } else { 0.0 },
    }));
    Transform { rot, pos }
}

/// Entry `(l, j)` of `[e_k]×` (`[e_k]× x = e_k × x`): the Levi-Civita symbol `ε_{l k j}`.
fn cross_entry(k: usize, l: usize, j: usize) -> f64 {
    match (l, k, j) {
        (0, 1, 2) | (1, 2, 0) | (2, 0, 1) => 1.0,
        (0, 2, 1) | (1, 0, 2) | (2, 1, 0) => -1.0,
        _ => 0.0,
    }
}

/// `G`'s Baumgarte part for a point: `K_p e + K_d J ν`, `e` the placement error of
/// `dyngen_runtime::placement_error` for a point held at `anchor` (`Rᵀ (p − anchor)` in local
/// axes, `p − anchor` in world axes), written generically; a frame's needs `log₆` and has no
/// derivative here.
pub(super) fn point_error<S: Scalar>(
    reference: ReferenceFrame,
    frame: &Transform<S>,
    anchor: Vec3<S>,
) -> [S; 3] {
    let offset = frame.pos - anchor;
    let e = match reference {
        ReferenceFrame::LocalWorldAligned => offset,
        _ => frame.rot.tr_mul_vec(&offset),
    };
    e.0
}

/// Whether every stabilised contact is a point (a frame's error needs `log₆`).
pub(super) fn differentiable(contacts: &[Contact], stabilised: bool) -> bool {
    !stabilised || contacts.iter().all(|c| c.kind == ContactKind::Point)
}
