//! Weighted least squares on the base parameters, with standard deviations, and the
//! diagnosis of what the data cannot determine.
//!
//! `W θ_b ≈ τ` (rows sample-major, the stacked observation). Joints differ in noise (a wrist's
//! torque sensor is finer than a shoulder's, and an industrial arm's torques span three orders
//! of magnitude from base to wrist), so the fit is weighted by `1/σ_j`, and the `σ_j` are
//! estimated from the data by iterative reweighting:
//! 1. ordinary least squares; the residuals of joint `j` give a first `σ_j`;
//! 2. least squares weighted by `1/σ_j`; its residuals give the next `σ_j`; repeated until no
//!    `σ_j` changes by more than [`NOISE_SETTLED`] (at most [`MAX_NOISE_ITERATIONS`] times).
//!
//! Why repeat: the ordinary residuals of a quiet joint carry the noise of the loud ones (every
//! joint's rows determine the shared parameters, and the loud joints' errors leak into the
//! quiet joint's residuals through them), so the first `σ_j` of a wrist comes out several times
//! too large and the weighted fit under-weights it; the weighted residuals no longer leak, and
//! two or three re-estimates settle. Each `σ_j²` is `‖r_j‖²` over its degrees of freedom
//! `N − tr(H_j)`, `H_j` the joint's share of the hat matrix (its leverage: the shares add up to
//! the `b` parameters), so the estimate is unbiased whatever the weights.
//!
//! The covariance of `θ_b` is `s² (Wᵀ Σ⁻¹ W)⁻¹` with `s²` the weighted residual variance (≈ 1
//! when the noise model fits).
//!
//! Numerics: columns are scaled to unit norm (masses, moments, inertias and friction differ
//! by orders of magnitude), the normal equations are solved by Cholesky and refined once with
//! the true residual, which recovers noise-free parameters to rounding error for any
//! excitation whose scaled condition number is below ~10⁶. Below that, the data does not
//! determine every base parameter: that is an error naming the parameter and why. The same
//! algorithm runs on normal equations accumulated sample by sample (a log too long to stack),
//! where the residuals come from the sums and there is nothing to refine with.

use crate::error::IdentifyError;
use crate::normal_equations::NormalEquations;
use nalgebra::{DMatrix, DVector};

/// The least-squares estimate of the base parameters.
#[derive(Clone, Debug)]
pub struct BaseEstimate {
    pub names: Vec<String>,
    pub theta_b: Vec<f64>,
    /// Standard deviation of each base parameter: the square roots of the diagonal of
    /// [`BaseEstimate::covariance`].
    pub std_dev: Vec<f64>,
    /// Estimated torque noise `σ_j` per joint (from the weighted residuals, once settled).
    pub joint_noise: Vec<f64>,
    /// How many times the noise was re-estimated from weighted residuals.
    pub noise_iterations: usize,
    /// Whether the noise estimate settled (no `σ_j` changed by more than 0.1% in the last
    /// re-estimate) within the cap on re-estimates.
    pub noise_settled: bool,
    /// Weighted residual variance `s²` (≈ 1 when the per-joint noise model fits).
    pub residual_variance: f64,
    /// Information matrix `Wᵀ Σ⁻¹ W / s²` in column-scaled coordinates, and the scales:
    /// `θ_b = scale ∘ x`. Its Cholesky factor turns a parameter error into a whitened
    /// data misfit (used by the consistent estimate).
    pub information_scaled: DMatrix<f64>,
    pub scale: Vec<f64>,
    /// Condition number of the column-scaled stacked regressor.
    pub condition_number: f64,
}

/// The limit on a parameter's relative standard deviation `σ/|θ_b|` above which it is
/// reported as poorly determined, unless the caller chooses another: 10%, a parameter known
/// to a tenth of its value.
pub const DEFAULT_MAX_RELATIVE_STD: f64 = 0.10;

/// How far an estimate can be trusted, at a limit on the relative standard deviation
/// ([`BaseEstimate::trust`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Trust {
    /// The limit on `σ/|θ_b|` (a fraction: 0.1 is 10%).
    pub max_relative_std: f64,
    /// The parameters whose `σ/|θ_b|` is above the limit, in column order.
    pub flagged: Vec<usize>,
    /// Why the estimate as a whole cannot be trusted, in one sentence; `None` when it can.
    pub untrusted: Option<String>,
}

