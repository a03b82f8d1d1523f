//! Sines and cosines of all joint angles at once.
//!
//! `libm::sincos` is one call per joint with a branchy range reduction, and seven of them are
//! most of the cost of forward kinematics. Here the joints go through `f64x4` lanes, eight at a
//! time as two vectors, every step straight-line: a Cody–Waite reduction by π/2 (three parts, so
//! `k·P1` and `k·P2` are exact for `|k| < 2²⁰`), Taylor polynomials on `[−π/4, π/4]` by
//! Estrin's scheme with multiply-adds (the first omitted terms are below 1e-17, a tenth of an
//! ulp), and the quadrant applied by selects. Angles beyond `LIMIT` (and NaN or infinity) take
//! `libm::sincos`, which reduces exactly for any argument.
//!
//! Four lanes, not eight, even where the target has AVX-512: one `f64x8` kernel is faster alone,
//! but its 512-bit instructions slow the scalar code that follows them, the generated function
//! the sines and cosines are for, and the call as a whole is slower.
//!
//! Written on the lane type rather than as loops over arrays: the compiler vectorised those
//! loops as 4 + 2 + 1 lanes for seven joints, kept the quadrant's bit operations scalar and
//! used no FMA, 2.5 times the instructions of this form.

use crate::JointTrig;
use wide::f64x4;

/// Largest `|q|` the fast reduction serves; far beyond any joint's range.
const LIMIT: f64 = 1e5;
pub(crate) const TWO_OVER_PI: f64 = core::f64::consts::FRAC_2_PI;
/// π/2 in three parts: 33 significant bits, 33 more, and the rest.
pub(crate) const P1: f64 = 1.5707963267341256;
pub(crate) const P2: f64 = 6.077100506303966e-11;
pub(crate) const P3: f64 = 2.0222662487959506e-21;
/// Adding `1.5·2⁵²` rounds to an integer (ties to even), exactly, for `|x| < 2⁵¹`.
pub(crate) const ROUND: f64 = 6755399441055744.0;

/// `1/n!` for the odd (sine) and even (cosine) Taylor terms, alternating signs applied below.
pub(crate) const SIN: [f64; 8] = [
    0.16666666666666666,
    0.008333333333333333,
    0.0001984126984126984,
    2.7557319223985893e-06,
    2.505210838544172e-08,
    1.6059043836821613e-10,
    7.647163731819816e-13,
    2.8114572543455206e-15,
];
pub(crate) const COS: [f64; 8] = [
    0.5,
    0.041666666666666664,
    0.001388888888888889,
    2.48015873015873e-05,
    2.755731922398589e-07,
    2.08767569878681e-09,
    1.1470745597729725e-11,
    4.779477332387385e-14,
];

/// The joint positions `q` with their sines and cosines: fused where the build targets FMA or
/// the processor has it. On x86-64 with AVX2 and FMA (targeted or found at run time) by the
/// intrinsics kernel (`trig_fused`), which stores each result once, into the value returned;
/// inlined into the caller, so that this value is the caller's. Built in a temporary and
/// copied, the results were read back in pieces of another width than they were stored in,
/// which the processor cannot forward: a stall on every load, and times that varied from one
/// run to the next (`docs/performance-notes.md`).
#[inline(always)]
pub(crate) fn joint_trig<const N: usize>(q: &[f64; N]) -> JointTrig<N> {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2", target_feature = "fma"))]
    {
        // SAFETY: the build targets AVX2 and FMA (and so AVX).
        unsafe { crate::trig_fused::joint_trig(q) }
    }
    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx2", target_feature = "fma")))]
    {
        #[cfg(target_arch = "x86_64")]
        if crate::cpu::has_avx2_fma() {
            // SAFETY: the processor has AVX, AVX2 and FMA (just checked).
            return unsafe { crate::trig_fused::joint_trig(q) };
        }
        lane_joint_trig(q)
    }
}

