//! Forward-mode differentiation as a scalar: `Dual<S>` carries a value and its derivative along
//! one direction, so any algorithm generic over [`Scalar`] also computes its directional
//! derivative, written once.
//!
//! Run with `S = Expr`, the value parts are the very nodes the plain algorithm records (the graph
//! is hash-consed), so a derivative function shares the function's own values, and tangents that
//! are structurally zero (a joint's angle does not move the bodies above it) fold away while
//! they are built: forward mode over the expression graph, with the tree's sparsity for free.
//! One tangent per run (not `n` at once) keeps the type `Copy` and the directions independent;
//! the cost is the same, since every direction's tangent is its own set of nodes anyway.

use crate::scalar::Scalar;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// `value + ε·tangent` with `ε² = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<S> {
    pub value: S,
    pub tangent: S,
}

impl<S: Scalar> Dual<S> {
    /// A quantity that does not depend on the direction of differentiation.
    pub fn constant(value: S) -> Self {
        Dual {
            value,
            tangent: S::zero(),
        }
    }

    /// The variable the derivative is taken with respect to (tangent one).
    pub fn variable(value: S) -> Self {
        Dual {
            value,
            tangent: S::one(),
        }
    }
}

impl<S: Scalar> Add for Dual<S> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Dual {
            value: self.value + o.value,
            tangent: self.tangent + o.tangent,
        }
    }
}

impl<S: Scalar> Sub for Dual<S> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Dual {
            value: self.value - o.value,
            tangent: self.tangent - o.tangent,
        }
    }
}

impl<S: Scalar> Mul for Dual<S> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Dual {
            value: self.value * o.value,
            tangent: self.value * o.tangent + self.tangent * o.value,
        }
    }
}

impl<S: Scalar> Div for Dual<S> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let value = self.value / o.value;
        Dual {
            value,
            tangent: (self.tangent - value * o.tangent) / o.value,
        }
    }
}

impl<S: Scalar> Neg for Dual<S> {
    type Output = Self;
    fn neg(self) -> Self {
        Dual {
            value: -self.value,
            tangent: -self.tangent,
        }
    }
}

impl<S: Scalar> Scalar for Dual<S> {
    fn from_f64(x: f64) -> Self {
        Dual::constant(S::from_f64(x))
    }
    fn sin(self) -> Self {
        Dual {
            value: self.value.sin(),
            tangent: self.value.cos() * self.tangent,
        }
    }
    fn cos(self) -> Self {
        Dual {
            value: self.value.cos(),
            tangent: -(self.value.sin() * self.tangent),
        }
    }
    /// Piecewise constant: its derivative is 0 (where it has one; friction at rest is a kink).
    fn sign(self) -> Self {
        Dual::constant(self.value.sign())
    }
    fn tanh(self) -> Self {
        let t = self.value.tanh();
        Dual {
            value: t,
            tangent: (S::one() - t * t) * self.tangent,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn product_quotient_and_trig_rules() {
        let x = Dual::variable(0.7_f64);
        let f = (x * x.sin() + x.cos()) / (x + Dual::from_f64(2.0));
        let h = 1e-6;
        let g = |x: f64| (x * x.sin() + x.cos()) / (x + 2.0);
        let fd = (g(0.7 + h) - g(0.7 - h)) / (2.0 * h);
        assert!((f.value - g(0.7)).abs() < 1e-15);
        assert!((f.tangent - fd).abs() < 1e-9, "{} vs {fd}", f.tangent);
    }
}