impl BaseEstimate {
    /// Weighted least squares on a stacked base regressor `w` (rows sample-major over `dof`
    /// joints: row `k·dof + j` is joint `j` at sample `k`) and its torques, the parameters
    /// named `names`: what [`identify`](crate::identify) computes first.
    pub fn from_stacked(
        w: &DMatrix<f64>,
        tau: &DVector<f64>,
        dof: usize,
        names: &[String],
    ) -> Result<BaseEstimate, IdentifyError> {
        if dof == 0 || w.nrows() != tau.len() || !w.nrows().is_multiple_of(dof) || w.ncols() != names.len() {
            return Err(IdentifyError::data(format!(
                "a stacked regressor of {} × {} with {} torques, {dof} joints and {} names do not fit together",
                w.nrows(),
                w.ncols(),
                tau.len(),
                names.len()
            )));
        }
        estimate(Observations::Stacked { w, tau, n: dof }, names)
    }

    /// Weighted least squares on accumulated normal equations (a log too long to stack).
    pub fn from_normal_equations(
        equations: &NormalEquations,
        names: &[String],
    ) -> Result<BaseEstimate, IdentifyError> {
        if equations.parameters() != names.len() {
            return Err(IdentifyError::data(format!(
                "normal equations of {} parameters with {} names",
                equations.parameters(),
                names.len()
            )));
        }
        estimate(Observations::Accumulated(equations), names)
    }

    /// Relative standard deviation `σ/|θ|` of base parameter `k` (∞ for θ = 0).
    pub fn relative_std_dev(&self, k: usize) -> f64 {
        self.std_dev[k] / self.theta_b[k].abs()
    }

    /// The covariance of `θ_b`, `s² (Wᵀ Σ⁻¹ W)⁻¹`: the per-joint noise weights as estimated,
    /// `s²` the weighted residual variance. Its diagonal is the square of
    /// [`BaseEstimate::std_dev`].
    pub fn covariance(&self) -> DMatrix<f64> {
        let b = self.scale.len();
        let scaled = self
            .information_scaled
            .clone()
            .cholesky()
            .map(|c| c.inverse())
            .unwrap_or_else(|| DMatrix::from_element(b, b, f64::NAN));
        DMatrix::from_fn(b, b, |i, j| scaled[(i, j)] * self.scale[i] * self.scale[j])
    }

    /// The estimate of the first `b` parameters alone (those of the base regressor, before
    /// unknowns of the torque channel): their values, σ and marginal covariance, which
    /// carries the other unknowns' uncertainty.
    pub(crate) fn leading(&self, b: usize) -> BaseEstimate {
        let covariance = self
            .information_scaled
            .clone()
            .cholesky()
            .map(|c| c.inverse())
            .unwrap_or_else(|| DMatrix::from_element(self.scale.len(), self.scale.len(), f64::NAN));
        let block = covariance.view((0, 0), (b, b)).into_owned();
        let information_scaled = block
            .cholesky()
            .map(|c| c.inverse())
            .unwrap_or_else(|| DMatrix::from_element(b, b, f64::NAN));
        BaseEstimate {
            names: self.names[..b].to_vec(),
            theta_b: self.theta_b[..b].to_vec(),
            std_dev: self.std_dev[..b].to_vec(),
            information_scaled,
            scale: self.scale[..b].to_vec(),
            ..self.clone()
        }
    }

    /// Which parameters are poorly determined (`σ/|θ_b|` above `max_relative_std`, a
    /// fraction), and whether the estimate as a whole can be trusted: not when every
    /// parameter is poorly determined (the data says nothing about the robot beyond its
    /// noise). Data that cannot determine some parameter at all never gets this far: the
    /// estimate is then an [`IdentifyError::Unidentifiable`].
    pub fn trust(&self, max_relative_std: f64) -> Trust {
        let b = self.theta_b.len();
        let flagged: Vec<usize> = (0..b)
            // Above the limit, or not a number (0/0): not within it.
            .filter(|&k| {
                !matches!(
                    self.relative_std_dev(k).partial_cmp(&max_relative_std),
                    Some(std::cmp::Ordering::Less | std::cmp::Ordering::Equal)
                )
            })
            .collect();
        let untrusted = (b > 0 && flagged.len() == b).then(|| {
            let best = (0..b)
                .min_by(|&i, &j| self.relative_std_dev(i).total_cmp(&self.relative_std_dev(j)))
                .expect("b > 0");
            format!(
                "every one of the {b} base parameters has a relative standard deviation above {}% \
                 (the best determined, '{}', {:.3}%; scaled condition number {:.1}): the data \
                 determines none of them; excite the robot more (longer, faster, a better-conditioned \
                 trajectory) or check the torque noise",
                100.0 * max_relative_std,
                self.names[best],
                100.0 * self.relative_std_dev(best),
                self.condition_number
            )
        });
        Trust {
            max_relative_std,
            flagged,
            untrusted,
        }
    }
}