/// [`joint_trig`] by the lane form, where the build has no intrinsics kernel to run: out of line
/// where a build chooses at run time (the path of x86-64 processors without FMA), inlined
/// where it is the build's only form.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx2", target_feature = "fma")))]
#[cfg_attr(target_arch = "x86_64", inline(never))]
#[cfg_attr(not(target_arch = "x86_64"), inline(always))]
fn lane_joint_trig<const N: usize>(q: &[f64; N]) -> JointTrig<N> {
    let (sin, cos) = sin_cos_all_with(q, sin_cos_8);
    JointTrig { q: *q, sin, cos }
}

/// The sines and cosines of [`joint_trig`].
#[cfg(test)]
pub(crate) fn sin_cos_all<const N: usize>(q: &[f64; N]) -> ([f64; N], [f64; N]) {
    let trig = joint_trig(q);
    (trig.sin, trig.cos)
}

/// `kernel` over `q` eight entries at a time (the last group padded with zeros), and the exact
/// reduction for entries out of its range.
#[cfg(not(all(target_arch = "x86_64", target_feature = "avx2", target_feature = "fma")))]
#[inline(always)]
fn sin_cos_all_with<const N: usize>(
    q: &[f64; N],
    kernel: impl Fn(&[f64; 8]) -> ([f64; 8], [f64; 8]),
) -> ([f64; N], [f64; N]) {
    let mut sin = [0.0; N];
    let mut cos = [0.0; N];
    let mut start = 0;
    while start < N {
        let x: [f64; 8] = core::array::from_fn(|k| q.get(start + k).copied().unwrap_or(0.0));
        let (s, c) = kernel(&x);
        let count = (N - start).min(8);
        sin[start..start + count].copy_from_slice(&s[..count]);
        cos[start..start + count].copy_from_slice(&c[..count]);
        start += 8;
    }
    exact_beyond_limit(q, &mut sin, &mut cos);
    (sin, cos)
}

/// The entries of `q` out of the kernel's range (or NaN, for which the comparison is false) by
/// the exact reduction.
#[inline(always)]
pub(crate) fn exact_beyond_limit<const N: usize>(q: &[f64; N], sin: &mut [f64; N], cos: &mut [f64; N]) {
    let in_range = |x: f64| f64::from_bits(x.to_bits() & !(1 << 63)) <= LIMIT;
    if !q.iter().all(|&x| in_range(x)) {
        for i in 0..N {
            if !in_range(q[i]) {
                (sin[i], cos[i]) = libm::sincos(q[i]);
            }
        }
    }
}

/// The sines and cosines of one lane vector's four angles, each exactly as [`sin_cos_all`]
/// computes it (so lane functions match scalar ones bit for bit), straight from the vector.
/// Going through [`sin_cos_all`] instead meant an eight-angle array per joint, built from lanes
/// and read back in one wide load the processor cannot forward.
#[inline]
pub(crate) fn sin_cos_f64x4(q: f64x4) -> (f64x4, f64x4) {
    let (sin, cos) = sin_cos_four_in_range(q);
    if q.abs().simd_le(f64x4::splat(LIMIT)).all() {
        return (sin, cos);
    }
    let angles = q.to_array();
    let (mut sin, mut cos) = (sin.to_array(), cos.to_array());
    exact_beyond_limit(&angles, &mut sin, &mut cos);
    (f64x4::new(sin), f64x4::new(cos))
}

/// `f` (a sine and cosine) of each of `q`.
#[inline(always)]
pub(crate) fn each<T: Copy, const N: usize>(q: &[T; N], f: impl Fn(T) -> (T, T)) -> ([T; N], [T; N]) {
    let (mut sin, mut cos) = (*q, *q);
    for i in 0..N {
        (sin[i], cos[i]) = f(q[i]);
    }
    (sin, cos)
}

