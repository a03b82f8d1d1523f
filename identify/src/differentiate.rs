//! Velocities and accelerations from sampled positions: a zero-phase low-pass filter, then
//! central differences.
//!
//! - Filter: a second-order Butterworth low-pass (bilinear transform, cutoff pre-warped), run
//!   forward and then backward over the samples ("filtfilt"): zero phase, so the filtered
//!   positions are not delayed against the torques, and an effective fourth-order magnitude
//!   response. The signal is extended at both ends by its point reflection over
//!   [`padding`] samples, and the filter starts from its steady state at the first value, so
//!   the ends carry little transient.
//! - Differences: `q̇_k = (q_{k+1} − q_{k−1}) / (t_{k+1} − t_{k−1})` and the three-point second
//!   difference for `q̈` (exact for parabolas, for any spacing); one-sided at the two ends.
//! - Sampling must be uniform to 1% (a digital filter assumes it); the default cutoff
//!   [`DEFAULT_CUTOFF_HZ`] is far above an excitation's band (a few tenths of a hertz to a few
//!   hertz) and far below encoder-noise bands. Identification drops [`padding`] samples at each
//!   end, where the filter's transient lives.

use crate::error::IdentifyError;

/// Default cutoff of the low-pass filter (Hz).
pub(crate) const DEFAULT_CUTOFF_HZ: f64 = 20.0;

/// Samples at each end that the filter's transient may affect: three time constants of the
/// cutoff, at least 3.
pub(crate) fn padding(rate: f64, cutoff: f64) -> usize {
    ((3.0 * rate / cutoff).ceil() as usize).max(3)
}

/// Coefficients `(b0, b1, b2, a1, a2)` of the second-order Butterworth low-pass.
fn butterworth(rate: f64, cutoff: f64) -> (f64, f64, f64, f64, f64) {
    let k = (std::f64::consts::PI * cutoff / rate).tan();
    let q = std::f64::consts::FRAC_1_SQRT_2;
    let norm = 1.0 / (1.0 + k / q + k * k);
    let b0 = k * k * norm;
    (
        b0,
        2.0 * b0,
        b0,
        2.0 * (k * k - 1.0) * norm,
        (1.0 - k / q + k * k) * norm,
    )
}

/// One pass of the filter (direct form II transposed), starting in steady state at `x[0]`.
fn pass(x: &[f64], c: (f64, f64, f64, f64, f64)) -> Vec<f64> {
    let (b0, b1, b2, a1, a2) = c;
    let x0 = x.first().copied().unwrap_or(0.0);
    let mut z2 = (b2 - a2) * x0;
    let mut z1 = (b1 - a1) * x0 + z2;
    x.iter()
        .map(|&v| {
            let y = b0 * v + z1;
            z1 = b1 * v - a1 * y + z2;
            z2 = b2 * v - a2 * y;
            y
        })
        .collect()
}

/// Zero-phase low-pass of one signal sampled at `rate` Hz.
pub(crate) fn filtfilt(x: &[f64], rate: f64, cutoff: f64) -> Vec<f64> {
    let n = x.len();
    if n < 3 {
        return x.to_vec();
    }
    let pad = padding(rate, cutoff).min(n - 1);
    let mut ext = Vec::with_capacity(n + 2 * pad);
    ext.extend((1..=pad).rev().map(|k| 2.0 * x[0] - x[k]));
    ext.extend_from_slice(x);
    ext.extend((1..=pad).map(|k| 2.0 * x[n - 1] - x[n - 1 - k]));
    let c = butterworth(rate, cutoff);
    let mut y = pass(&ext, c);
    y.reverse();
    let mut y = pass(&y, c);
    y.reverse();
    y[pad..pad + n].to_vec()
}

/// Sampling rate of `time` (Hz), which must be uniform to 1%.
pub(crate) fn uniform_rate(time: &[f64], lines: &[usize]) -> Result<f64, IdentifyError> {
    if time.len() < 3 {
        return Err(IdentifyError::data(format!(
            "{} samples: at least 3 are needed to compute velocities and accelerations",
            time.len()
        )));
    }
    let h = (time[time.len() - 1] - time[0]) / (time.len() - 1) as f64;
    for (k, w) in time.windows(2).enumerate() {
        check_step(w[1] - w[0], h, lines.get(k + 1).copied())?;
    }
    Ok(1.0 / h)
}

/// A time step `step` (ending on `line`) against the mean step `h`: within 1%, or an error.
pub(crate) fn check_step(step: f64, h: f64, line: Option<usize>) -> Result<(), IdentifyError> {
    if (step - h).abs() <= 0.01 * h {
        return Ok(());
    }
    let msg = format!(
        "time step {step} s differs from the mean step {h} s by more than 1%: the filter \
         that computes velocities and accelerations needs uniform sampling (or give qd and qdd columns)"
    );
    let e = IdentifyError::data(msg);
    Err(match line {
        Some(l) => e.at_line(l).at_column(1, "time"),
        None => e,
    })
}

/// First and second derivatives of `x(t)` by three-point differences (any spacing).
pub(crate) fn differences(time: &[f64], x: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = x.len();
    let mut d1 = vec![0.0; n];
    let mut d2 = vec![0.0; n];
    if n < 3 {
        return (d1, d2);
    }
    // Three-point formulas on (k−1, k, k+1): exact for parabolas.
    let three = |k: usize, at: f64| {
        let (t0, t1, t2) = (time[k - 1], time[k], time[k + 1]);
        let (x0, x1, x2) = (x[k - 1], x[k], x[k + 1]);
        let (h0, h1) = (t1 - t0, t2 - t1);
        let second = 2.0 * (x2 / (h1 * (h0 + h1)) - x1 / (h0 * h1) + x0 / (h0 * (h0 + h1)));
        // Derivative of the interpolating parabola at `at` (at t1 with equal steps:
        // (x2 − x0) / 2h, the central difference).
        let first = (x1 - x0) / h0 + second * (at - 0.5 * (t0 + t1));
        (first, second)
    };
    for k in 1..n - 1 {
        let (f, s) = three(k, time[k]);
        d1[k] = f;
        d2[k] = s;
    }
    let (f0, s0) = three(1, time[0]);
    let (fl, sl) = three(n - 2, time[n - 1]);
    d1[0] = f0;
    d2[0] = s0;
    d1[n - 1] = fl;
    d2[n - 1] = sl;
    (d1, d2)
}
