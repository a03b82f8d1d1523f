//! The scalar type every dynamics algorithm is generic over.
//!
//! With `f64` the algorithms are dyngen's generic (reference) dynamics; with the symbolic
//! expression type they record the computation, which the code generator then simplifies and
//! emits. One algorithm written once, two uses — the way Pinocchio does its code generation.

use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Arithmetic that the dynamics algorithms need: a field with sine and cosine.
///
/// `Copy` keeps the algorithm code free of clones; the symbolic type is a handle into a graph.
pub trait Scalar:
    Copy
    + Debug
    + PartialEq
    + 'static
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// A constant. Model data (geometry, masses) enters the algorithms through here.
    fn from_f64(x: f64) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    /// `sign(x)`: 1, −1, or 0 at 0 (Coulomb friction is zero at rest; [`sign`]).
    fn sign(self) -> Self;
    /// Hyperbolic tangent (smoothed Coulomb friction).
    fn tanh(self) -> Self;

    fn zero() -> Self {
        Self::from_f64(0.0)
    }
    fn one() -> Self {
        Self::from_f64(1.0)
    }
}

impl Scalar for f64 {
    fn from_f64(x: f64) -> Self {
        x
    }
    fn sin(self) -> Self {
        f64::sin(self)
    }
    fn cos(self) -> Self {
        f64::cos(self)
    }
    fn sign(self) -> Self {
        sign(self)
    }
    fn tanh(self) -> Self {
        f64::tanh(self)
    }
}

/// `sign(x)` with `sign(0) = 0` (and 0 for NaN): the runtime's, which generated code calls.
pub use dyngen_runtime::__private::sign;
