//! The torque channel between the drives and the log: a delay behind the positions (any
//! fraction of a sample) and a gain per joint.
//!
//! **Delay.** A torque logged at sample `k` with a delay of `d` samples belongs to the motion
//! at `k − d`. For a fraction of a sample, the motion's rows are interpolated there (cubic
//! Lagrange on the four samples around it; its error is `O(h⁴)` of a smooth motion), never
//! the torques: interpolating noisy torques would average their noise, and a delay halfway
//! between samples would look less noisy than the truth. The regressor, the instruments and
//! the simulated torques are rows of the motion and are interpolated alike ([`Alignment`]).
//!
//! **Gains.** A joint's torque channel may read `g_j` times its torque (a drive's torque
//! constant off, a gear ratio written wrong): `τ_j = g_j Y_j θ_b + ε_j`. All gains at once are
//! not identifiable (every torque twice as large is a robot twice as heavy), so they are
//! estimated relative to one joint's, held at 1. The model is bilinear in `(θ_b, g)`; about a
//! point `(θ₀, g₀)` it is linear, `τ + g₀ ∘ Y θ₀ ≈ diag(g₀) Y θ_b + diag(Y θ₀) g`
//! ([`GainModel::linearised`]), and each estimator's step solves that (Gauss–Newton: the least
//! squares repeat it to convergence, IDIM-IV and DIDIM once per simulation). The residuals
//! stay in the logged torques' units, so each joint's noise is estimated as without gains.
//! (The form linear from the start, `Y_j θ_b − τ_j/g_j = 0`, puts the noisy torques in the
//! regressor and leaves the other joints' rows without a target: weighting each joint by its
//! residuals then shrinks `θ_b` and `1/g_j` towards zero, where those rows fit exactly.)

use crate::error::IdentifyError;
use crate::least_squares::{estimate, estimate_at_noise, BaseEstimate, Observations};
use nalgebra::{DMatrix, DVector};

/// Each joint's torque gain, relative to one joint's ([`Identification::gains`]).
///
/// [`Identification::gains`]: crate::Identification::gains
#[derive(Clone, Debug, PartialEq)]
pub struct TorqueGains {
    /// The joint whose gain is held at 1.
    pub reference: usize,
    /// Per joint, what its torque channel reads per unit of torque (1 for the reference): the
    /// estimate divides the logged torques by it.
    pub gains: Vec<f64>,
    /// Their standard deviations (0 for the reference).
    pub std_dev: Vec<f64>,
}

/// Which motion each torque used pairs with: the torque at a log index, and the motion's
/// rows at `k − d` as weights on the kept samples' rows.
#[derive(Clone, Debug)]
pub(crate) struct Alignment {
    pairs: Vec<(usize, Vec<(usize, f64)>)>,
}

/// A delay within this of a whole number of samples is that number: its rows are the
/// samples' own.
const WHOLE: f64 = 1e-9;

impl Alignment {
    /// The torques of a log of `len` samples, `delay` samples behind the motion, paired with
    /// the motion of the samples `kept` (ascending and contiguous, as [`crate::prepare`] keeps
    /// them), for every torque index `take` accepts whose motion is among them.
    pub fn new(kept: &[usize], len: usize, delay: f64, take: impl Fn(usize) -> bool) -> Alignment {
        let (first, last) = (kept[0] as i64, kept[kept.len() - 1] as i64);
        let position = |i: i64| (i - first) as usize;
        let pairs = (0..len)
            .filter(|&k| take(k))
            .filter_map(|k| {
                let at = k as f64 - delay;
                let below = at.floor();
                let s = at - below;
                let nodes: Vec<(i64, f64)> = if s <= WHOLE || s >= 1.0 - WHOLE {
                    vec![(at.round() as i64, 1.0)]
                } else {
                    let i = below as i64;
                    vec![
                        (i - 1, -s * (s - 1.0) * (s - 2.0) / 6.0),
                        (i, (s + 1.0) * (s - 1.0) * (s - 2.0) / 2.0),
                        (i + 1, -(s + 1.0) * s * (s - 2.0) / 2.0),
                        (i + 2, (s + 1.0) * s * (s - 1.0) / 6.0),
                    ]
                };
                nodes
                    .iter()
                    .all(|&(i, _)| i >= first && i <= last)
                    .then(|| (k, nodes.iter().map(|&(i, c)| (position(i), c)).collect()))
            })
            .collect();
        Alignment { pairs }
    }

    /// The torques used.
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// The rows of `m` (sample-major over `n` joints, one sample per kept index) at the motion
    /// each torque pairs with.
    pub fn rows(&self, m: &DMatrix<f64>, n: usize) -> DMatrix<f64> {
        let mut out = DMatrix::zeros(self.pairs.len() * n, m.ncols());
        for (p, (_, nodes)) in self.pairs.iter().enumerate() {
            let mut block = out.rows_mut(p * n, n);
            for &(i, c) in nodes {
                block += m.rows(i * n, n) * c;
            }
        }
        out
    }

