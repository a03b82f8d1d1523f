//! The lane vector of generated functions that carry eight tangent directions at once (the
//! derivatives of the dynamics). Such a function names it through its multiply-add strategy,
//! `M::Eight` of [`MulAdd`](crate::dispatch::MulAdd), and creates its vectors through it
//! (`arith.eight([..])`), so [`dispatch_eight`](crate::dispatch::dispatch_eight) can give it the
//! widest registers the processor has even in a build that does not target them: `wide::f64x8`
//! compiles to the build's target alone, four SSE2 instructions per operation in a default
//! build, which made the Panda's derivatives 2.7–4× slower there than in a native one.

use core::ops::{Add, Div, Mul, Neg, Sub};

/// Eight `f64` lanes with lane-wise arithmetic and the four signed multiply-adds.
pub trait EightLanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    /// `self · m + a`.
    fn mul_add(self, m: Self, a: Self) -> Self;
    /// `self · m − s`.
    fn mul_sub(self, m: Self, s: Self) -> Self;
    /// `a − self · m`.
    fn mul_neg_add(self, m: Self, a: Self) -> Self;
    /// `−(self · m) − s`.
    fn mul_neg_sub(self, m: Self, s: Self) -> Self;
    /// The eight lanes.
    fn to_array(self) -> [f64; 8];
}

/// A multiply-add method of `EightLanes` as `wide`'s method of the same name.
macro_rules! forward {
    ($method:ident) => {
        #[inline(always)]
        fn $method(self, m: Self, c: Self) -> Self {
            wide::f64x8::$method(self, m, c)
        }
    };
}

impl EightLanes for wide::f64x8 {
    forward!(mul_add);
    forward!(mul_sub);
    forward!(mul_neg_add);
    forward!(mul_neg_sub);
    #[inline(always)]
    fn to_array(self) -> [f64; 8] {
        wide::f64x8::to_array(self)
    }
}
