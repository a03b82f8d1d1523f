//! Identification without accelerations: the energy theorem and the Lagrange equations,
//! integrated over windows of the data.
//!
//! ## Energy form
//!
//! The total energy `H = T + V` is linear in θ (`H = e_H(q, q̇)·θ`, the kinetic energy with the
//! armature and the potential in gravity), and the joint torques change it at the rate `q̇ᵀ τ`
//! less the power the friction and offset terms take (`e_P(q̇)·θ`, also linear in θ). Over a
//! window `[t0, t1]`:
//!
//! ```text
//! ∫ q̇ᵀ τ dt = [e_H(t1) − e_H(t0) + ∫ e_P dt] · θ
//! ```
//!
//! one equation per window, with positions, velocities and torques only: no `q̈`, so a
//! velocity computed by one difference of filtered positions suffices. The integrals are the
//! trapezoid rule over the samples (the integrands `q̇ᵀ τ`, `q̇_j²`, `|q̇_j|`, `q̇_j` are
//! continuous even where Coulomb friction switches).
//!
//! Base parameters: a direction of θ that changes no torque at any state does no work, so its
//! `H` is the same at every state and cancels in the difference `e_H(t1) − e_H(t0)` (its `H`
//! need not be zero: the first moment along a base joint's vertical axis adds a constant
//! potential). So the windowed rows, restricted to the torque regressor's base columns, fit
//! the same base parameters `θ_b` as the torque form; `tests/energy.rs` checks this.
//!
//! Weights: window `w`'s torque integral carries noise of variance `Σ_j F_wj σ_j²` with
//! `F_wj = Σ_k c_k² q̇_jk²` (`c_k` the trapezoid weights), and the energy difference carries the
//! error of the velocities at its two ends, about the same in every window (`σ_0²`). The
//! variances `σ_0², σ_j²` are fitted (non-negative least squares) to the squared residuals of
//! the previous fit, starting from an unweighted one, and the windows weighted by
//! `1/(σ_0² + Σ_j F_wj σ_j²)`, until the `σ_j` settle (as the torque form's noise does).
//! [`BaseEstimate::joint_noise`] then holds the fitted torque noise `σ_j` of each joint.
//!
//! One scalar equation per window mixes all joints: the energy form's condition number is
//! tens to hundreds of times the torque form's on the same data, and so are its errors
//! (`docs/identification.md`).
//!
//! ## Momentum form
//!
//! The Lagrange equations `ṗ − ∂T/∂q + g = τ − τ_terms` with the generalised momentum
//! `p = ∂T/∂q̇ = D q̇`, integrated over each window, one equation per joint:
//!
//! ```text
//! ∫ τ dt = p(t1) − p(t0) + ∫ (g − ∂T/∂q + τ_terms) dt
//! ```
//!
//! again with `q` and `q̇` only. Its rows are integrals of the torque form's rows, so they have
//! its base parameters and about its condition number, and its noise is per joint, weighted
//! and re-estimated by the torque form's least squares.

use crate::data::Samples;
use crate::error::IdentifyError;
use crate::least_squares::{estimate, BaseEstimate, Observations};
use crate::observation::{BaseModel, Prepared};
use dyngen_model::dynamics::NumericDynamics;
use nalgebra::{DMatrix, DVector};

/// What identification fits to the data.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Observation {
    /// The inverse dynamics `Y_b(q, q̇, q̈) θ_b = τ` at every sample: needs accelerations (given,
    /// or positions differentiated twice).
    #[default]
    Torque,
    /// The energy theorem over consecutive windows of `window` seconds: needs velocities
    /// (given, or positions differentiated once), no accelerations; one equation per window.
    Energy { window: f64 },
    /// The Lagrange equations integrated over consecutive windows of `window` seconds (the
    /// generalised momentum `p = D q̇` at the ends, the other terms integrated): like
    /// `Energy`, no accelerations, but one equation per joint and window.
    Momentum { window: f64 },
}