/// [`sin_cos_f64x4`] of each of `q` (the joints of a `JointTrigLanes`): where a build chooses at
/// run time and the processor has AVX2 and FMA, all of them in one function compiled for those
/// features.
#[inline]
pub(crate) fn sin_cos_f64x4_all<const N: usize>(q: &[f64x4; N]) -> ([f64x4; N], [f64x4; N]) {
    #[cfg(all(
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    if crate::cpu::has_avx2_fma() {
        let angles: [[f64; 4]; N] = core::array::from_fn(|i| q[i].to_array());
        // SAFETY: the processor has AVX, AVX2 and FMA (just checked).
        let (mut sin, mut cos) = unsafe { crate::trig_fused::sin_cos_fours(&angles) };
        for i in 0..N {
            exact_beyond_limit(&angles[i], &mut sin[i], &mut cos[i]);
        }
        return (sin.map(f64x4::new), cos.map(f64x4::new));
    }
    each(q, sin_cos_f64x4)
}

/// [`sin_cos_f64x8`] of each of `q`: as [`sin_cos_f64x4_all`], each half as four lanes, where
/// a build chooses at run time and the processor has AVX2 and FMA.
#[inline]
pub(crate) fn sin_cos_f64x8_all<const N: usize>(
    q: &[wide::f64x8; N],
) -> ([wide::f64x8; N], [wide::f64x8; N]) {
    #[cfg(all(
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    if crate::cpu::has_avx2_fma() {
        let halves = q.map(halves);
        let ((s0, c0), (s1, c1)) = (
            sin_cos_f64x4_all(&halves.map(|h| h.0)),
            sin_cos_f64x4_all(&halves.map(|h| h.1)),
        );
        return (
            core::array::from_fn(|i| join(s0[i], s1[i])),
            core::array::from_fn(|i| join(c0[i], c1[i])),
        );
    }
    each(q, sin_cos_f64x8)
}

/// Lanes 0–3 and 4–7 of `q`.
#[inline(always)]
fn halves(q: wide::f64x8) -> (f64x4, f64x4) {
    let a = q.to_array();
    (
        f64x4::new([a[0], a[1], a[2], a[3]]),
        f64x4::new([a[4], a[5], a[6], a[7]]),
    )
}

/// Eight lanes from their halves.
#[inline(always)]
fn join(low: f64x4, high: f64x4) -> wide::f64x8 {
    let (l, h) = (low.to_array(), high.to_array());
    wide::f64x8::new([l[0], l[1], l[2], l[3], h[0], h[1], h[2], h[3]])
}

/// The kernel on four angles: fused where the build targets FMA or the processor has it.
#[inline(always)]
fn sin_cos_four_in_range(q: f64x4) -> (f64x4, f64x4) {
    #[cfg(all(
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    if crate::cpu::has_avx2_fma() {
        // SAFETY: the processor has AVX, AVX2 and FMA (just checked).
        let (sin, cos) = unsafe { crate::trig_fused::sin_cos_four(&q.to_array()) };
        return (f64x4::new(sin), f64x4::new(cos));
    }
    sin_cos_lanes(q)
}

/// [`sin_cos_f64x4`] on each half of eight lanes.
#[inline]
pub(crate) fn sin_cos_f64x8(q: wide::f64x8) -> (wide::f64x8, wide::f64x8) {
    let (low, high) = halves(q);
    let ((s0, c0), (s1, c1)) = (sin_cos_f64x4(low), sin_cos_f64x4(high));
    (join(s0, s1), join(c0, c1))
}

/// Sines and cosines of eight angles, each within `LIMIT`, as two `f64x4` vectors.
#[cfg(any(
    test,
    not(all(target_arch = "x86_64", target_feature = "avx2", target_feature = "fma"))
))]
#[inline(always)]
fn sin_cos_8(x: &[f64; 8]) -> ([f64; 8], [f64; 8]) {
    let (s0, c0) = sin_cos_lanes(f64x4::new([x[0], x[1], x[2], x[3]]));
    let (s1, c1) = sin_cos_lanes(f64x4::new([x[4], x[5], x[6], x[7]]));
    let (s0, c0, s1, c1) = (s0.to_array(), c0.to_array(), s1.to_array(), c1.to_array());
    (
        [s0[0], s0[1], s0[2], s0[3], s1[0], s1[1], s1[2], s1[3]],
        [c0[0], c0[1], c0[2], c0[3], c1[0], c1[1], c1[2], c1[3]],
    )
}

