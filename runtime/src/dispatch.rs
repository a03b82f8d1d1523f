//! Run-time choice of the processor's fused multiply-add for generated functions.
//!
//! Rust never contracts `a * b + c`, so a build that does not target FMA (the default
//! `x86-64`, without `-C target-cpu`) runs every multiply-add of the generated code as two
//! instructions with two roundings, and without the three-operand AVX encodings, far slower
//! than in a `target-cpu=native` build. Each generated
//! function is therefore written once as a [`Kernel`], generic over how it multiplies and adds
//! ([`MulAdd`]), and called through [`dispatch`]:
//! - in a build that targets AVX2 and FMA, the kernel runs [`Fused`] directly (nothing is
//!   checked at run time, nothing is compiled twice);
//! - in any other optimised x86-64 build, a processor that has AVX2 and FMA (asked once,
//!   cached) runs the kernel [`Fused`] inside a function compiled for those features, and any
//!   other runs it [`Unfused`], exactly as written;
//! - in debug builds (`debug_assertions`) and on other architectures, [`Unfused`].
//!
//! The `unsafe` this takes lives here, not in generated code: a [`Fused`] value exists only
//! where the processor has FMA, because only this module creates one.
//!
//! [`set_fused_multiply_adds`] makes a run-time choosing build run everything unfused, as on a
//! processor without FMA: tests compare the two forms with it (it is reached through the hidden
//! `__private`, like everything here, and is not part of the API).

/// How a kernel computes `a·b + c`, and in which registers it holds eight or four lanes.
pub trait MulAdd: Copy {
    /// The eight-lane vector of a kernel that carries tangents in lanes ([`dispatch_eight`]).
    type Eight: EightLanes + LaneVector<Self>;
    /// The four-lane vector of a kernel that computes four rows of a column at once (the
    /// regressors, [`dispatch_eight`]), and of a `*_lanes` function called with four lanes.
    type Four: FourLanes + LaneVector<Self>;
    fn mul_add(self, a: f64, b: f64, c: f64) -> f64;
    /// The lane vector of `lanes`.
    fn eight(self, lanes: [f64; 8]) -> Self::Eight;
    /// Every lane `x`.
    #[inline(always)]
    fn splat_eight(self, x: f64) -> Self::Eight {
        self.eight([x; 8])
    }
    /// The four-lane vector of `lanes`.
    fn four(self, lanes: [f64; 4]) -> Self::Four;
    /// Every lane `x`.
    #[inline(always)]
    fn splat_four(self, x: f64) -> Self::Four {
        self.four([x; 4])
    }
}

use crate::lane_kernels::LaneVector;
use crate::lane_vectors::{EightLanes, FourLanes};

/// `a·b + c` as written: two roundings, on any processor.
#[derive(Clone, Copy, Debug)]
pub struct Unfused;

impl MulAdd for Unfused {
    type Eight = wide::f64x8;
    type Four = wide::f64x4;
    #[inline(always)]
    fn mul_add(self, a: f64, b: f64, c: f64) -> f64 {
        a * b + c
    }
    #[inline(always)]
    fn eight(self, lanes: [f64; 8]) -> wide::f64x8 {
        wide::f64x8::new(lanes)
    }
    #[inline(always)]
    fn four(self, lanes: [f64; 4]) -> wide::f64x4 {
        wide::f64x4::new(lanes)
    }
}

/// `a·b + c` in one instruction with one rounding. Only [`dispatch`] creates one, and only
/// where the processor has FMA: that is what makes [`MulAdd::mul_add`] sound on it.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub struct Fused(());

#[cfg(target_arch = "x86_64")]
impl MulAdd for Fused {
    /// `wide`'s where the build targets AVX2 and FMA (its instructions are the build's, 512-bit
    /// ones where it targets AVX-512); two AVX registers where the build chooses at run time.
    #[cfg(all(target_feature = "avx2", target_feature = "fma"))]
    type Eight = wide::f64x8;
    #[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
    type Eight = crate::lane_vectors_x86::Avx2Eight;
    #[cfg(all(target_feature = "avx2", target_feature = "fma"))]
    type Four = wide::f64x4;
    #[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
    type Four = crate::lane_vectors_x86::Avx2Four;
    #[inline(always)]
    fn mul_add(self, a: f64, b: f64, c: f64) -> f64 {
        // SAFETY: a `Fused` exists only where the processor has FMA (see the type). Inlined into
        // a kernel that `dispatch` compiled with FMA enabled, this is one `vfmadd`.
        unsafe { crate::mul_add::fused_instruction(a, b, c) }
    }
    #[inline(always)]
    fn eight(self, lanes: [f64; 8]) -> Self::Eight {
        #[cfg(all(target_feature = "avx2", target_feature = "fma"))]
        return wide::f64x8::new(lanes);
        // SAFETY: a `Fused` exists only where the processor has AVX2 and FMA (see the type).
        #[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
        return unsafe { crate::lane_vectors_x86::Avx2Eight::new(lanes) };
    }
    #[inline(always)]
    fn four(self, lanes: [f64; 4]) -> Self::Four {
        #[cfg(all(target_feature = "avx2", target_feature = "fma"))]
        return wide::f64x4::new(lanes);
        // SAFETY: a `Fused` exists only where the processor has AVX2 and FMA (see the type).
        #[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
        return unsafe { crate::lane_vectors_x86::Avx2Four::new(lanes) };
    }
}