/// A window for [`Observation::Energy`] and [`Observation::Momentum`] (s). The velocity error
/// at a window's two ends enters its equation once, whatever its length, while the integrals
/// grow with it: on arm7 with 14- and 12-bit encoders and the default filter, the momentum
/// form's validation torque error with 0.1 s windows is a third and a seventh of that with
/// 0.02 s ones (`docs/identification.md`), and 20 s of data still give 200 windows.
pub const DEFAULT_WINDOW: f64 = 0.1;

/// Re-estimates of the window variances at most: variances that have not settled by then are
/// reported (`noise_settled`), not looped on.
const MAX_VARIANCE_ITERATIONS: usize = 10;
/// The window variances have settled when no `σ_j` changes by more than this fraction.
const VARIANCE_SETTLED: f64 = 1e-3;

/// The windowed energy equations: one row of the base regressor and one power integral per
/// window, and the noise features `[1, F_w1, …, F_wn]` of each window.
pub(crate) struct EnergyRows {
    pub w: DMatrix<f64>,
    pub y: DVector<f64>,
    pub features: DMatrix<f64>,
}

/// Windows of `window` seconds over the prepared samples (`time` of the original samples), each
/// ending where the next begins.
pub(crate) fn energy_rows(
    base: &BaseModel<'_>,
    prepared: &Prepared,
    time: &[f64],
    window: f64,
) -> Result<EnergyRows, IdentifyError> {
    check_window(window)?;
    let dynamics = NumericDynamics::new(base.model);
    let n = base.model.dof();
    let columns = &base.base.columns;
    let b = columns.len();
    let t: Vec<f64> = prepared.kept.iter().map(|&k| time[k]).collect();
    let energy = |k: usize| {
        let e = dynamics.energy_regressor(&prepared.q[k], &prepared.qd[k]);
        DVector::from_iterator(b, columns.iter().map(|&c| e[c]))
    };
    let dissipation = |k: usize| {
        let e = dynamics.joint_term_power_regressor(&prepared.qd[k]);
        DVector::from_iterator(b, columns.iter().map(|&c| e[c]))
    };
    let power = |k: usize| {
        prepared.qd[k]
            .iter()
            .zip(&prepared.tau[k])
            .map(|(v, f)| v * f)
            .sum::<f64>()
    };
    let (mut rows, mut ys, mut features) = (Vec::new(), Vec::new(), Vec::new());
    for (start, end) in windows(&t, window) {
        let mut row = energy(end) - energy(start);
        let mut y = 0.0;
        let mut f = vec![0.0; n + 1];
        f[0] = 1.0;
        for k in start..=end {
            let c = trapezoid(&t, start, end, k);
            row += dissipation(k) * c;
            y += power(k) * c;
            for j in 0..n {
                f[j + 1] += (c * prepared.qd[k][j]).powi(2);
            }
        }
        rows.push(row);
        ys.push(y);
        features.push(f);
    }
    let windows = rows.len();
    let mut w = DMatrix::zeros(windows, b);
    for (i, r) in rows.iter().enumerate() {
        w.row_mut(i).copy_from(&r.transpose());
    }
    Ok(EnergyRows {
        w,
        y: DVector::from_vec(ys),
        features: DMatrix::from_fn(windows, n + 1, |i, j| features[i][j]),
    })
}

