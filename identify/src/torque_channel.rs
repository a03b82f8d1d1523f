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
//! constant off, a gear ratio written wrong). All gains at once are not identifiable (every
//! torque twice as large is a robot twice as heavy), so they are estimated relative to one
//! joint's, held at 1: with `κ_j = 1/g_j`, the rows `Y_j θ_b − κ_j τ_j = 0` for the other
//! joints and `Y_r θ_b = τ_r` for the reference are linear in `(θ_b, κ)`, and any estimator
//! solves them ([`with_gain_columns`]).

use crate::error::IdentifyError;
use crate::least_squares::BaseEstimate;
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

/// `[m | −T]` with `T` a column per joint but `reference`, holding that joint's `torques` on its
/// rows (rows sample-major over `n` joints): the unknowns `κ_j = 1/g_j` after the parameters.
pub(crate) fn with_gain_columns(m: &DMatrix<f64>, torques: &DVector<f64>, n: usize, reference: usize) -> DMatrix<f64> {
    let b = m.ncols();
    let mut out = m.clone().resize_horizontally(b + n - 1, 0.0);
    for r in 0..m.nrows() {
        let j = r % n;
        if j != reference {
            out[(r, b + gain_column(j, reference))] = -torques[r];
        }
    }
    out
}

/// The target of the rows of [`with_gain_columns`]: the reference joint's torques, zero on
/// the others' rows.
pub(crate) fn gain_target(torques: &DVector<f64>, n: usize, reference: usize) -> DVector<f64> {
    DVector::from_fn(torques.len(), |r, _| if r % n == reference { torques[r] } else { 0.0 })
}

/// The column (after the parameters) of joint `j`'s `κ_j`.
fn gain_column(j: usize, reference: usize) -> usize {
    if j < reference {
        j
    } else {
        j - 1
    }
}

/// The names of the parameters and, after them, of the inverse gains.
pub(crate) fn gain_names(names: &[String], joints: &[String], reference: usize) -> Vec<String> {
    let mut all = names.to_vec();
    all.extend(
        joints
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != reference)
            .map(|(_, name)| format!("1/gain[{name}]")),
    );
    all
}

/// The estimate of the rows of [`with_gain_columns`] split into the base parameters' (their
/// marginal covariance) and the gains.
pub(crate) fn split_gains(
    estimate: &BaseEstimate,
    b: usize,
    joints: &[String],
    reference: usize,
) -> Result<(BaseEstimate, TorqueGains), IdentifyError> {
    let n = joints.len();
    let mut gains = vec![1.0; n];
    let mut std_dev = vec![0.0; n];
    for j in (0..n).filter(|&j| j != reference) {
        let c = b + gain_column(j, reference);
        let kappa = estimate.theta_b[c];
        if kappa <= 0.0 {
            return Err(IdentifyError::Unidentifiable(format!(
                "the torque gain of joint '{}' relative to joint '{}' comes out {}: not a gain; the \
                 data cannot tell it (check that the joint moves and its torque is logged)",
                joints[j],
                joints[reference],
                if kappa == 0.0 { "infinite".to_string() } else { "negative".to_string() }
            )));
        }
        gains[j] = 1.0 / kappa;
        std_dev[j] = estimate.std_dev[c] / (kappa * kappa);
    }
    Ok((
        estimate.leading(b),
        TorqueGains {
            reference,
            gains,
            std_dev,
        },
    ))
}