/// [`Fused`] with eight lanes in one AVX-512 register, for kernels of [`dispatch_eight`] in a
/// build that chooses at run time. Only `dispatch_eight` creates one, and only where the
/// processor has AVX-512 (F, DQ, BW, VL), AVX2 and FMA.
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
#[derive(Clone, Copy, Debug)]
pub struct Fused512(());

#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
impl MulAdd for Fused512 {
    type Eight = crate::lane_vectors_x86::Avx512Eight;
    /// Four lanes fill one AVX register (with AVX-512's 32 of them and its EVEX encodings).
    type Four = crate::lane_vectors_x86::Avx2Four;
    #[inline(always)]
    fn mul_add(self, a: f64, b: f64, c: f64) -> f64 {
        // SAFETY: a `Fused512` exists only where the processor has FMA (see the type).
        unsafe { crate::mul_add::fused_instruction(a, b, c) }
    }
    #[inline(always)]
    fn eight(self, lanes: [f64; 8]) -> Self::Eight {
        // SAFETY: a `Fused512` exists only where the processor has AVX-512F (see the type).
        unsafe { crate::lane_vectors_x86::Avx512Eight::new(lanes) }
    }
    #[inline(always)]
    fn four(self, lanes: [f64; 4]) -> Self::Four {
        // SAFETY: a `Fused512` exists only where the processor has AVX2 and FMA (see the type).
        unsafe { crate::lane_vectors_x86::Avx2Four::new(lanes) }
    }
}

/// A generated function's body, written once for both ways of multiplying and adding.
/// `Args` are its arguments (a tuple); implementations mark [`Kernel::run`]
/// `#[inline(always)]`, so that [`dispatch`] compiles the whole body with the processor
/// features it enables.
pub trait Kernel<Args> {
    type Output;
    fn run<M: MulAdd>(arith: M, args: Args) -> Self::Output;
}

/// Runs kernel `K` on `args` with the processor's fused multiply-add where it has one.
#[inline(always)]
pub fn dispatch<K: Kernel<Args>, Args>(args: Args) -> K::Output {
    choice::dispatch::<K, Args>(args)
}

/// [`dispatch`] for a kernel that carries lane vectors (`M::Eight`, `M::Four`), or that holds far more values
/// than sixteen registers (the derivatives of the dynamics, `C`, the regressors): in a build
/// that chooses at run time, a processor with AVX-512 (F, DQ, BW, VL) runs it with [`Fused512`]
/// inside a function compiled for AVX-512 (one register per lane vector and 32 registers, as a
/// `-C target-cpu=native` build on it), one without with [`Fused`] (two AVX registers per lane
/// vector). Only these kernels are compiled a third time.
#[inline(always)]
pub fn dispatch_eight<K: Kernel<Args>, Args>(args: Args) -> K::Output {
    choice::dispatch_eight::<K, Args>(args)
}

/// [`dispatch`] for a scalar kernel (no lane vectors) that holds far more values than sixteen
/// registers (`C`, the regressors' products, derivatives taken one direction per run): in a
/// build that chooses at run time, an AMD processor with AVX-512 runs it as [`dispatch_eight`]
/// does, inside a function compiled for AVX-512, for its 32 registers; an Intel one in the
/// AVX2 copy. There LLVM turns some of a scalar kernel's operations and spills into 512-bit
/// instructions, and while those are in flight an Intel core leaves the rest of the vector
/// arithmetic fewer ports, so such a kernel runs slower in the AVX-512 copy than in the AVX2
/// one, which is as fast as native there. AMD cores run 512-bit instructions without that
/// penalty, and there the 32 registers save spills (`docs/performance-notes.md`).
#[inline(always)]
pub fn dispatch_many<K: Kernel<Args>, Args>(args: Args) -> K::Output {
    choice::dispatch_many::<K, Args>(args)
}

/// Whether lane kernels ([`dispatch_eight`]) hold their eight lanes in one AVX-512 register:
/// in a build that targets AVX-512F, always (the lane type's instructions are the build's); in
/// an optimised x86-64 build that chooses at run time, where the processor has AVX-512 (F, DQ,
/// BW, VL) and runs [`Fused`] (unless [`set_avx512_lanes`] turned it off); never elsewhere.
#[inline]
pub fn avx512_lanes() -> bool {
    choice::avx512_lanes()
}

