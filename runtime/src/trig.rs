//! Sines and cosines of all joint angles at once.
//!
//! `libm::sincos` is one call per joint with a branchy range reduction, and seven of them are
//! most of the cost of forward kinematics. Here every step is straight-line arithmetic and bit
//! operations over the whole array, which the compiler turns into SIMD lanes: a Cody–Waite
//! reduction by π/2 (three parts, so `k·P1` and `k·P2` are exact for `|k| < 2²⁰`), Taylor
//! polynomials on `[−π/4, π/4]` (the first omitted terms are below 1e-17, a tenth of an ulp),
//! and the quadrant applied by selects and sign flips. Angles beyond `LIMIT` (and NaN or
//! infinity) take `libm::sincos`, which reduces exactly for any argument.

/// Largest `|q|` the fast reduction serves; far beyond any joint's range.
const LIMIT: f64 = 1e5;
const TWO_OVER_PI: f64 = core::f64::consts::FRAC_2_PI;
/// π/2 in three parts: 33 significant bits, 33 more, and the rest.
const P1: f64 = 1.5707963267341256;
const P2: f64 = 6.077100506303966e-11;
const P3: f64 = 2.0222662487959506e-21;
/// Adding `1.5·2⁵²` rounds to an integer, which then sits in the low mantissa bits.
const ROUND: f64 = 6755399441055744.0;

/// `1/n!` for the odd (sine) and even (cosine) Taylor terms, alternating signs applied below.
const SIN: [f64; 8] = [
    0.16666666666666666,
    0.008333333333333333,
    0.0001984126984126984,
    2.7557319223985893e-06,
    2.505210838544172e-08,
    1.6059043836821613e-10,
    7.647163731819816e-13,
    2.8114572543455206e-15,
];
const COS: [f64; 8] = [
    0.5,
    0.041666666666666664,
    0.001388888888888889,
    2.48015873015873e-05,
    2.755731922398589e-07,
    2.08767569878681e-09,
    1.1470745597729725e-11,
    4.779477332387385e-14,
];

/// Sines and cosines of every entry of `q`.
#[inline]
pub(crate) fn sin_cos_all<const N: usize>(q: &[f64; N]) -> ([f64; N], [f64; N]) {
    const SIGN: u64 = 1 << 63;
    // Each step is its own loop over the joints, so that every loop is one SIMD operation.
    let t: [f64; N] = core::array::from_fn(|i| q[i] * TWO_OVER_PI + ROUND);
    let k: [f64; N] = core::array::from_fn(|i| t[i] - ROUND);
    let r: [f64; N] = core::array::from_fn(|i| ((q[i] - k[i] * P1) - k[i] * P2) - k[i] * P3);
    let z: [f64; N] = core::array::from_fn(|i| r[i] * r[i]);
    let mut ps = [SIN[7]; N];
    let mut pc = [COS[7]; N];
    for c in (0..7).rev() {
        for i in 0..N {
            ps[i] = SIN[c] - z[i] * ps[i];
            pc[i] = COS[c] - z[i] * pc[i];
        }
    }
    let mut sin = [0.0; N];
    let mut cos = [0.0; N];
    for i in 0..N {
        // On [−π/4, π/4] sin r has the sign of r; setting it keeps sin(−0) = −0.
        let s = r[i] - r[i] * z[i] * ps[i];
        let s = (s.to_bits() & !SIGN) | (r[i].to_bits() & SIGN);
        let c = (1.0 - z[i] * pc[i]).to_bits();
        // Quadrant 1: (cos r, −sin r); 2: (−sin r, −cos r); 3: (−cos r, sin r).
        let quadrant = t[i].to_bits();
        let odd = 0u64.wrapping_sub(quadrant & 1);
        let (s, c) = ((s & !odd) | (c & odd), (c & !odd) | (s & odd));
        sin[i] = f64::from_bits(s ^ ((quadrant & 2) << 62));
        cos[i] = f64::from_bits(c ^ (((quadrant + 1) & 2) << 62));
    }
    // Out of range (or NaN, for which the comparison is false): the exact reduction.
    let in_range = |x: f64| f64::from_bits(x.to_bits() & !SIGN) <= LIMIT;
    if !q.iter().all(|&x| in_range(x)) {
        for i in 0..N {
            if !in_range(q[i]) {
                (sin[i], cos[i]) = libm::sincos(q[i]);
            }
        }
    }
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
