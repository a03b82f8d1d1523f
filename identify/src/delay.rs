//! A delay between the torque channel and the positions, estimated jointly with the
//! parameters: the torques are logged `d` samples after the motion they belong to (a drive's
//! filter, a bus, a logger that stamps late), so the torque at `k` pairs with the motion at
//! `k − d` ([`crate::torque_channel`]).
//!
//! For every whole candidate `d` in `−max..=max` the weighted least squares are fitted on the
//! same torques (those whose motion is in the log at every candidate), and the delay whose fit
//! is most likely is kept: with each joint's noise estimated, the Gaussian likelihood is
//! largest where `Σ_j ln σ_j` is smallest. A wrong delay adds `τ̇ d h` to every residual, which
//! at any excitation worth the name dwarfs the noise. Asked for a fraction, the criterion is
//! then minimised between the whole candidates on either side of the best (golden section to
//! [`FRACTION_TOLERANCE`], the motion's rows interpolated), and its curvature there gives the
//! delay's standard deviation: the log-likelihood is `−N Σ_j ln σ_j(d)`, so
//! `σ_d² = 1/(N ∂²Σ_j ln σ_j/∂d²)`.

use crate::error::IdentifyError;
use crate::least_squares::BaseEstimate;
use crate::torque_channel::Alignment;

/// A [`DelaySearch::log_likelihood_margin`] below this may be the noise's: the delay found
/// can be off by a sample.
pub const DELAY_MARGIN: f64 = 20.0;

/// Where the golden section stops, in samples.
const FRACTION_TOLERANCE: f64 = 0.002;
/// The step of the curvature's second difference, in samples.
const CURVATURE_STEP: f64 = 0.1;

/// The delay found and how the candidates compared.
#[derive(Clone, Debug, PartialEq)]
pub struct DelaySearch {
    /// The torques' delay behind the positions, in samples (negative: the torques lead): a
    /// whole number, unless a fraction was asked for.
    pub samples: f64,
    /// Per whole candidate delay, `Σ_j ln σ_j` of its fit (smaller is more likely), in order.
    pub criterion: Vec<(i64, f64)>,
    /// The torques every candidate was fitted on.
    pub samples_compared: usize,
    /// With a fraction: the delay's standard deviation in samples, from the curvature of the
    /// log-likelihood at it.
    pub std_dev: Option<f64>,
}

impl DelaySearch {
    /// The most likely whole candidate.
    pub fn whole(&self) -> i64 {
        self.criterion
            .iter()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(0, |(d, _)| *d)
    }

    /// How much more likely the best whole candidate is than the next best, as the natural
    /// logarithm of the likelihood ratio, `N (Σ_j ln σ_j(next) − Σ_j ln σ_j(best))` over the
    /// `N` torques compared. The two candidates pair the same torques with different rows, so
    /// the margin varies from one data set to the next by about `√(2 m)` around its mean `m`:
    /// a margin below [`DELAY_MARGIN`] (about three of those deviations) can be the noise's,
    /// and the delay off by a sample. (With a fraction, [`DelaySearch::std_dev`] says how sure
    /// it is; a delay halfway between two samples has a small margin and is no less sure.)
    pub fn log_likelihood_margin(&self) -> f64 {
        let whole = self.whole();
        let best = self
            .criterion
            .iter()
            .find(|(d, _)| *d == whole)
            .map_or(f64::NAN, |(_, c)| *c);
        let next = self
            .criterion
            .iter()
            .filter(|(d, _)| *d != whole)
            .map(|(_, c)| *c)
            .fold(f64::INFINITY, f64::min);
        self.samples_compared as f64 * (next - best)
    }
}

/// Searches the delay over `−max..=max` samples (then between samples when `fractional`), the
/// log of `len` samples with the motion of the samples `kept`, each candidate fitted by
/// `fit` on the torques its [`Alignment`] pairs, each joint's noise estimated with the fit
/// (whole candidates) or held at the best whole candidate's (between samples: the criterion
/// is then smooth in the delay, where noise estimates that settle to a tolerance would make
/// it jump by as much as it changes over a tenth of a sample).
pub(crate) fn search_delay(
    kept: &[usize],
    len: usize,
    max: usize,
    fractional: bool,
    fit: impl Fn(&Alignment, Option<&[f64]>) -> Result<BaseEstimate, IdentifyError>,
) -> Result<DelaySearch, IdentifyError> {
    if len <= 2 * max + 1 || kept.is_empty() {
        return Err(IdentifyError::data(format!(
            "{len} samples cannot show a delay of up to {max} samples"
        )));
    }
    // The torques whose motion is in the log at every candidate (and, for a fraction, the
    // interpolation's neighbours of every delay up to a sample beyond).
    let reach = if fractional { max + 3 } else { max };
    let (first, last) = (kept[0], kept[kept.len() - 1]);
    let common = |k: usize| k >= first + reach && k + reach <= last;
    let mut samples_compared = 0;
    // `Σ_j ln σ_j` at delay `d`, and the noise; `noise` held, when given.
    let criterion_at = |d: f64, noise: Option<&[f64]>, compared: &mut usize| {
        let alignment = Alignment::new(kept, len, d, common);
        *compared = alignment.len();
        let estimate = fit(&alignment, noise)?;
        let criterion: f64 = estimate.joint_noise.iter().map(|s| s.ln()).sum();
        Ok::<_, IdentifyError>((criterion, estimate.joint_noise))
    };
    let m = max as i64;
    let mut criterion = Vec::with_capacity(2 * max + 1);
    let mut noises = Vec::with_capacity(2 * max + 1);
    for d in -m..=m {
        let (c, noise) = criterion_at(d as f64, None, &mut samples_compared)?;
        criterion.push((d, c));
        noises.push(noise);
    }
    let mut search = DelaySearch {
        samples: 0.0,
        criterion,
        samples_compared,
        std_dev: None,
    };
    let whole = search.whole();
    search.samples = whole as f64;
    if fractional {
        let noise = &noises[(whole + m) as usize];
        let mut at = |d: f64| criterion_at(d, Some(noise), &mut samples_compared).map(|(c, _)| c);
        let golden = (5f64.sqrt() - 1.0) / 2.0;
        let (mut a, mut b) = (whole as f64 - 1.0, whole as f64 + 1.0);
        let (mut c, mut d) = (b - golden * (b - a), a + golden * (b - a));
        let (mut fc, mut fd) = (at(c)?, at(d)?);
        while b - a > FRACTION_TOLERANCE {
            if fc < fd {
                (b, d, fd) = (d, c, fc);
                c = b - golden * (b - a);
                fc = at(c)?;
            } else {
                (a, c, fc) = (c, d, fd);
                d = a + golden * (b - a);
                fd = at(d)?;
            }
        }
        let found = 0.5 * (a + b);
        let centre = at(found)?;
        let (below, above) = (at(found - CURVATURE_STEP)?, at(found + CURVATURE_STEP)?);
        let curvature = (below - 2.0 * centre + above) / (CURVATURE_STEP * CURVATURE_STEP);
        search.samples = found;
        search.std_dev = Some(if curvature > 0.0 {
            (samples_compared as f64 * curvature).sqrt().recip()
        } else {
            f64::INFINITY
        });
    }
    Ok(search)
}
