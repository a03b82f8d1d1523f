//! The `*_lanes` functions (several states per call) run with the processor's widest registers
//! and fused multiply-adds even in a build that does not target them, as the one-state functions
//! do ([`dispatch`](crate::dispatch)).
//!
//! A caller's lane type (`f64x4`, `f64x8`: `wide`'s) compiles to the build's target alone: in a
//! default x86-64 build, SSE2 and no FMA, where four states per call ran slower per state than
//! one per call. So a lane function is written once as a [`LaneKernel`], generic over the vector type
//! it computes in ([`LaneVector`]), and called through [`dispatch_lanes`]: the kernel runs under
//! [`dispatch_eight`](crate::dispatch::dispatch_eight)'s choice of multiply-adds, computing in
//! that strategy's vector of the caller's width (`M::Four` for four lanes, `M::Eight` for eight:
//! AVX2 or AVX-512 registers where the processor has them): it converts the caller's lanes in
//! ([`lanes_in`], [`trig_in`]) and each output back as it stores it ([`lane_out`]). A caller's
//! own [`Lanes`] type of another width runs the kernel in that type, as written.
//!
//! A compute vector is made only through the strategy value (`splat_in(arith, x)`), never from
//! nothing: a value of the strategy exists only where the processor has its instructions, which
//! is what makes the AVX types' safe operations sound.

use crate::dispatch::{Kernel, MulAdd};
use crate::lanes::{JointTrigLanes, Lanes};
use core::marker::PhantomData;
use core::ops::{Add, Div, Mul, Neg, Sub};

/// The vector a lane kernel computes in, under the multiply-add strategy `M`: lane-wise
/// arithmetic, and vectors made only through a value of `M`.
pub trait LaneVector<M>:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    /// Every lane `x`.
    fn splat_in(arith: M, x: f64) -> Self;
    /// Lane `k` is `f(k)`.
    fn from_fn_in(arith: M, f: impl FnMut(usize) -> f64) -> Self;
    /// Lane `k`.
    fn lane(&self, k: usize) -> f64;
    /// `self · b + c` lane by lane, fused where `M` fuses.
    fn mul_add(self, b: Self, c: Self) -> Self;
    /// `f` applied lane by lane (the few non-arithmetic nodes: `sign`, `tanh`, the sine of a
    /// constant-shifted angle).
    #[inline]
    fn map_in(self, arith: M, f: impl Fn(f64) -> f64) -> Self {
        Self::from_fn_in(arith, |k| f(self.lane(k)))
    }
}

/// A caller's lane type computes as itself, under any strategy (its operations are the build's,
/// safe on any processor the build runs on).
impl<M, T: Lanes> LaneVector<M> for T {
    #[inline(always)]
    fn splat_in(_: M, x: f64) -> Self {
        T::splat(x)
    }
    #[inline(always)]
    fn from_fn_in(_: M, f: impl FnMut(usize) -> f64) -> Self {
        T::from_fn(f)
    }
    #[inline(always)]
    fn lane(&self, k: usize) -> f64 {
        Lanes::lane(self, k)
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        Lanes::mul_add(self, b, c)
    }
}

/// A `*_lanes` function's body for the caller's lane type `C`: `Args` are its arguments (in
/// `C`), [`LaneKernel::run`] computes in `L` and returns the result in `C`. Implementations
/// mark `run` `#[inline(always)]`, so that the dispatch compiles it with the features it enables.
pub trait LaneKernel<C: Lanes, Args> {
    type Output;
    fn run<M: MulAdd, L: LaneVector<M>>(arith: M, args: Args) -> Self::Output;
}

/// Runs lane kernel `K` on `args` in the caller's lane type `C`, with the processor's widest
/// registers and fused multiply-adds where it has them (see the module).
#[inline(always)]
pub fn dispatch_lanes<K: LaneKernel<C, Args>, C: Lanes, Args>(args: Args) -> K::Output {
    crate::dispatch::dispatch_eight::<InLanes<K, C>, Args>(args)
}

/// [`LaneKernel`] `K` as a [`Kernel`]: the strategy's vector of `C`'s width
/// ([`Lanes::run_lane_kernel`]).
struct InLanes<K, C>(PhantomData<(K, C)>);

impl<K: LaneKernel<C, Args>, C: Lanes, Args> Kernel<Args> for InLanes<K, C> {
    type Output = K::Output;
    #[inline(always)]
    fn run<M: MulAdd>(arith: M, args: Args) -> K::Output {
        C::run_lane_kernel::<M, K, Args>(arith, args)
    }
}

/// The caller's lanes `x` as compute vectors.
#[inline(always)]
pub fn lanes_in<M: Copy, C: Lanes, L: LaneVector<M>, const N: usize>(arith: M, x: &[C; N]) -> [L; N] {
    core::array::from_fn(|i| lane_out(arith, x[i]))
}

