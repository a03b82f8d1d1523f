//! A delay between the torque channel and the positions, in whole samples, estimated jointly
//! with the parameters: the torques are read `d` samples after the motion they belong to (a
//! drive's filter, a bus, a logger that stamps late), so the sample at `k` is paired with the
//! torques at `k + d`.
//!
//! For every candidate `d` in `−max..=max` the weighted least squares are fitted on the same
//! samples (those whose torques at every candidate shift are in the log), and the delay whose
//! fit is most likely is kept: with each joint's noise estimated, the Gaussian likelihood is
//! largest where `Σ_j ln σ_j` is smallest. A wrong delay adds `τ̇ d h` to every residual, which
//! at any excitation worth the name dwarfs the noise. The estimate is then made with the
//! torques shifted by the delay found, on every sample whose shifted torques are in the log.

use crate::error::IdentifyError;
use crate::least_squares::{estimate, BaseEstimate, Observations};
use nalgebra::{DMatrix, DVector};

/// A [`DelaySearch::log_likelihood_margin`] below this may be the noise's: the delay found
/// can be off by a sample.
pub const DELAY_MARGIN: f64 = 20.0;

/// The delay found and how the candidates compared.
#[derive(Clone, Debug, PartialEq)]
pub struct DelaySearch {
    /// The torques' delay behind the positions, in samples (negative: the torques lead).
    pub samples: i64,
    /// Per candidate delay, `Σ_j ln σ_j` of its fit (smaller is more likely), in order.
    pub criterion: Vec<(i64, f64)>,
    /// The samples every candidate was fitted on.
    pub samples_compared: usize,
}

impl DelaySearch {
    /// How much more likely the delay found is than the next best candidate, as the natural
    /// logarithm of the likelihood ratio, `N (Σ_j ln σ_j(next) − Σ_j ln σ_j(found))` over the
    /// `N` samples compared. The two candidates pair the same torques with different rows, so
    /// the margin varies from one data set to the next by about `√(2 m)` around its mean `m`:
    /// a margin below [`DELAY_MARGIN`] (about three of those deviations) can be the noise's,
    /// and the delay off by a sample.
    pub fn log_likelihood_margin(&self) -> f64 {
        let best = self
            .criterion
            .iter()
            .find(|(d, _)| *d == self.samples)
            .map_or(f64::NAN, |(_, c)| *c);
        let next = self
            .criterion
            .iter()
            .filter(|(d, _)| *d != self.samples)
            .map(|(_, c)| *c)
            .fold(f64::INFINITY, f64::min);
        self.samples_compared as f64 * (next - best)
    }
}

/// The stacked rows of the kept samples whose torques shifted by `d` are in the log: the
/// regressor's rows (from `w`, rows sample-major over `n` joints, one sample per `kept` index)
/// and the torques of `tau` (every sample of the log) at `kept[i] + d`, for the samples `i`
/// that `take` accepts.
fn shifted(
    w: &DMatrix<f64>,
    tau: &[Vec<f64>],
    kept: &[usize],
    n: usize,
    d: i64,
    take: impl Fn(usize) -> bool,
) -> (DMatrix<f64>, DVector<f64>, usize) {
    let picked: Vec<usize> = (0..kept.len())
        .filter(|&i| {
            let k = kept[i] as i64 + d;
            take(kept[i]) && k >= 0 && (k as usize) < tau.len()
        })
        .collect();
    let rows: Vec<usize> = picked
        .iter()
        .flat_map(|&i| (0..n).map(move |j| i * n + j))
        .collect();
    let sub = w.select_rows(rows.iter());
    let torques = DVector::from_iterator(
        rows.len(),
        picked
            .iter()
            .flat_map(|&i| tau[(kept[i] as i64 + d) as usize].iter().copied()),
    );
    (sub, torques, picked.len())
}

/// Searches the delay over `−max..=max` samples and fits the base parameters with it: the
/// search, the estimate and the samples it used.
pub(crate) fn estimate_with_delay(
    w: &DMatrix<f64>,
    tau: &[Vec<f64>],
    kept: &[usize],
    n: usize,
    names: &[String],
    max: usize,
) -> Result<(DelaySearch, BaseEstimate, usize), IdentifyError> {
    let m = max as i64;
    let len = tau.len();
    if len <= 2 * max + 1 {
        return Err(IdentifyError::data(format!(
            "{len} samples cannot show a delay of up to {max} samples"
        )));
    }
    // The samples every candidate has torques for.
    let common = |k: usize| k >= max && k + max < len;
    let mut criterion = Vec::with_capacity(2 * max + 1);
    let mut samples_compared = 0;
    for d in -m..=m {
        let (sub, torques, count) = shifted(w, tau, kept, n, d, common);
        samples_compared = count;
        let fit = estimate(
            Observations::Stacked {
                w: &sub,
                tau: &torques,
                n,
            },
            names,
        )?;
        let log_noise: f64 = fit.joint_noise.iter().map(|s| s.ln()).sum();
        criterion.push((d, log_noise));
    }
    let (samples, _) = *criterion
        .iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .expect("at least one candidate");
    let (sub, torques, used) = shifted(w, tau, kept, n, samples, |_| true);
    let fit = estimate(
        Observations::Stacked {
            w: &sub,
            tau: &torques,
            n,
        },
        names,
    )?;
    Ok((
        DelaySearch {
            samples,
            criterion,
            samples_compared,
        },
        fit,
        used,
    ))
}
