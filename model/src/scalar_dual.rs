//! Forward-mode differentiation as a scalar: `Dual<S, T>` carries a value and its derivative
//! (`T = S`: along one direction; `T` a [`LaneTangent`]: along up to [`LANES`] directions at
//! once, one per lane), so any algorithm generic over [`Scalar`] also computes its directional
//! derivatives, written once.
//!
//! Run with `S = Expr`, the value parts are the very nodes the plain algorithm records (the graph
//! is hash-consed), so a derivative function shares the function's own values, and tangents that
//! are structurally zero (a joint's angle does not move the bodies above it) fold away while
//! they are built. With lane tangents (`Dual<Expr, LaneExpr>`) every tangent is one lane-vector
//! node (`f64x8` in generated code) holding all directions: a tangent along one direction only
//! stays a scalar in its lane (the joint transforms' derivatives), and the lanes fill where
//! directions mix (the bodies below several joints), so one vector operation does the work of
//! up to eight scalar ones.

use crate::scalar::Scalar;
use std::fmt::Debug;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// Directions carried at once by a lane tangent: the lanes of one `f64x8`.
pub const LANES: usize = 8;

/// What a tangent needs: a vector space over the scalar `S`.
pub trait Tangent<S>:
    Copy + Debug + PartialEq + 'static + Add<Output = Self> + Sub<Output = Self> + Neg<Output = Self>
{
    fn zero() -> Self;
    /// `s · self`.
    fn scale(self, s: S) -> Self;
    /// `self / s`.
    fn divide(self, s: S) -> Self;
}

/// One direction: the tangent is a scalar.
impl<S: Scalar> Tangent<S> for S {
    fn zero() -> Self {
        S::zero()
    }
    fn scale(self, s: S) -> Self {
        s * self
    }
    fn divide(self, s: S) -> Self {
        self / s
    }
}

/// [`LANES`] directions at once, one per lane.
pub trait LaneTangent<S>: Tangent<S> {
    /// `s` in lane `k`, zero in the others.
    fn unit(k: usize, s: S) -> Self;
    /// Lane `k`.
    fn lane(self, k: usize) -> S;
}

/// A scalar whose derivatives can be taken [`LANES`] directions at a time.
pub trait LaneScalar: Scalar {
    type Lanes: LaneTangent<Self>;
}

/// The numeric lane tangent: eight `f64`s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct F64Lanes(pub [f64; LANES]);

impl Add for F64Lanes {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        F64Lanes(std::array::from_fn(|k| self.0[k] + o.0[k]))
    }
}

impl Sub for F64Lanes {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        F64Lanes(std::array::from_fn(|k| self.0[k] - o.0[k]))
    }
}

impl Neg for F64Lanes {
    type Output = Self;
    fn neg(self) -> Self {
        F64Lanes(self.0.map(|x| -x))
    }
}

impl Tangent<f64> for F64Lanes {
    fn zero() -> Self {
        F64Lanes([0.0; LANES])
    }
    fn scale(self, s: f64) -> Self {
        F64Lanes(self.0.map(|x| s * x))
    }
    fn divide(self, s: f64) -> Self {
        F64Lanes(self.0.map(|x| x / s))
    }
}

impl LaneTangent<f64> for F64Lanes {
    fn unit(k: usize, s: f64) -> Self {
        let mut v = [0.0; LANES];
        v[k] = s;
        F64Lanes(v)
    }
    fn lane(self, k: usize) -> f64 {
        self.0[k]
    }
}

impl LaneScalar for f64 {
    type Lanes = F64Lanes;
}

/// `value + ε·tangent` with `ε² = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual<S, T = S> {
    pub value: S,
    pub tangent: T,
}

impl<S: Scalar, T: Tangent<S>> Dual<S, T> {
    /// A quantity that does not depend on the direction of differentiation.
    pub fn constant(value: S) -> Self {
        Dual {
            value,
            tangent: T::zero(),
        }
    }
}