/// [`lanes_in`] of the sines and cosines (and angles) of `t`.
#[inline(always)]
pub fn trig_in<M: Copy, C: Lanes, L: LaneVector<M>, const N: usize>(
    arith: M,
    t: &JointTrigLanes<N, C>,
) -> JointTrigLanes<N, L> {
    JointTrigLanes {
        q: lanes_in(arith, &t.q),
        sin: lanes_in(arith, &t.sin),
        cos: lanes_in(arith, &t.cos),
    }
}

/// A lane vector in another lane type under the same strategy (a computed one in the caller's,
/// or the caller's in the kernel's): where the two are one type, nothing.
#[inline(always)]
pub fn lane_out<M: Copy, L: LaneVector<M>, C: LaneVector<M>>(arith: M, x: L) -> C {
    C::from_fn_in(arith, |k| x.lane(k))
}

#[cfg(test)]
mod tests {
    use super::{dispatch_lanes, lane_out, lanes_in, LaneKernel, LaneVector};
    use crate::dispatch::MulAdd;
    use crate::lanes::{f64x4, f64x8, Lanes};
    use core::ops::{Add, Div, Mul, Neg, Sub};

    /// `a·b + 1` lane by lane, through every conversion a generated lane kernel uses.
    struct MulAddOne;
    impl<C: Lanes> LaneKernel<C, (&[C; 3], &[C; 3])> for MulAddOne {
        type Output = [C; 3];
        #[inline(always)]
        fn run<M: MulAdd, L: LaneVector<M>>(arith: M, (a, b): (&[C; 3], &[C; 3])) -> [C; 3] {
            let (a, b): ([L; 3], [L; 3]) = (lanes_in(arith, a), lanes_in(arith, b));
            core::array::from_fn(|i| lane_out(arith, a[i].mul_add(b[i], L::splat_in(arith, 1.0))))
        }
    }

    /// A caller's own lane type of two lanes, which the kernel computes in as it is.
    #[derive(Clone, Copy, Debug)]
    struct Two([f64; 2]);
    macro_rules! two_operator {
        ($op:ident, $method:ident, $symbol:tt) => {
            impl $op for Two {
                type Output = Two;
                fn $method(self, b: Two) -> Two {
                    Two([self.0[0] $symbol b.0[0], self.0[1] $symbol b.0[1]])
                }
            }
        };
    }
    two_operator!(Add, add, +);
    two_operator!(Sub, sub, -);
    two_operator!(Mul, mul, *);
    two_operator!(Div, div, /);
    impl Neg for Two {
        type Output = Two;
        fn neg(self) -> Two {
            Two([-self.0[0], -self.0[1]])
        }
    }
    impl Lanes for Two {
        const WIDTH: usize = 2;
        fn splat(x: f64) -> Two {
            Two([x; 2])
        }
        fn from_fn(mut f: impl FnMut(usize) -> f64) -> Two {
            Two([f(0), f(1)])
        }
        fn lane(&self, k: usize) -> f64 {
            self.0[k]
        }
        fn mul_add(self, b: Two, c: Two) -> Two {
            self * b + c
        }
        fn sin_cos(self) -> (Two, Two) {
            let [(s0, c0), (s1, c1)] = self.0.map(libm::sincos);
            (Two([s0, s1]), Two([c0, c1]))
        }
    }

    /// Every lane of the dispatched kernel's result is `a·b + 1` of that lane, once or twice
    /// rounded as the dispatch chose, for `wide`'s types (computed in the strategy's vectors)
    /// and for a lane type of another width (computed in itself).
    fn computes_lane_by_lane<C: Lanes>() {
        let mut rng = crate::SplitMix64::new(3);
        let mut draw = || -> [C; 3] { core::array::from_fn(|_| C::from_fn(|_| rng.uniform((-4.0, 4.0)))) };
        let (a, b) = (draw(), draw());
        let got = dispatch_lanes::<MulAddOne, C, _>((&a, &b));
        for i in 0..3 {
            for k in 0..C::WIDTH {
                let (x, y) = (a[i].lane(k), b[i].lane(k));
                let want = x * y + 1.0;
                let gap = (got[i].lane(k) - want).abs();
                assert!(
                    gap <= 1e-15 * want.abs().max(1.0),
                    "width {}, {i}/{k}: {gap:e}",
                    C::WIDTH
                );
            }
        }
    }

    #[test]
    fn lane_kernels_compute_lane_by_lane_in_any_width() {
        computes_lane_by_lane::<f64x4>();
        computes_lane_by_lane::<f64x8>();
        computes_lane_by_lane::<Two>();
    }
}