/// The windowed momentum equations (window-major, then joint, like the torque form's rows):
/// `∫ τ_j dt = [p_j]_{t0}^{t1} + ∫ (g_j − ∂T/∂q_j + τ_terms,j) dt`, each term's base regressor.
pub(crate) fn momentum_rows(
    base: &BaseModel<'_>,
    prepared: &Prepared,
    time: &[f64],
    window: f64,
) -> Result<(DMatrix<f64>, DVector<f64>), IdentifyError> {
    check_window(window)?;
    let model = base.model;
    let dynamics = NumericDynamics::new(model);
    let n = model.dof();
    let columns = &base.base.columns;
    let b = columns.len();
    let inertial = model.inertial_parameter_count();
    let t: Vec<f64> = prepared.kept.iter().map(|&k| time[k]).collect();
    let zero = vec![0.0; n];
    let restrict = |y: &DMatrix<f64>| y.select_columns(columns.iter());
    // p = D q̇ (armature included): the regressor at a = q̇ without velocity, less gravity.
    let momentum = |k: usize| {
        let (q, qd) = (&prepared.q[k], &prepared.qd[k]);
        restrict(&(dynamics.regressor(q, &zero, &zero, qd) - dynamics.regressor(q, &zero, &zero, &zero)))
    };
    // g − ∂T/∂q + τ_terms: gravity from the regressor at rest (inertial columns), the joint
    // terms from the regressor at (q̇, v = q̇, a = 0) (their columns), ∂T/∂q by central
    // differences of the kinetic energy's regressor (a trigonometric polynomial in q: the
    // step's truncation error is ~1e-12 of it).
    let forcing = |k: usize| {
        let (q, qd) = (&prepared.q[k], &prepared.qd[k]);
        let mut f = dynamics.regressor(q, &zero, &zero, &zero);
        let moving = dynamics.regressor(q, qd, qd, &zero);
        let terms = f.ncols() - inertial;
        f.columns_mut(inertial, terms)
            .copy_from(&moving.columns(inertial, terms));
        let h = 1e-6;
        for j in 0..n {
            let (mut up, mut down) = (q.clone(), q.clone());
            up[j] += h;
            down[j] -= h;
            let d = (dynamics.kinetic_energy_regressor(&up, qd)
                - dynamics.kinetic_energy_regressor(&down, qd))
                / (2.0 * h);
            let mut row = f.row_mut(j);
            row -= d.transpose();
        }
        restrict(&f)
    };
    let windows = windows(&t, window);
    let mut w = DMatrix::zeros(windows.len() * n, b);
    let mut y = DVector::zeros(windows.len() * n);
    for (i, &(start, end)) in windows.iter().enumerate() {
        let mut block = momentum(end) - momentum(start);
        let mut integral = DVector::zeros(n);
        for k in start..=end {
            let c = trapezoid(&t, start, end, k);
            block += forcing(k) * c;
            integral += DVector::from_column_slice(&prepared.tau[k]) * c;
        }
        w.view_mut((i * n, 0), (n, b)).copy_from(&block);
        y.rows_mut(i * n, n).copy_from(&integral);
    }
    Ok((w, y))
}

fn check_window(window: f64) -> Result<(), IdentifyError> {
    if window.is_finite() && window > 0.0 {
        Ok(())
    } else {
        Err(IdentifyError::data(format!(
            "the integration window must be a positive number of seconds, not {window}"
        )))
    }
}

/// Consecutive windows `(start, end)` (sample indices, inclusive) of at least `window` seconds,
/// each ending where the next begins; a tail shorter than a window is left out (its equation
/// would be weighted as a full one's).
fn windows(t: &[f64], window: f64) -> Vec<(usize, usize)> {
    let long_enough = |a: usize, b: usize| t[b] - t[a] >= window * (1.0 - 1e-9);
    let mut out = Vec::new();
    let mut start = 0;
    while start + 1 < t.len() {
        let mut end = start + 1;
        while end + 1 < t.len() && !long_enough(start, end) {
            end += 1;
        }
        if !long_enough(start, end) {
            break;
        }
        out.push((start, end));
        start = end;
    }
    out
}

/// The trapezoid rule's weight of sample `k` in the integral over `[start, end]`.
fn trapezoid(t: &[f64], start: usize, end: usize, k: usize) -> f64 {
    let left = if k > start { t[k] - t[k - 1] } else { 0.0 };
    let right = if k < end { t[k + 1] - t[k] } else { 0.0 };
    0.5 * (left + right)
}

/// Base parameters from the windowed momentum equations: the torque form's least squares
/// (weighted by each joint's noise, re-estimated) on integrals instead of samples.
pub(crate) fn estimate_by_momentum(
    base: &BaseModel<'_>,
    samples: &Samples,
    prepared: &Prepared,
    window: f64,
) -> Result<BaseEstimate, IdentifyError> {
    let (w, y) = momentum_rows(base, prepared, &samples.time, window)?;
    let observations = Observations::Stacked {
        w: &w,
        tau: &y,
        n: base.model.dof(),
    };
    estimate(observations, &base.base.names)
}