    /// The torques used, stacked, from every sample's torques `tau`.
    pub fn torques(&self, tau: &[Vec<f64>]) -> DVector<f64> {
        DVector::from_iterator(
            self.pairs.iter().map(|(k, _)| tau[*k].len()).sum(),
            self.pairs.iter().flat_map(|(k, _)| tau[*k].iter().copied()),
        )
    }
}

/// The weighted least squares of `m θ ≈ tau` (rows sample-major over `n` joints), the
/// unknowns named `names`: each joint's noise estimated with them until it settles
/// ([`estimate`]), or held at `noise` ([`estimate_at_noise`], a smooth function of the data,
/// as a search over the data needs).
pub(crate) fn fit_torques(
    m: &DMatrix<f64>,
    tau: &DVector<f64>,
    n: usize,
    names: &[String],
    noise: Option<&[f64]>,
) -> Result<BaseEstimate, IdentifyError> {
    let observations = Observations::Stacked { w: m, tau, n };
    match noise {
        Some(noise) => estimate_at_noise(observations, names, noise),
        None => estimate(observations, names),
    }
}

/// The gains' unknowns after the base parameters: one per joint but `reference`, whose gain
/// is 1.
#[derive(Clone, Debug)]
pub(crate) struct GainModel {
    /// Base parameters (the unknowns before the gains).
    pub b: usize,
    /// The joints' names, in joint order.
    pub joints: Vec<String>,
    /// The joint whose gain is held at 1.
    pub reference: usize,
}

/// Gauss–Newton steps of the least squares with gains, at most.
const MAX_GAIN_STEPS: usize = 30;
/// The least squares with gains have converged when no gain moves by more than this share of
/// its σ,
const GAIN_STEP: f64 = 1e-4;
/// or by more than this (a gain is near 1: noise-free data leave only rounding).
const GAIN_ROUNDING: f64 = 1e-12;
/// A gain whose σ is above this is not determined by the data. A joint's gain shows only
/// through the parameters its torque shares with the other joints' torques (its own joint
/// terms scale with it): a wrist whose body barely loads the other joints, against their
/// noise, leaves its gain free (measured: a 7-axis arm's last joint, σ 0.6 and growing with
/// each step, where the other joints' are 0.03–0.05).
pub const GAIN_UNDETERMINED: f64 = 0.2;

impl GainModel {
    fn n(&self) -> usize {
        self.joints.len()
    }

    /// The column (after the parameters) of joint `j`'s gain.
    fn column(&self, j: usize) -> Option<usize> {
        match j.cmp(&self.reference) {
            std::cmp::Ordering::Less => Some(self.b + j),
            std::cmp::Ordering::Equal => None,
            std::cmp::Ordering::Greater => Some(self.b + j - 1),
        }
    }

    /// Joint `j`'s gain at the unknowns `x`.
    fn gain(&self, x: &[f64], j: usize) -> f64 {
        self.column(j).map_or(1.0, |c| x[c])
    }