/// Lets a build that chooses at run time hold lane kernels' vectors in two AVX registers even
/// on a processor with AVX-512 (`false`), as on one without, or in one AVX-512 register again
/// (`true`, the default), for the whole program; the results are the same bit for bit (the
/// same fused operations lane by lane), only the speed differs. For tests and for measuring an
/// AVX2 processor's speed on an AVX-512 one. No effect elsewhere. Returns [`avx512_lanes`] after
/// the change.
pub fn set_avx512_lanes(enabled: bool) -> bool {
    choice::set_avx512_lanes(enabled);
    avx512_lanes()
}

/// Whether generated functions run [`Fused`] here: always in a build that targets AVX2 and FMA;
/// in an optimised x86-64 build that does not, where the processor has both (unless
/// [`set_fused_multiply_adds`] turned it off); never elsewhere.
#[inline]
pub fn fused_multiply_adds() -> bool {
    choice::fused()
}

/// Lets a build that chooses at run time (optimised, x86-64, not targeting FMA) run every
/// generated function unfused (`false`) or, where the processor has FMA, fused again (`true`,
/// the default), for the whole program. No effect elsewhere. Returns [`fused_multiply_adds`]
/// after the change.
pub fn set_fused_multiply_adds(enabled: bool) -> bool {
    choice::set(enabled);
    fused_multiply_adds()
}

/// A build that targets AVX2 and FMA: the fused form only, nothing checked at run time.
#[cfg(all(target_arch = "x86_64", target_feature = "avx2", target_feature = "fma"))]
mod choice {
    use super::{Fused, Kernel};

    #[inline(always)]
    pub fn dispatch<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        K::run(Fused(()), args)
    }

    #[inline(always)]
    pub fn dispatch_eight<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        crate::stack_align::align_stack_frame();
        K::run(Fused(()), args)
    }

    #[inline(always)]
    pub fn dispatch_many<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        dispatch_eight::<K, Args>(args)
    }

    pub fn fused() -> bool {
        true
    }

    pub fn set(_: bool) {}

    pub fn avx512_lanes() -> bool {
        cfg!(target_feature = "avx512f")
    }

    pub fn set_avx512_lanes(_: bool) {}
}

/// An optimised x86-64 build that does not target AVX2 and FMA: both forms, chosen by the
/// processor (asked once, cached).
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma")),
    not(debug_assertions)
))]
mod choice {
    use super::{Fused, Fused512, Kernel, Unfused};
    use core::sync::atomic::{AtomicBool, Ordering};

    /// Whether [`super::set_fused_multiply_adds`] turned the fused form off.
    static UNFUSED_REQUESTED: AtomicBool = AtomicBool::new(false);
    /// Whether [`super::set_avx512_lanes`] turned the 512-bit lanes off.
    static AVX512_DECLINED: AtomicBool = AtomicBool::new(false);

    #[inline(always)]
    pub fn dispatch<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        if fused() {
            // SAFETY: the processor has AVX2 and FMA (checked by `fused`).
            unsafe { run_fused::<K, Args>(args) }
        } else {
            K::run(Unfused, args)
        }
    }

    #[inline(always)]
    pub fn dispatch_eight<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        if !fused() {
            K::run(Unfused, args)
        } else if avx512_lanes() {
            // SAFETY: the processor has AVX-512 F, DQ, BW, VL, AVX2 and FMA (checked by
            // `avx512_lanes`).
            unsafe { run_fused512::<K, Args>(args) }
        } else {
            // SAFETY: the processor has AVX2 and FMA (checked by `fused`).
            unsafe { run_fused_eight::<K, Args>(args) }
        }
    }

    #[inline(always)]
    pub fn dispatch_many<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        if avx512_lanes() && crate::cpu::is_intel() {
            // SAFETY: the processor has AVX2 and FMA (`avx512_lanes` checks `fused`).
            unsafe { run_fused_eight::<K, Args>(args) }
        } else {
            dispatch_eight::<K, Args>(args)
        }
    }

    #[inline]
    pub fn fused() -> bool {
        crate::cpu::has_avx2_fma() && !UNFUSED_REQUESTED.load(Ordering::Relaxed)
    }

    pub fn set(enabled: bool) {
        UNFUSED_REQUESTED.store(!enabled, Ordering::Relaxed);
    }

    #[inline]
    pub fn avx512_lanes() -> bool {
        fused() && crate::cpu::has_avx512() && !AVX512_DECLINED.load(Ordering::Relaxed)
    }

    pub fn set_avx512_lanes(enabled: bool) {
        AVX512_DECLINED.store(!enabled, Ordering::Relaxed);
    }

    /// `K` compiled for AVX2 and FMA: its `#[inline(always)]` body, and the [`Fused`]
    /// multiply-adds in it, become part of this function.
    ///
    /// # Safety
    /// The processor must have AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn run_fused<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        K::run(Fused(()), args)
    }

    /// [`run_fused`] for a lane kernel, whose many spilled vectors want an aligned frame (a
    /// scalar kernel spills few, and does not pay for the realignment).
    ///
    /// # Safety
    /// The processor must have AVX2 and FMA.
    #[target_feature(enable = "avx2,fma")]
    unsafe fn run_fused_eight<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        crate::stack_align::align_stack_frame();
        K::run(Fused(()), args)
    }

    /// `K` compiled for AVX-512 (F, DQ, BW, VL), AVX2 and FMA, its lane vectors in 512-bit
    /// registers. With F alone, the kernel's 128- and 256-bit instructions could not use the
    /// EVEX forms a native build uses: the Panda's `∂τ/∂x` was 29.5 KB of code instead of 27.1,
    /// and slower than a native build, which it matches with them.
    ///
    /// # Safety
    /// The processor must have AVX-512 F, DQ, BW and VL, AVX2 and FMA.
    #[target_feature(enable = "avx512f,avx512dq,avx512bw,avx512vl,avx2,fma")]
    unsafe fn run_fused512<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        crate::stack_align::align_stack_frame();
        K::run(Fused512(()), args)
    }
}