impl<S: Scalar> Dual<S> {
    /// The variable the derivative is taken with respect to (tangent one).
    pub fn variable(value: S) -> Self {
        Dual {
            value,
            tangent: S::one(),
        }
    }
}

impl<S: Scalar, T: LaneTangent<S>> Dual<S, T> {
    /// The variable of the direction in lane `k` (tangent one there, zero in the other lanes).
    pub fn lane_variable(value: S, k: usize) -> Self {
        Dual {
            value,
            tangent: T::unit(k, S::one()),
        }
    }
}

/// `values` with the derivative taken along entries `first .. first + width` (entry `first + k`
/// in lane `k`, `width ≤ LANES`); the other entries constant.
pub fn seeded<S: Scalar, T: LaneTangent<S>>(values: &[S], first: usize, width: usize) -> Vec<Dual<S, T>> {
    values
        .iter()
        .enumerate()
        .map(|(j, &x)| match j.checked_sub(first).filter(|&k| k < width) {
            Some(k) => Dual::lane_variable(x, k),
            None => Dual::constant(x),
        })
        .collect()
}

impl<S: Scalar, T: Tangent<S>> Add for Dual<S, T> {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Dual {
            value: self.value + o.value,
            tangent: self.tangent + o.tangent,
        }
    }
}

impl<S: Scalar, T: Tangent<S>> Sub for Dual<S, T> {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Dual {
            value: self.value - o.value,
            tangent: self.tangent - o.tangent,
        }
    }
}

impl<S: Scalar, T: Tangent<S>> Mul for Dual<S, T> {
    type Output = Self;
    fn mul(self, o: Self) -> Self {
        Dual {
            value: self.value * o.value,
            tangent: o.tangent.scale(self.value) + self.tangent.scale(o.value),
        }
    }
}

impl<S: Scalar, T: Tangent<S>> Div for Dual<S, T> {
    type Output = Self;
    fn div(self, o: Self) -> Self {
        let value = self.value / o.value;
        Dual {
            value,
            tangent: (self.tangent - o.tangent.scale(value)).divide(o.value),
        }
    }
}

impl<S: Scalar, T: Tangent<S>> Neg for Dual<S, T> {
    type Output = Self;
    fn neg(self) -> Self {
        Dual {
            value: -self.value,
            tangent: -self.tangent,
        }
    }
}

impl<S: Scalar, T: Tangent<S>> Scalar for Dual<S, T> {
    fn from_f64(x: f64) -> Self {
        Dual::constant(S::from_f64(x))
    }
    fn sin(self) -> Self {
        Dual {
            value: self.value.sin(),
            tangent: self.tangent.scale(self.value.cos()),
        }
    }
    fn cos(self) -> Self {
        Dual {
            value: self.value.cos(),
            tangent: -self.tangent.scale(self.value.sin()),
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
            tangent: self.tangent.scale(S::one() - t * t),
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

    #[test]
    fn lane_tangents_are_the_directions_side_by_side() {
        // f(x, y) = x·sin(y) / (x + y): both partial derivatives in one run, lanes 0 and 1.
        let x: Dual<f64, F64Lanes> = Dual::lane_variable(0.7, 0);
        let y: Dual<f64, F64Lanes> = Dual::lane_variable(-0.3, 1);
        let f = x * y.sin() / (x + y) + y.cos() * y.tanh();
        let g = |x: f64, y: f64| x * y.sin() / (x + y) + y.cos() * y.tanh();
        let h = 1e-6;
        let dx = (g(0.7 + h, -0.3) - g(0.7 - h, -0.3)) / (2.0 * h);
        let dy = (g(0.7, -0.3 + h) - g(0.7, -0.3 - h)) / (2.0 * h);
        assert!((f.tangent.lane(0) - dx).abs() < 1e-8, "{:?} vs {dx}", f.tangent);
        assert!((f.tangent.lane(1) - dy).abs() < 1e-8, "{:?} vs {dy}", f.tangent);
        assert!(f.tangent.0[2..].iter().all(|&t| t == 0.0));
    }
}