    /// The names of the base parameters `names` and, after them, of the gains.
    pub fn names(&self, names: &[String]) -> Vec<String> {
        let mut all = names.to_vec();
        all.extend(
            self.joints
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != self.reference)
                .map(|(_, name)| format!("gain[{name}]")),
        );
        all
    }

    /// The model `τ ≈ g ∘ m θ_b` linearised at the unknowns `x` (`θ₀`, then the gains `g₀`):
    /// the rows `[diag(g₀) m | diag(m θ₀)]` (a gain column per joint but the reference, on
    /// that joint's rows) and the target `τ + g₀ ∘ m θ₀` (`τ` on the reference's rows, whose
    /// gain is no unknown), rows sample-major.
    pub fn linearised(
        &self,
        m: &DMatrix<f64>,
        tau: &DVector<f64>,
        x: &[f64],
    ) -> (DMatrix<f64>, DVector<f64>) {
        self.linearised_affine(m, None, tau, x)
    }

    /// [`GainModel::linearised`] for a model torque affine in `θ_b` about `θ₀`, `m θ_b + c`
    /// (DIDIM's simulated torques `τ_s(θ₀) + ∂τ_s/∂θ_b (θ_b − θ₀)`, `c = τ_s(θ₀) − m θ₀`;
    /// none: `c = 0`): `τ ≈ g ∘ (m θ_b + c)` linearised at `x` has the rows
    /// `[diag(g₀) m | diag(m θ₀ + c)]` and the target `τ + g₀ ∘ m θ₀`, and `τ − c` on the
    /// reference's rows.
    pub fn linearised_affine(
        &self,
        m: &DMatrix<f64>,
        offset: Option<&DVector<f64>>,
        tau: &DVector<f64>,
        x: &[f64],
    ) -> (DMatrix<f64>, DVector<f64>) {
        let n = self.n();
        let theta = DVector::from_column_slice(&x[..self.b]);
        let linear = m * theta;
        let mut rows = m.clone().resize_horizontally(self.b + n - 1, 0.0);
        let mut target = tau.clone();
        for r in 0..m.nrows() {
            let j = r % n;
            let g = self.gain(x, j);
            let c = offset.map_or(0.0, |c| c[r]);
            rows.row_mut(r).columns_mut(0, self.b).scale_mut(g);
            match self.column(j) {
                Some(column) => {
                    rows[(r, column)] = linear[r] + c;
                    target[r] += g * linear[r];
                }
                None => target[r] -= c,
            }
        }
        (rows, target)
    }

    /// The weighted least squares of `τ ≈ g ∘ m θ_b` (rows `m` sample-major, torques `tau`)
    /// by Gauss–Newton from every gain 1, the unknowns named `unknowns`; each joint's noise
    /// estimated with them, or held at `noise` (see [`fit_torques`]).
    pub fn least_squares(
        &self,
        m: &DMatrix<f64>,
        tau: &DVector<f64>,
        unknowns: &[String],
        noise: Option<&[f64]>,
    ) -> Result<BaseEstimate, IdentifyError> {
        let n = self.n();
        let mut x = fit_torques(m, tau, n, &unknowns[..self.b], noise)?.theta_b;
        x.resize(unknowns.len(), 1.0);
        let mut steps = Vec::new();
        while steps.len() < MAX_GAIN_STEPS {
            let (rows, target) = self.linearised(m, tau, &x);
            let fit = fit_torques(&rows, &target, n, unknowns, noise)?;
            self.determined(&fit)?;
            // The gains' change (at fixed gains the parameters are linear), in σ, or against
            // the rounding of noise-free data.
            let step = (self.b..x.len())
                .map(|k| (fit.theta_b[k] - x[k]).abs() / fit.std_dev[k].max(GAIN_ROUNDING / GAIN_STEP))
                .fold(0.0, f64::max);
            steps.push(step);
            x.clone_from(&fit.theta_b);
            if step <= GAIN_STEP {
                return Ok(fit);
            }
        }
        Err(IdentifyError::Unidentifiable(format!(
            "the torque gains did not settle in {MAX_GAIN_STEPS} Gauss–Newton steps (the last moved a gain \
             by {:.2e} σ): the data barely tells the gains from the parameters; excite every joint more, \
             or leave the gains out",
            steps[steps.len() - 1]
        )))
    }

    /// An error naming the gain of `estimate` least determined when its σ is above
    /// [`GAIN_UNDETERMINED`].
    pub fn determined(&self, estimate: &BaseEstimate) -> Result<(), IdentifyError> {
        let worst = (0..self.n())
            .filter_map(|j| self.column(j).map(|c| (j, estimate.std_dev[c])))
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match worst {
            Some((j, sigma)) if sigma.is_nan() || sigma > GAIN_UNDETERMINED => {
                Err(IdentifyError::Unidentifiable(format!(
                    "the torque gain of joint '{}' is not determined by this data (σ {sigma:.2}, above \
                 {GAIN_UNDETERMINED}): a joint's gain shows only through the parameters its torque shares \
                 with the other joints', and this joint's body barely loads them; leave the gains out, or \
                 excite with more load on that joint",
                    self.joints[j]
                )))
            }
            _ => Ok(()),
        }
    }

    /// The estimate of the unknowns split into the base parameters' (their marginal
    /// covariance) and the gains: an error for a gain not determined or not positive.
    pub fn split(&self, estimate: &BaseEstimate) -> Result<(BaseEstimate, TorqueGains), IdentifyError> {
        self.determined(estimate)?;
        let n = self.n();
        let mut gains = vec![1.0; n];
        let mut std_dev = vec![0.0; n];
        for j in 0..n {
            let Some(c) = self.column(j) else { continue };
            let g = estimate.theta_b[c];
            if g <= 0.0 {
                return Err(IdentifyError::Unidentifiable(format!(
                    "the torque gain of joint '{}' relative to joint '{}' comes out {g:.3} (σ {:.3}): its \
                     torque channel reads {}; check the sign convention of the logged torques",
                    self.joints[j],
                    self.joints[self.reference],
                    estimate.std_dev[c],
                    if g == 0.0 { "nothing" } else { "against the torque" }
                )));
            }
            gains[j] = g;
            std_dev[j] = estimate.std_dev[c];
        }
        Ok((
            estimate.leading(self.b),
            TorqueGains {
                reference: self.reference,
                gains,
                std_dev,
            },
        ))
    }
}