/// Scaled columns whose smallest eigenvalue of `WᵀW` is below this fraction of the largest
/// (a scaled condition number above 10⁶) do not determine every parameter: beyond it, noise
/// is amplified a million-fold and the refined solution loses its last digits.
pub(crate) const IDENTIFIABILITY_TOL: f64 = 1e-12;

/// Zero column: a norm below this fraction of the largest.
const ZERO_COLUMN_TOL: f64 = 1e-12;

/// Floor of a joint's noise estimate, relative to its torque RMS: noise-free data must not
/// make a weight infinite.
const NOISE_FLOOR: f64 = 1e-12;
/// Floor of a joint's noise relative to its torque RMS, as a share of the largest such ratio
/// of any joint: a joint the model fits exactly (noise-free, or its torque channel's gain
/// estimated) beside one it does not would otherwise get weights 10²⁴ times the other's, and
/// the weighted normal equations lose the other joints' rows to rounding.
const RELATIVE_NOISE_FLOOR: f64 = 1e-4;

/// Each joint's noise `raw` (from its residuals) held above the floors, `torque_rms` its
/// torque RMS: [`NOISE_FLOOR`] of the torques and [`RELATIVE_NOISE_FLOOR`] of the noisiest
/// joint's share.
pub(crate) fn floored_noise(raw: &[f64], torque_rms: &[f64]) -> Vec<f64> {
    let noisiest = raw
        .iter()
        .zip(torque_rms)
        .filter(|(_, r)| **r > 0.0)
        .map(|(s, r)| s / r)
        .fold(0.0, f64::max);
    raw.iter()
        .zip(torque_rms)
        .map(|(s, r)| {
            s.max(NOISE_FLOOR * r)
                .max(RELATIVE_NOISE_FLOOR * noisiest * r)
                .max(f64::MIN_POSITIVE)
        })
        .collect()
}

/// The noise estimate has settled when no joint's `σ_j` changes by more than this fraction.
pub(crate) const NOISE_SETTLED: f64 = 1e-3;
/// Cap on re-estimates of the noise: it settles in two to four on the arms tested; a noise
/// model that has not settled after this many is reported (`noise_settled`), not looped on.
pub(crate) const MAX_NOISE_ITERATIONS: usize = 20;

/// What an estimate is computed from.
#[derive(Clone, Copy)]
pub(crate) enum Observations<'a> {
    /// The stacked regressor (rows sample-major over `n` joints) and torques: residuals are
    /// computed from the rows, and every solve is refined once with the true residual, which
    /// restores the accuracy the normal equations lose.
    Stacked {
        w: &'a DMatrix<f64>,
        tau: &'a DVector<f64>,
        n: usize,
    },
    /// Normal equations accumulated sample by sample ([`NormalEquations`]): memory that does
    /// not grow with the data, at the normal equations' accuracy.
    Accumulated(&'a NormalEquations),
}

/// The per-joint normal equations in column-scaled coordinates (`x = θ_b ∘ norms`), with what
/// the residuals need.
struct Scaled<'a> {
    observations: Observations<'a>,
    norms: Vec<f64>,
    grams: Vec<DMatrix<f64>>,
    rhs: Vec<DVector<f64>>,
    squares: Vec<f64>,
}

impl Scaled<'_> {
    /// Solves `(Σ w_j G_j) x = Σ w_j c_j` (refined with the true residual when the rows are
    /// at hand).
    fn solve(&self, a: &DMatrix<f64>, weights: &[f64]) -> DVector<f64> {
        let chol = a.clone().cholesky().expect("checked positive definite");
        let b = self.norms.len();
        let rhs = self
            .rhs
            .iter()
            .zip(weights)
            .fold(DVector::zeros(b), |acc, (c, w)| acc + c * *w);
        let mut x = chol.solve(&rhs);
        if let Observations::Stacked { w, tau, n } = self.observations {
            let r = tau - w * self.unscaled(&x);
            let weighted = DVector::from_fn(r.len(), |i, _| r[i] * weights[i % n]);
            let correction = self.unscaled(&w.tr_mul(&weighted));
            x += chol.solve(&correction);
        }
        x
    }

    fn unscaled(&self, x: &DVector<f64>) -> DVector<f64> {
        DVector::from_fn(x.len(), |k, _| x[k] / self.norms[k])
    }

    /// `‖r_j‖²` of every joint at `x`.
    fn residual_squares(&self, x: &DVector<f64>) -> Vec<f64> {
        match self.observations {
            Observations::Stacked { w, tau, n } => {
                let r = tau - w * self.unscaled(x);
                let mut squares = vec![0.0; n];
                for (i, v) in r.iter().enumerate() {
                    squares[i % n] += v * v;
                }
                squares
            }
            Observations::Accumulated(_) => (0..self.grams.len())
                .map(|j| {
                    let g = &self.grams[j];
                    (self.squares[j] - 2.0 * x.dot(&self.rhs[j]) + x.dot(&(g * x))).max(0.0)
                })
                .collect(),
        }
    }
}

