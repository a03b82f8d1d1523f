//! The joint sines and cosines of [`crate::trig`] written with AVX2 and FMA intrinsics: what
//! every x86-64 build runs where the processor has those features (targeted, or found at run
//! time by [`crate::cpu::has_avx2_fma`]). The same steps and constants as the lane form, so the
//! same values as that form fused.

use crate::trig::{COS, P1, P2, P3, ROUND, SIN, TWO_OVER_PI};
use crate::JointTrig;
use core::arch::x86_64::*;

/// [`crate::trig::joint_trig`] with every step compiled for AVX2 and FMA: the angles read from
/// `q`, four joints per vector, and each result stored once, into the value returned.
///
/// # Safety
/// The processor must have AVX, AVX2 and FMA.
#[target_feature(enable = "avx,avx2,fma")]
pub(crate) unsafe fn joint_trig<const N: usize>(q: &[f64; N]) -> JointTrig<N> {
    // Its constant vectors spill (more than sixteen registers' worth): whole, into aligned slots.
    crate::stack_align::align_stack_frame();
    let (mut sin, mut cos) = ([0.0; N], [0.0; N]);
    let mut start = 0;
    while start < N {
        let count = (N - start).min(4);
        let angle = |k: usize| if k < count { q[start + k] } else { 0.0 };
        // SAFETY: the enclosing function's features; every read and write is within the
        // arrays (a full vector only where four entries remain, single lanes otherwise).
        unsafe {
            let x = if count == 4 {
                _mm256_loadu_pd(q[start..].as_ptr())
            } else {
                _mm256_setr_pd(angle(0), angle(1), angle(2), 0.0)
            };
            let (s, c) = sin_cos_4(x);
            store(&mut sin[start..start + count], s);
            store(&mut cos[start..start + count], c);
        }
        start += 4;
    }
    crate::trig::exact_beyond_limit(q, &mut sin, &mut cos);
    JointTrig { q: *q, sin, cos }
}

/// The first `out.len()` (one to four) lanes of `v` into `out`.
#[target_feature(enable = "avx,avx2,fma")]
#[inline]
unsafe fn store(out: &mut [f64], v: __m256d) {
    // SAFETY: the enclosing function's features; each store covers entries of `out` only.
    unsafe {
        let low = _mm256_castpd256_pd128(v);
        match out.len() {
            4 => _mm256_storeu_pd(out.as_mut_ptr(), v),
            1 => _mm_store_sd(out.as_mut_ptr(), low),
            count => {
                _mm_storeu_pd(out.as_mut_ptr(), low);
                if count == 3 {
                    _mm_store_sd(out[2..].as_mut_ptr(), _mm256_extractf128_pd::<1>(v));
                }
            }
        }
    }
}

/// The kernel on four angles (one lane vector of `JointTrigLanes`), compiled for AVX2 and FMA,
/// for builds that choose at run time (a build that targets the features runs the lane form
/// fused).
///
/// # Safety
/// The processor must have AVX, AVX2 and FMA.
#[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
#[target_feature(enable = "avx,avx2,fma")]
pub(crate) unsafe fn sin_cos_four(q: &[f64; 4]) -> ([f64; 4], [f64; 4]) {
    let (mut sin, mut cos) = ([0.0; 4], [0.0; 4]);
    // SAFETY: the enclosing function's features; reads and writes stay in the arrays.
    unsafe {
        let (s, c) = sin_cos_4(_mm256_loadu_pd(q.as_ptr()));
        _mm256_storeu_pd(sin.as_mut_ptr(), s);
        _mm256_storeu_pd(cos.as_mut_ptr(), c);
    }
    (sin, cos)
}

/// [`sin_cos_four`] of every vector of `q` in one function compiled for AVX2 and FMA: the joints
/// of a `JointTrigLanes` of four lanes (or of each half of eight) in one call: one call per
/// joint, each through arrays, left a default build far behind a native one.
///
/// # Safety
/// The processor must have AVX, AVX2 and FMA.
#[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
#[target_feature(enable = "avx,avx2,fma")]
pub(crate) unsafe fn sin_cos_fours<const N: usize>(q: &[[f64; 4]; N]) -> ([[f64; 4]; N], [[f64; 4]; N]) {
    let (mut sin, mut cos) = ([[0.0; 4]; N], [[0.0; 4]; N]);
    for i in 0..N {
        // SAFETY: the enclosing function's features; reads and writes stay in the arrays.
        unsafe {
            let (s, c) = sin_cos_4(_mm256_loadu_pd(q[i].as_ptr()));
            _mm256_storeu_pd(sin[i].as_mut_ptr(), s);
            _mm256_storeu_pd(cos[i].as_mut_ptr(), c);
        }
    }
    (sin, cos)
}

#[target_feature(enable = "avx,avx2,fma")]
#[inline]
unsafe fn sin_cos_4(q: __m256d) -> (__m256d, __m256d) {
    let splat = |x: f64| _mm256_set1_pd(x);
    let neg = |x: __m256d| _mm256_xor_pd(x, _mm256_set1_pd(-0.0));
    let round = splat(ROUND);
    let k = _mm256_sub_pd(_mm256_fmadd_pd(q, splat(TWO_OVER_PI), round), round);
    let minus_k = neg(k);
    let r = _mm256_fmadd_pd(
        minus_k,
        splat(P3),
        _mm256_fmadd_pd(minus_k, splat(P2), _mm256_fmadd_pd(minus_k, splat(P1), q)),
    );
    let z = _mm256_mul_pd(r, r);
    let minus_z = neg(z);
    let z2 = _mm256_mul_pd(z, z);
    let z4 = _mm256_mul_pd(z2, z2);
    let polynomial = |c: &[f64; 8]| {
        let term = |i: usize| _mm256_fmadd_pd(minus_z, splat(c[i + 1]), splat(c[i]));
        let low = _mm256_fmadd_pd(z2, term(2), term(0));
        let high = _mm256_fmadd_pd(z2, term(6), term(4));
        _mm256_fmadd_pd(z4, high, low)
    };
    let ps = polynomial(&SIN);
    let pc = polynomial(&COS);
    let sin_r = _mm256_fmadd_pd(neg(_mm256_mul_pd(r, z)), ps, r);
    let r_is_zero = _mm256_cmp_pd::<_CMP_EQ_OQ>(r, splat(0.0));
    let sin_r = _mm256_blendv_pd(sin_r, r, r_is_zero);
    let cos_r = _mm256_fmadd_pd(minus_z, pc, splat(1.0));
    let quarter = _mm256_sub_pd(
        _mm256_add_pd(_mm256_fmadd_pd(k, splat(0.25), splat(-0.375)), round),
        round,
    );
    let j = _mm256_fmadd_pd(quarter, splat(-4.0), k);
    let is = |v: f64| _mm256_cmp_pd::<_CMP_EQ_OQ>(j, splat(v));
    let odd = _mm256_or_pd(is(1.0), is(3.0));
    let sin = _mm256_blendv_pd(sin_r, cos_r, odd);
    let cos = _mm256_blendv_pd(cos_r, sin_r, odd);
    let sin = _mm256_blendv_pd(sin, neg(sin), _mm256_cmp_pd::<_CMP_GE_OQ>(j, splat(2.0)));
    let cos = _mm256_blendv_pd(cos, neg(cos), _mm256_or_pd(is(1.0), is(2.0)));
    (sin, cos)
}
