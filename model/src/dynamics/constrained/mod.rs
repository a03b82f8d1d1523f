//! Dynamics under rigid contacts: frames held to the world, or to each other (loop closures),
//! by point (3-D) or frame (6-D) contacts. Constrained forward dynamics with the contact forces, impulse dynamics at
//! touchdown, and the operational-space inertia of the contacts' rows, for fixed and floating
//! bases.
//!
//! With `J` the stacked rows, `M` the mass matrix and `b` the bias forces,
//!
//! ```text
//! M a = τ − b + Jᵀ λ,      J a = −drift − K_p e − K_d J ν     (forward dynamics)
//! M (ν⁺ − ν⁻) = Jᵀ Λ,      J ν⁺ = −r J ν⁻                     (an impact, restitution r)
//! ```
//!
//! The rows are written linear-first in each contact's `Local` or `LocalWorldAligned` axes
//! (`rows.rs`), the placement error is `−log₆(c₁Mc₂)` (`c₂` an anchor in the world, or the
//! frame held to): Pinocchio's `constraintDynamics`, against whose values the tests
//! hold these functions. The rows are generic over the scalar (the generator traces them); the
//! solve is `dyngen_runtime::solve_contacts`, the one generated robots use.

mod derivatives;
mod error;
mod freedom;
mod numeric;
mod numeric_derivatives;
mod rows;

pub use derivatives::ConstrainedDerivatives;
pub use error::ConstraintError;
pub use freedom::free_degrees;
pub use numeric::ConstrainedMotion;
#[doc(hidden)]
pub use rows::{constraint_rows, ConstraintRows, ContactMotion, OriginRates};
