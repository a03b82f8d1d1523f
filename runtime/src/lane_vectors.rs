//! The lane vectors of generated functions that compute several values side by side in one
//! vector: eight tangent directions at once (the derivatives of the dynamics, [`EightLanes`]),
//! or four rows of a regressor column at once ([`FourLanes`]). Such a function names its vector
//! type through its multiply-add strategy (`M::Eight` or `M::Four` of
//! [`MulAdd`](crate::dispatch::MulAdd)) and creates its vectors through it (`arith.eight([..])`,
//! `arith.four([..])`), so [`dispatch_eight`](crate::dispatch::dispatch_eight) can give it the
//! widest registers the processor has even in a build that does not target them: `wide`'s types
//! compile to the build's target alone, four SSE2 instructions per eight-lane operation in a
//! default build, where AVX-512 takes one.

use core::ops::{Add, Div, Mul, Neg, Sub};

/// The trait of a lane vector of `$width` `f64`s: lane-wise arithmetic and the four signed
/// multiply-adds.
macro_rules! lane_vector_trait {
    ($(#[$doc:meta])* $name:ident, $width:literal) => {
        $(#[$doc])*
        pub trait $name:
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
            /// The lanes.
            fn to_array(self) -> [f64; $width];
        }
    };
}

lane_vector_trait!(
    /// Eight `f64` lanes with lane-wise arithmetic and the four signed multiply-adds.
    EightLanes, 8
);
lane_vector_trait!(
    /// Four `f64` lanes (one AVX register) with lane-wise arithmetic and the four signed
    /// multiply-adds.
    FourLanes, 4
);

/// `$trait` for `wide`'s type `$t`, each method `wide`'s method of the same name.
macro_rules! wide_lanes {
    ($trait:ident, $t:ident, $width:literal) => {
        impl $trait for wide::$t {
            wide_lanes!(@forward $t, mul_add);
            wide_lanes!(@forward $t, mul_sub);
            wide_lanes!(@forward $t, mul_neg_add);
            wide_lanes!(@forward $t, mul_neg_sub);
            #[inline(always)]
            fn to_array(self) -> [f64; $width] {
                wide::$t::to_array(self)
            }
        }
    };
    (@forward $t:ident, $method:ident) => {
        #[inline(always)]
        fn $method(self, m: Self, c: Self) -> Self {
            wide::$t::$method(self, m, c)
        }
    };
}

wide_lanes!(EightLanes, f64x8, 8);
wide_lanes!(FourLanes, f64x4, 4);