/// Sines and cosines of four angles, each within `LIMIT`.
#[inline(always)]
fn sin_cos_lanes(q: f64x4) -> (f64x4, f64x4) {
    let splat = f64x4::splat;
    // k = round(q·2/π), exactly, and r = q − k·π/2 in [−π/4, π/4].
    let k = q.mul_add(splat(TWO_OVER_PI), splat(ROUND)) - splat(ROUND);
    let r = (-k).mul_add(splat(P3), (-k).mul_add(splat(P2), (-k).mul_add(splat(P1), q)));
    let z = r * r;
    let minus_z = -z;
    // The polynomials in −z by Estrin's scheme: three dependent multiply-adds instead of
    // Horner's seven (the chain's latency, not the operation count, bounds this function).
    let z2 = z * z;
    let z4 = z2 * z2;
    let polynomial = |k: &[f64; 8]| {
        let term = |i: usize| minus_z.mul_add(splat(k[i + 1]), splat(k[i]));
        let low = z2.mul_add(term(2), term(0));
        let high = z2.mul_add(term(6), term(4));
        z4.mul_add(high, low)
    };
    let ps = polynomial(&SIN);
    let pc = polynomial(&COS);
    // sin r = r − r·z·p(z): the small correction added to r last. At r = ±0 that sum is +0
    // whatever the sign of r, so r itself is kept there (sin(−0) = −0).
    let sin_r = (-(r * z)).mul_add(ps, r);
    let sin_r = r.simd_eq(splat(0.0)).select(r, sin_r);
    let cos_r = minus_z.mul_add(pc, splat(1.0));
    // The quadrant j = k mod 4 in {0, 1, 2, 3}, from floor(k/4) by the same rounding
    // (k/4 − 3/8 is within 3/8 of that floor, so rounds to it).
    let quarter = (k.mul_add(splat(0.25), splat(-0.375)) + splat(ROUND)) - splat(ROUND);
    let j = quarter.mul_add(splat(-4.0), k);
    let is = |v: f64| j.simd_eq(splat(v));
    // Quadrant 1: (cos r, −sin r); 2: (−sin r, −cos r); 3: (−cos r, sin r).
    let odd = is(1.0) | is(3.0);
    let sin = odd.select(cos_r, sin_r);
    let cos = odd.select(sin_r, cos_r);
    let sin = j.simd_ge(splat(2.0)).select(-sin, sin);
    let cos = (is(1.0) | is(2.0)).select(-cos, cos);
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Within `ulps` units in the last place of `b` (2.2e-16·|b|), or that much absolute near
    /// the zeros of sin and cos.
    fn within(a: f64, b: f64, ulps: f64) -> bool {
        (a - b).abs() <= ulps * 2.3e-16 * b.abs().max(0.5)
    }
    fn close(a: f64, b: f64) -> bool {
        within(a, b, 4.0)
    }

    #[test]
    fn matches_libm_over_joint_ranges_and_beyond() {
        let mut rng = crate::SplitMix64::new(7);
        let mut worst = 0.0f64;
        for k in 0..200_000 {
            let scale = [1.0, 4.0, 7.0, 100.0, 3.0e4, 1.0e5][k % 6];
            let q = [rng.uniform((-scale, scale))];
            let (s, c) = sin_cos_all(&q);
            let (ls, lc) = libm::sincos(q[0]);
            worst = worst.max((s[0] - ls).abs()).max((c[0] - lc).abs());
            assert!(
                close(s[0], ls) && close(c[0], lc),
                "q = {:e}: ({}, {}) vs ({ls}, {lc})",
                q[0],
                s[0],
                c[0]
            );
            // Within a joint's range the reduction is exact: only the polynomial rounds.
            if scale <= 7.0 {
                assert!(within(s[0], ls, 2.0) && within(c[0], lc, 2.0), "q = {:e}", q[0]);
            }
        }
        assert!(worst < 5e-16, "{worst:e}");
    }

    type Kernel = fn(&[f64; 8]) -> ([f64; 8], [f64; 8]);

    /// Every form of the kernel this processor runs: the lanes, and the AVX2/FMA intrinsics
    /// where the build targets them or the processor has them (so both are checked).
    fn kernels() -> Vec<(&'static str, Kernel)> {
        #[allow(unused_mut)]
        let mut forms: Vec<(&'static str, Kernel)> = vec![("lanes", sin_cos_8)];
        #[cfg(target_arch = "x86_64")]
        {
            fn fused(q: &[f64; 8]) -> ([f64; 8], [f64; 8]) {
                // SAFETY: only listed when the processor has AVX2 and FMA.
                let trig = unsafe { crate::trig_fused::joint_trig(q) };
                (trig.sin, trig.cos)
            }
            #[cfg(not(all(target_feature = "avx2", target_feature = "fma")))]
            let has = crate::cpu::has_avx2_fma();
            #[cfg(all(target_feature = "avx2", target_feature = "fma"))]
            let has = true;
            if has {
                forms.push(("fused", fused));
            }
        }
        forms
    }

    #[test]
    fn every_form_of_the_kernel_matches_libm() {
        let mut rng = crate::SplitMix64::new(11);
        for (name, kernel) in kernels() {
            for k in 0..20_000 {
                let scale = [1.0, 4.0, 7.0, 100.0, 3.0e4, 1.0e5][k % 6];
                let q: [f64; 8] = core::array::from_fn(|_| rng.uniform((-scale, scale)));
                let (s, c) = kernel(&q);
                for i in 0..8 {
                    let (ls, lc) = libm::sincos(q[i]);
                    let ulps = if scale <= 7.0 { 2.0 } else { 4.0 };
                    assert!(
                        within(s[i], ls, ulps) && within(c[i], lc, ulps),
                        "{name}, q = {:e}: ({}, {}) vs ({ls}, {lc})",
                        q[i],
                        s[i],
                        c[i]
                    );
                }
            }
            let q = [0.0, -0.0, 1e-300, -1e-300, core::f64::consts::PI, -2.5, 7.0, -7.0];
            let (s, c) = kernel(&q);
            assert_eq!((s[0].to_bits(), c[0]), (0.0f64.to_bits(), 1.0), "{name}");
            assert_eq!((s[1].to_bits(), c[1]), ((-0.0f64).to_bits(), 1.0), "{name}");
            assert_eq!((s[2], s[3]), (1e-300, -1e-300), "{name}");
        }
    }

    #[test]
    fn special_angles() {
        let q = [
            0.0,
            -0.0,
            core::f64::consts::FRAC_PI_2,
            -core::f64::consts::PI,
            1e-300,
            3.0 * core::f64::consts::FRAC_PI_2,
        ];
        let (s, c) = sin_cos_all(&q);
        for i in 0..q.len() {
            let (ls, lc) = libm::sincos(q[i]);
            assert!(close(s[i], ls) && close(c[i], lc), "q = {:e}", q[i]);
        }
        assert_eq!((s[0], c[0]), (0.0, 1.0));
        assert_eq!(s[1].to_bits(), (-0.0f64).to_bits());
    }

    #[test]
    fn out_of_range_and_non_finite_take_the_exact_reduction() {
        let q = [1e6, -3.5e12, f64::INFINITY, f64::NAN, 0.5];
        let (s, c) = sin_cos_all(&q);
        for i in 0..q.len() {
            let (ls, lc) = libm::sincos(q[i]);
            assert!((s[i].to_bits() == ls.to_bits() || s[i].is_nan() && ls.is_nan()) || i == 4);
            assert!((c[i].to_bits() == lc.to_bits() || c[i].is_nan() && lc.is_nan()) || i == 4);
        }
        assert!(close(s[4], libm::sin(0.5)) && close(c[4], libm::cos(0.5)));
    }
}