/// Non-negative least squares `min ‖A x − y‖, x ≥ 0` for a few unknowns: the unconstrained
/// solution on the free variables, the most negative one fixed at zero, repeated.
fn non_negative_least_squares(a: &DMatrix<f64>, y: &DVector<f64>) -> DVector<f64> {
    let p = a.ncols();
    let norms: Vec<f64> = a.column_iter().map(|c| c.norm().max(f64::MIN_POSITIVE)).collect();
    let mut free: Vec<usize> = (0..p).filter(|&j| norms[j] > f64::MIN_POSITIVE).collect();
    let mut x = DVector::zeros(p);
    while !free.is_empty() {
        let sub = DMatrix::from_fn(a.nrows(), free.len(), |i, k| a[(i, free[k])] / norms[free[k]]);
        let Ok(solution) = sub.clone().svd(true, true).solve(y, 1e-12) else {
            break;
        };
        let most_negative = (0..free.len())
            .filter(|&k| solution[k] < 0.0)
            .min_by(|&i, &j| solution[i].total_cmp(&solution[j]));
        match most_negative {
            Some(k) => {
                free.remove(k);
            }
            None => {
                x.fill(0.0);
                for (k, &j) in free.iter().enumerate() {
                    x[j] = solution[k] / norms[j];
                }
                break;
            }
        }
    }
    x
}

/// Base parameters from the windowed energy equations of `samples` (already prepared),
/// weighted least squares with the window variances fitted to the residuals; see the module docs.
pub(crate) fn estimate_by_energy(
    base: &BaseModel<'_>,
    samples: &Samples,
    prepared: &Prepared,
    window: f64,
) -> Result<BaseEstimate, IdentifyError> {
    let rows = energy_rows(base, prepared, &samples.time, window)?;
    let n = base.model.dof();
    let windows = rows.y.len();
    let b = rows.w.ncols();
    if windows < b + n + 1 {
        return Err(IdentifyError::Unidentifiable(format!(
            "{windows} energy windows of {window} s give {windows} equations for {b} base parameters \
             (and {} noise levels): record longer or use shorter windows",
            n + 1
        )));
    }
    let weighted = |variance: &DVector<f64>| -> Result<BaseEstimate, IdentifyError> {
        let scale = variance.map(|v| 1.0 / v.sqrt());
        let mut w = rows.w.clone();
        for (mut r, s) in w.row_iter_mut().zip(scale.iter()) {
            r *= *s;
        }
        let y = rows.y.component_mul(&scale);
        let observations = Observations::Stacked { w: &w, tau: &y, n: 1 };
        estimate(observations, &base.base.names)
    };
    // The variances' fit to squared residuals, floored so that no window's weight is infinite.
    let variances = |estimate: &BaseEstimate| -> (DVector<f64>, Vec<f64>) {
        let theta = DVector::from_column_slice(&estimate.theta_b);
        let r2 = (&rows.y - &rows.w * theta).map(|r| r * r);
        let s = non_negative_least_squares(&rows.features, &r2);
        let mut v = &rows.features * &s;
        let floor = 1e-9 * v.max().max(r2.mean()).max(f64::MIN_POSITIVE);
        v.apply(|x| *x = x.max(floor));
        (v, s.iter().skip(1).map(|x| x.sqrt()).collect())
    };
    let mut fit = weighted(&DVector::from_element(windows, 1.0))?;
    let (mut variance, mut noise) = variances(&fit);
    let (mut iterations, mut settled) = (0, false);
    while iterations < MAX_VARIANCE_ITERATIONS {
        fit = weighted(&variance)?;
        iterations += 1;
        let (next_variance, next_noise) = variances(&fit);
        let change = next_noise
            .iter()
            .zip(&noise)
            .map(|(a, b)| {
                if *b > 0.0 {
                    (a / b - 1.0).abs()
                } else {
                    (a - b).abs()
                }
            })
            .fold(0.0, f64::max);
        (variance, noise) = (next_variance, next_noise);
        if change <= VARIANCE_SETTLED {
            settled = true;
            break;
        }
    }
    fit = weighted(&variance)?;
    fit.joint_noise = noise;
    fit.noise_iterations = iterations;
    fit.noise_settled = settled;
    Ok(fit)
}
