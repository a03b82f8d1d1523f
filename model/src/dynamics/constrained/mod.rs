//! Dynamics under rigid constraints: frames held to the world by point (3-D) or frame (6-D)
//! contacts. Constrained forward dynamics with the constraint forces, impulse dynamics at
//! touchdown, and the operational-space inertia of a set of constrained rows.
//!
//! Every constrained row is an acceleration (or, at an impact, a velocity) the solution must
//! give: with `J` the stacked rows, `M` the mass matrix and `b` the bias forces,
//!
//! ```text
//! M a = τ − b + Jᵀ λ,      J a = −drift − K_p e − K_d J ν     (forward dynamics)
//! M (ν⁺ − ν⁻) = Jᵀ Λ,      J ν⁺ = −r J ν⁻                     (an impact, restitution r)
//! ```
//!
//! solved through the Delassus matrix `J M⁻¹ Jᵀ` regularised by `μ` and refined by proximal
//! iterations (`λ_k = (J M⁻¹ Jᵀ + μ I)⁻¹ (rhs − J M⁻¹ (τ − b) + μ λ_{k−1})`), which converge to
//! the exact solution where the rows are independent and to a solution that satisfies the rows
//! in the least-squares sense where they are redundant. The conventions (rows linear-first in
//! the contact's `LOCAL` or `LOCAL_WORLD_ALIGNED` axes, a point's drift its classical
//! acceleration, a frame's its spatial acceleration, the placement error `−log₆(c₁Mc₂)`) are
//! Pinocchio's `constraintDynamics`, against whose values the tests hold these functions.

mod contact;
mod delassus;
mod numeric;
mod placement_error;
mod rows;

pub use contact::{Anchor, ConstraintError, Contact, ContactKind, ProximalSettings, Stabilisation};
#[doc(hidden)]
pub use delassus::Delassus;
pub use numeric::{ConstrainedMotion, Impact};
#[doc(hidden)]
pub use rows::{constraint_rows, ConstraintRows};