/// Estimates `θ_b` from the observations and the base parameters' names.
pub(crate) fn estimate(
    observations: Observations<'_>,
    names: &[String],
) -> Result<BaseEstimate, IdentifyError> {
    fit(observations, names, None)
}

/// One weighted least squares with each joint's noise at `noise`, and the noise its residuals
/// show ([`BaseEstimate::joint_noise`]; `noise_settled` when it is `noise` to
/// [`NOISE_SETTLED`]): a smooth function of the observations, for an outer iteration that
/// re-estimates the noise itself (the settled noise of [`estimate`] depends on where its
/// re-estimates stop, which would make the outer map jump).
pub(crate) fn estimate_at_noise(
    observations: Observations<'_>,
    names: &[String],
    noise: &[f64],
) -> Result<BaseEstimate, IdentifyError> {
    fit(observations, names, Some(noise))
}

/// [`estimate`], or [`estimate_at_noise`] with `given`.
fn fit(
    observations: Observations<'_>,
    names: &[String],
    given: Option<&[f64]>,
) -> Result<BaseEstimate, IdentifyError> {
    let stacked;
    let equations = match observations {
        Observations::Stacked { w, tau, n } => {
            stacked = NormalEquations::from_stacked(w, tau, n);
            &stacked
        }
        Observations::Accumulated(equations) => equations,
    };
    let (n, b, samples) = (equations.dof(), equations.parameters(), equations.samples());
    let rows = samples * n;
    if rows < b + n {
        return Err(IdentifyError::Unidentifiable(format!(
            "{samples} samples give {rows} equations for {b} base parameters (and {n} noise levels): too few samples"
        )));
    }
    let norms: Vec<f64> = (0..b)
        .map(|k| (0..n).map(|j| equations.joint(j).0[(k, k)]).sum::<f64>().sqrt())
        .collect();
    let largest = norms.iter().copied().fold(0.0, f64::max);
    if let Some(k) = (0..b).find(|&k| norms[k] <= ZERO_COLUMN_TOL * largest) {
        return Err(IdentifyError::Unidentifiable(format!(
            "base parameter '{}' cannot be determined: its regressor column is zero over all samples \
             (the data never moves, accelerates or reverses what it multiplies); excite that joint",
            names[k]
        )));
    }
    // Columns scaled to unit norm: the weighted normal equations are the weighted sum of the
    // joints' scaled Gram matrices.
    let scaled = Scaled {
        observations,
        grams: (0..n)
            .map(|j| DMatrix::from_fn(b, b, |r, c| equations.joint(j).0[(r, c)] / (norms[r] * norms[c])))
            .collect(),
        rhs: (0..n)
            .map(|j| DVector::from_fn(b, |r, _| equations.joint(j).1[r] / norms[r]))
            .collect(),
        squares: (0..n).map(|j| equations.joint(j).2).collect(),
        norms: norms.clone(),
    };
    let grams = &scaled.grams;
    let a = grams.iter().fold(DMatrix::zeros(b, b), |acc, g| acc + g);
    let condition_number = scaled_condition_number(&a, names)?;
    // The torque RMS of each joint, for the floor of its noise.
    let torque_rms: Vec<f64> = scaled
        .squares
        .iter()
        .map(|s| (s / samples as f64).sqrt())
        .collect();
    // σ_j² = ‖r_j‖² / (N − tr(A⁻¹ G_j w_j)): the residuals of a fit weighted by `w_j`
    // (normal matrix `A = Σ w_j G_j`), over the joint's degrees of freedom.
    let noise_of = |x: &DVector<f64>, a: &DMatrix<f64>, w: &[f64]| -> Vec<f64> {
        let squares = scaled.residual_squares(x);
        let a_inv = a.clone().cholesky().expect("checked positive definite").inverse();
        let raw: Vec<f64> = (0..n)
            .map(|j| {
                let leverage = a_inv.component_mul(&grams[j]).sum() * w[j];
                let dof = (samples as f64 - leverage).max(1.0);
                (squares[j] / dof).sqrt()
            })
            .collect();
        floored_noise(&raw, &torque_rms)
    };
    let weighted = |noise: &[f64]| {
        let w: Vec<f64> = noise.iter().map(|s| s.powi(-2)).collect();
        let aw = grams
            .iter()
            .zip(&w)
            .fold(DMatrix::zeros(b, b), |acc, (g, wj)| acc + g * *wj);
        let x = scaled.solve(&aw, &w);
        (x, aw, w)
    };
    // 1. Ordinary least squares and a first noise of each joint (or the noise given).
    let mut joint_noise = match given {
        Some(noise) => noise.to_vec(),
        None => {
            let x = scaled.solve(&a, &vec![1.0; n]);
            noise_of(&x, &a, &vec![1.0; n])
        }
    };
    // 2. Weighted least squares, the noise re-estimated from its residuals until it settles
    // (given: once, the fit kept at the noise given).
    let (mut x, mut aw, mut weights) = weighted(&joint_noise);
    let (mut noise_iterations, mut noise_settled) = (0, false);
    if given.is_some() {
        let next = noise_of(&x, &aw, &weights);
        noise_iterations = 1;
        noise_settled = relative_change(&next, &joint_noise) <= NOISE_SETTLED;
        joint_noise = next;
    }
    while given.is_none() && noise_iterations < MAX_NOISE_ITERATIONS {
        let next = noise_of(&x, &aw, &weights);
        noise_iterations += 1;
        let change = relative_change(&next, &joint_noise);
        joint_noise = next;
        (x, aw, weights) = weighted(&joint_noise);
        if change <= NOISE_SETTLED {
            noise_settled = true;
            break;
        }
    }
    let s2 = scaled
        .residual_squares(&x)
        .iter()
        .zip(&weights)
        .map(|(r, w)| r * w)
        .sum::<f64>()
        / (rows - b) as f64;
    let s2 = if s2 > 0.0 { s2 } else { 1.0 };
    let inverse = aw
        .clone()
        .cholesky()
        .expect("checked positive definite")
        .inverse();
    let theta_b: Vec<f64> = (0..b).map(|k| x[k] / norms[k]).collect();
    let std_dev: Vec<f64> = (0..b).map(|k| (s2 * inverse[(k, k)]).sqrt() / norms[k]).collect();
    Ok(BaseEstimate {
        names: names.to_vec(),
        theta_b,
        std_dev,
        joint_noise,
        noise_iterations,
        noise_settled,
        residual_variance: s2,
        information_scaled: aw / s2,
        scale: norms.iter().map(|s| 1.0 / s).collect(),
        condition_number,
    })
}