/// Any other build: the unfused form only. Debug builds are among them, because compiling every
/// generated function twice, once inlined into an AVX2/FMA function, made the test build of
/// the generated robots several times slower (minutes) for no use there.
#[cfg(not(any(
    all(target_arch = "x86_64", target_feature = "avx2", target_feature = "fma"),
    all(
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma")),
        not(debug_assertions)
    )
)))]
mod choice {
    use super::{Kernel, Unfused};

    #[inline(always)]
    pub fn dispatch<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        K::run(Unfused, args)
    }

    #[inline(always)]
    pub fn dispatch_eight<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        K::run(Unfused, args)
    }

    #[inline(always)]
    pub fn dispatch_many<K: Kernel<Args>, Args>(args: Args) -> K::Output {
        K::run(Unfused, args)
    }

    pub fn fused() -> bool {
        false
    }

    pub fn set(_: bool) {}

    pub fn avx512_lanes() -> bool {
        false
    }

    pub fn set_avx512_lanes(_: bool) {}
}

#[cfg(test)]
mod tests {
    use super::{dispatch, Kernel, MulAdd};

    /// `(1 + 2⁻³⁰)² − (1 + 2⁻²⁹)`, which is 2⁻⁶⁰ with one rounding and 0 with two.
    struct SquareMinus;
    impl Kernel<(f64, f64)> for SquareMinus {
        type Output = f64;
        #[inline(always)]
        fn run<M: MulAdd>(arith: M, (x, c): (f64, f64)) -> f64 {
            arith.mul_add(x, x, -c)
        }
    }

    /// The one test of this crate that changes the process-wide choice, so no other test here
    /// can see it change.
    #[test]
    fn rounds_once_exactly_where_the_processor_has_fma_unless_told_not_to() {
        let x = 1.0 + f64::powi(2.0, -30);
        let c = 1.0 + f64::powi(2.0, -29);
        let fused = f64::powi(2.0, -60);
        assert_eq!(super::Unfused.mul_add(x, x, -c), 0.0);
        let expected = |on: bool| if on { fused } else { 0.0 };
        assert_eq!(
            dispatch::<SquareMinus, _>((x, c)),
            expected(super::fused_multiply_adds())
        );
        let off = super::set_fused_multiply_adds(false);
        assert_eq!(dispatch::<SquareMinus, _>((x, c)), expected(off));
        let on = super::set_fused_multiply_adds(true);
        assert_eq!(dispatch::<SquareMinus, _>((x, c)), expected(on));
        // Only a build that targets FMA can fail to turn it off.
        assert!(!off || cfg!(all(target_arch = "x86_64", target_feature = "fma")));
    }

    /// The fused form itself, on a processor with FMA, in any build (debug builds never choose
    /// it, so the test above sees it only in optimised ones).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn fused_rounds_once() {
        #[cfg(all(target_feature = "avx2", target_feature = "fma"))]
        let has_fma = true;
        #[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
        let has_fma = crate::cpu::has_avx2_fma();
        if has_fma {
            let x = 1.0 + f64::powi(2.0, -30);
            let c = 1.0 + f64::powi(2.0, -29);
            assert_eq!(super::Fused(()).mul_add(x, x, -c), f64::powi(2.0, -60));
        }
    }
}
