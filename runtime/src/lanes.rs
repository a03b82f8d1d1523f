//! Several states per call, one per SIMD lane: the generated `*_lanes` functions run the same
//! straight-line code as the scalar ones on a lane type `L` (`f64x4`: AVX; `f64x8`: AVX-512),
//! so one call evaluates four or eight states for little more than the cost of one.
//!
//! A caller's `f64x4` or `f64x8` is only what goes in and out: the functions compute in the
//! processor's registers of that width with its fused multiply-adds where it has them, also in
//! a build that does not target them ([`dispatch_lanes`](crate::lane_kernels::dispatch_lanes)),
//! under the same choice as the scalar functions. So the results equal the scalar functions'
//! bit for bit on x86-64: the same IEEE operations in the same order, lane by lane, fused or
//! not alike. On AArch64 the lane types fuse their multiply-adds and the scalar code does not,
//! so the two may differ in the last bits there.

use crate::dispatch::MulAdd;
use crate::lane_kernels::LaneKernel;
use crate::robot::Kinematics;
use core::ops::{Add, Div, Mul, Neg, Sub};
use nalgebra::SVector;
pub use wide::{f64x4, f64x8};

/// A vector of `WIDTH` `f64`s with lane-wise arithmetic: what the `*_lanes` functions compute in.
pub trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    /// States per call.
    const WIDTH: usize;
    /// Every lane `x`.
    fn splat(x: f64) -> Self;
    /// Lane `k` is `f(k)`.
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self;
    /// Lane `k` (`k < WIDTH`).
    fn lane(&self, k: usize) -> f64;
    /// `self · b + c` lane by lane, as [`mul_add`](crate::mul_add) computes it for one lane
    /// (one rounding where the target has FMA).
    fn mul_add(self, b: Self, c: Self) -> Self;
    /// The sine and cosine of every lane, each exactly as [`JointTrig::new`](crate::JointTrig::new)
    /// computes it.
    fn sin_cos(self) -> (Self, Self);
    /// `f` applied lane by lane (the few non-arithmetic nodes: `sign`, `tanh`, the sine of a
    /// constant-shifted angle).
    #[inline]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Self::from_fn(|k| f(self.lane(k)))
    }
    /// [`Lanes::sin_cos`] of each of `q` (what [`JointTrigLanes::new`] computes): for `f64x4` and
    /// `f64x8`, all in one function compiled for the processor's AVX2 and FMA where a build
    /// chooses at run time.
    #[doc(hidden)]
    #[inline]
    fn sin_cos_each<const N: usize>(q: &[Self; N]) -> ([Self; N], [Self; N]) {
        crate::trig::each(q, Self::sin_cos)
    }
    /// Runs a generated lane function's kernel under the multiply-add strategy `M`, computing
    /// in the strategy's vector of this type's width where it has one (`f64x4`, `f64x8`), else
    /// in this type (plumbing for generated code: [`dispatch_lanes`](crate::lane_kernels::dispatch_lanes)).
    #[doc(hidden)]
    #[inline(always)]
    fn run_lane_kernel<M: MulAdd, K: LaneKernel<Self, A>, A>(arith: M, args: A) -> K::Output {
        K::run::<M, Self>(arith, args)
    }
}

macro_rules! lanes {
    ($t:ty, $w:literal, $sin_cos:path, $sin_cos_each:path, $vector:ident) => {
        impl Lanes for $t {
            const WIDTH: usize = $w;
            #[inline]
            fn sin_cos_each<const N: usize>(q: &[Self; N]) -> ([Self; N], [Self; N]) {
                $sin_cos_each(q)
            }
            #[inline(always)]
            fn run_lane_kernel<M: MulAdd, K: LaneKernel<Self, A>, A>(arith: M, args: A) -> K::Output {
                K::run::<M, M::$vector>(arith, args)
            }
            #[inline(always)]
            fn splat(x: f64) -> Self {
                <$t>::splat(x)
            }
            #[inline(always)]
            fn from_fn(f: impl FnMut(usize) -> f64) -> Self {
                <$t>::new(core::array::from_fn(f))
            }
            #[inline(always)]
            fn lane(&self, k: usize) -> f64 {
                self.as_array()[k]
            }
            #[inline(always)]
            fn mul_add(self, b: Self, c: Self) -> Self {
                <$t>::mul_add(self, b, c)
            }
            #[inline(always)]
            fn sin_cos(self) -> (Self, Self) {
                $sin_cos(self)
            }
        }
    };
}
lanes!(
    f64x4,
    4,
    crate::trig::sin_cos_f64x4,
    crate::trig::sin_cos_f64x4_all,
    Four
);
lanes!(
    f64x8,
    8,
    crate::trig::sin_cos_f64x8,
    crate::trig::sin_cos_f64x8_all,
    Eight
);

