//! A reference scalar of about 106 significant bits: the unevaluated sum of two `f64`s
//! (Dekker's double-double), so that the generic algorithms, run on it, give the exact answer of
//! the `f64` problem to far below `f64` rounding. Written here rather than taken from a crate:
//! it needs the `Scalar` trait of the generator, and the four operations are a few lines each.
//!
//! Sines and cosines are the `f64` ones of the leading part: the reference solves the problem
//! whose joint sines and cosines are those `f64` values, the same inputs the `f64` code starts
//! from, so the comparison measures the algorithm's rounding, not the inputs'.

use dyngen_codegen::internals::scalar::Scalar;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// `hi + lo` with `|lo| ≤ ulp(hi) / 2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoubleDouble {
    pub hi: f64,
    pub lo: f64,
}

/// `a + b` exactly, as a rounded sum and its error (Knuth's two-sum).
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let v = s - a;
    (s, (a - (s - v)) + (b - v))
}

/// `a · b` exactly, as a rounded product and its error (with a fused multiply-add).
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

fn renormalised(hi: f64, lo: f64) -> DoubleDouble {
    let (hi, lo) = two_sum(hi, lo);
    DoubleDouble { hi, lo }
}

impl DoubleDouble {
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }
}

impl Add for DoubleDouble {
    type Output = DoubleDouble;
    fn add(self, o: DoubleDouble) -> DoubleDouble {
        let (s, e) = two_sum(self.hi, o.hi);
        let (t, f) = two_sum(self.lo, o.lo);
        let (s, e) = two_sum(s, e + t);
        renormalised(s, e + f)
    }
}

impl Neg for DoubleDouble {
    type Output = DoubleDouble;
    fn neg(self) -> DoubleDouble {
        DoubleDouble {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

impl Sub for DoubleDouble {
    type Output = DoubleDouble;
    fn sub(self, o: DoubleDouble) -> DoubleDouble {
        self + -o
    }
}

impl Mul for DoubleDouble {
    type Output = DoubleDouble;
    fn mul(self, o: DoubleDouble) -> DoubleDouble {
        let (p, e) = two_prod(self.hi, o.hi);
        renormalised(p, e + (self.hi * o.lo + self.lo * o.hi))
    }
}

impl Div for DoubleDouble {
    type Output = DoubleDouble;
    fn div(self, o: DoubleDouble) -> DoubleDouble {
        // Two Newton-style corrections of the f64 quotient.
        let q1 = self.hi / o.hi;
        let r = self - o * DoubleDouble::from_f64(q1);
        let q2 = r.hi / o.hi;
        let r = r - o * DoubleDouble::from_f64(q2);
        let q3 = r.hi / o.hi;
        DoubleDouble::from_f64(q1) + DoubleDouble::from_f64(q2) + DoubleDouble::from_f64(q3)
    }
}

impl Scalar for DoubleDouble {
    fn from_f64(x: f64) -> Self {
        DoubleDouble { hi: x, lo: 0.0 }
    }
    fn sin(self) -> Self {
        DoubleDouble::from_f64(self.hi.sin())
    }
    fn cos(self) -> Self {
        DoubleDouble::from_f64(self.hi.cos())
    }
    fn sign(self) -> Self {
        let x = self.to_f64();
        DoubleDouble::from_f64(if x > 0.0 {
            1.0
        } else if x < 0.0 {
            -1.0
        } else {
            0.0
        })
    }
    fn tanh(self) -> Self {
        DoubleDouble::from_f64(self.to_f64().tanh())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dd(x: f64) -> DoubleDouble {
        DoubleDouble::from_f64(x)
    }

    #[test]
    fn keeps_what_f64_rounds_away() {
        // (1 + 2⁻⁶⁰) − 1 is 0 in f64 and 2⁻⁶⁰ here.
        let tiny = 2f64.powi(-60);
        assert_eq!(((dd(1.0) + dd(tiny)) - dd(1.0)).to_f64(), tiny);
        // 1/3 · 3 − 1: exactly 0 to about 1e-32.
        let third = dd(1.0) / dd(3.0);
        assert!(((third * dd(3.0)) - dd(1.0)).to_f64().abs() < 1e-31);
        // (1 + 2⁻³⁰)² = 1 + 2⁻²⁹ + 2⁻⁶⁰, the last term beyond f64.
        let x = dd(1.0) + dd(2f64.powi(-30));
        let square = x * x - dd(1.0) - dd(2f64.powi(-29));
        assert_eq!(square.to_f64(), 2f64.powi(-60));
    }
}