/// The largest relative change from `before` to `after`, one number per joint.
pub(crate) fn relative_change(after: &[f64], before: &[f64]) -> f64 {
    after
        .iter()
        .zip(before)
        .map(|(a, b)| (a / b - 1.0).abs())
        .fold(0.0, f64::max)
}

/// The condition number of the columns whose scaled Gram matrix is `a` (columns of unit norm),
/// or an [`IdentifyError::Unidentifiable`] naming the parameter they cannot determine and the
/// columns it is a combination of.
pub(crate) fn scaled_condition_number(a: &DMatrix<f64>, names: &[String]) -> Result<f64, IdentifyError> {
    let b = a.nrows();
    let eigen = a.clone().symmetric_eigen();
    let (mut kmin, mut kmax) = (0, 0);
    for k in 0..b {
        if eigen.eigenvalues[k] < eigen.eigenvalues[kmin] {
            kmin = k;
        }
        if eigen.eigenvalues[k] > eigen.eigenvalues[kmax] {
            kmax = k;
        }
    }
    let (lmin, lmax) = (eigen.eigenvalues[kmin], eigen.eigenvalues[kmax]);
    if lmin <= IDENTIFIABILITY_TOL * lmax {
        let v = eigen.eigenvectors.column(kmin);
        let mut order: Vec<usize> = (0..b).collect();
        order.sort_by(|&i, &j| v[j].abs().total_cmp(&v[i].abs()));
        let others: Vec<String> = order[1..]
            .iter()
            .take_while(|&&i| v[i].abs() >= 0.1 * v[order[0]].abs())
            .take(4)
            .map(|&i| format!("'{}'", names[i]))
            .collect();
        let why = if others.is_empty() {
            "its regressor column is nearly zero".to_string()
        } else {
            format!(
                "its regressor column is a combination of those of {}",
                others.join(", ")
            )
        };
        return Err(IdentifyError::Unidentifiable(format!(
            "base parameter '{}' cannot be determined from this data: {why} (scaled condition number {:.3e}); \
             use a richer excitation",
            names[order[0]],
            (lmax / lmin.max(0.0)).sqrt()
        )));
    }
    Ok((lmax / lmin).sqrt())
}