/// `sign(x)` with `sign(0) = 0` (and 0 for NaN), unlike `f64::signum` (which gives ±1 at ±0):
/// a joint at rest has no Coulomb friction, and the mass matrix through the regressor
/// (`Y(q, 0, 0, eᵢ) − Y(q, 0, 0, 0)`) must not pick up a friction column.
#[inline]
pub fn sign(x: f64) -> f64 {
    if x > 0.0 {
        1.0
    } else if x < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The joint angles, sines and cosines of `L::WIDTH` states (lane `k` is state `k`).
#[derive(Clone, Copy, Debug)]
pub struct JointTrigLanes<const N: usize, L> {
    pub q: [L; N],
    pub sin: [L; N],
    pub cos: [L; N],
}

impl<const N: usize, L: Lanes> JointTrigLanes<N, L> {
    /// From the joint angles of each lane; the sines and cosines as
    /// [`JointTrig::new`](crate::JointTrig::new) computes them, so lane `k` matches the scalar
    /// functions exactly.
    pub fn new(q: &[L; N]) -> Self {
        let (sin, cos) = L::sin_cos_each(q);
        JointTrigLanes { q: *q, sin, cos }
    }
}

/// Lane `k` holds `vectors[k]`; lanes beyond `vectors.len()` repeat the last one (zeros if
/// there is none), so a short final batch computes valid states whose results are ignored.
pub fn pack<L: Lanes, const N: usize>(vectors: &[SVector<f64, N>]) -> [L; N] {
    let pick = |k: usize| vectors.get(k).or(vectors.last());
    core::array::from_fn(|i| L::from_fn(|k| pick(k).map_or(0.0, |v| v[i])))
}

/// Lane `k` of a joint-space vector.
pub fn unpack<L: Lanes, const N: usize>(x: &[L; N], k: usize) -> SVector<f64, N> {
    SVector::from_fn(|i, _| x[i].lane(k))
}

/// The functions a generated robot also emits in lane form: several states per call. Generated
/// with the group `base_parameters`.
///
/// `B` is the number of base parameters (of [`BaseParameters`](crate::BaseParameters)).
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `base_parameters`, which brings the lane functions",
    note = "add `base_parameters` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait LaneDynamics<const N: usize, const B: usize>: Kinematics<N> {
    /// Inverse dynamics `τ = D q̈ + C q̇ + g`, one state per lane.
    fn inverse_dynamics_lanes<L: Lanes>(t: &JointTrigLanes<N, L>, qd: &[L; N], qdd: &[L; N]) -> [L; N];
    /// The base regressor in torque form `Y_b(q, q̇, q̇, q̈)`, one state per lane, column-major
    /// (`[column][row]`).
    fn base_torque_regressor_lanes<L: Lanes>(
        t: &JointTrigLanes<N, L>,
        qd: &[L; N],
        qdd: &[L; N],
    ) -> [[L; N]; B];
}

#[cfg(test)]
mod tests {
    use super::{f64x4, f64x8, Lanes};

    /// Every lane's sine and cosine are bit for bit those of the scalar path
    /// (`JointTrig::new`), inside the kernel's range, beyond it, and at the special values.
    fn lanes_match_the_scalar_path<L: Lanes>() {
        let mut rng = crate::SplitMix64::new(11);
        let special = [
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            -f64::INFINITY,
            1e5,
            -1e5,
            1.5e5,
            1e300,
        ];
        for round in 0..2_000 {
            let q = L::from_fn(|k| match (round + k) % 5 {
                0 => special[(round + k) % special.len()],
                1 => rng.uniform((-2e5, 2e5)),
                _ => rng.uniform((-7.0, 7.0)),
            });
            let (sin, cos) = q.sin_cos();
            let angles: [f64; 8] = core::array::from_fn(|k| q.lane(k % L::WIDTH));
            let (s, c) = crate::trig::sin_cos_all(&angles);
            for k in 0..L::WIDTH {
                let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
                assert!(
                    same(sin.lane(k), s[k]) && same(cos.lane(k), c[k]),
                    "q = {:e}: lanes ({}, {}), scalar ({}, {})",
                    q.lane(k),
                    sin.lane(k),
                    cos.lane(k),
                    s[k],
                    c[k]
                );
            }
        }
    }

    #[test]
    fn four_lanes_match_the_scalar_path() {
        lanes_match_the_scalar_path::<f64x4>();
    }

    #[test]
    fn eight_lanes_match_the_scalar_path() {
        lanes_match_the_scalar_path::<f64x8>();
    }
}
