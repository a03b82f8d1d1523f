//! Where the consistent estimate starts from. Its free numbers are not convex in θ, so one
//! start can end in a poor local minimum when the description is far from the robot that was
//! measured (a 25 kg tool the description does not know, CAD masses off by 10%); each of
//! these starts is right in some such case, and the estimate keeps the best end.
//!
//! - [`ConsistentStart::Description`]: the description, with the joint-level parameters the
//!   least squares determine alone (a base parameter that is exactly one of them).
//! - [`ConsistentStart::LeastSquares`]: the full θ nearest the description (in the prior's
//!   scaled metric) whose base parameters are the least squares', brought to consistency body
//!   by body: right when the data is rich and the description far off.
//! - [`ConsistentStart::ScaledDescription`]: the description with each body scaled by one
//!   factor, the body that carries the end-effector free (a payload), and the joint-level
//!   parameters free, fitted to the data: a few numbers, so well determined even when the
//!   least squares' full θ is not near any consistent one.

use crate::least_squares::BaseEstimate;
use crate::objective::Problem;
use dyngen_runtime::PARAMETERS_PER_BODY;
use nalgebra::{DMatrix, DVector};
use std::fmt;

/// Where the consistent estimate started from (it tries each and keeps the best end).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConsistentStart {
    /// The description, with the joint-level parameters the least squares determine alone.
    Description,
    /// The full θ nearest the description whose base parameters are the least squares',
    /// brought to physical validity body by body.
    LeastSquares,
    /// The description with each body scaled by one factor, the end-effector's body (a
    /// payload) and the joint-level parameters fitted to the data.
    ScaledDescription,
}

impl fmt::Display for ConsistentStart {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ConsistentStart::Description => "the description",
            ConsistentStart::LeastSquares => "the least squares made consistent",
            ConsistentStart::ScaledDescription => "the description scaled, with a payload fitted",
        })
    }
}

/// Relative singular values below this are the data's blind directions in the fits below:
/// left at the description's values.
const BLIND: f64 = 1e-12;

/// `x₀ + pinv(M)(y − M x₀)`: the change of `x₀` that fits `M x ≈ y` best, smallest in norm.
fn nearest_fit(m: &DMatrix<f64>, y: &DVector<f64>, x0: &DVector<f64>) -> Option<DVector<f64>> {
    let rhs = y - m * x0;
    let svd = m.clone().svd(true, true);
    let eps = BLIND * svd.singular_values.max();
    let dx = svd.solve(&rhs, eps).ok()?;
    let x = x0 + dx;
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// The description, with the joint-level parameters the least squares determine alone.
pub(crate) fn description_start(problem: &Problem<'_>, estimate: &BaseEstimate) -> Vec<f64> {
    let p = problem.prior.len();
    let inertial = PARAMETERS_PER_BODY * problem.bodies.len();
    let mut description = problem.prior.clone();
    for row in 0..problem.k.nrows() {
        let nonzero: Vec<usize> = (0..p).filter(|&i| problem.k[(row, i)] != 0.0).collect();
        if let [i] = nonzero[..] {
            if i >= inertial && problem.k[(row, i)] == 1.0 {
                description[i] = estimate.theta_b[row];
            }
        }
    }
    description
}

/// The full θ nearest the description whose base parameters are the least squares' (not
/// consistent in general).
pub(crate) fn least_squares_start(problem: &Problem<'_>) -> Option<Vec<f64>> {
    let p = problem.prior.len();
    let prior = DVector::from_column_slice(&problem.prior);
    let scaled_a = DMatrix::from_fn(problem.a.nrows(), p, |i, j| problem.a[(i, j)] * problem.scales[j]);
    let y = nearest_fit(&scaled_a, &(&problem.c - &problem.a * &prior), &DVector::zeros(p))?;
    Some(
        (0..p)
            .map(|i| problem.prior[i] + problem.scales[i] * y[i])
            .collect(),
    )
}

/// The description scaled body by body, the end-effector's body and the joint-level
/// parameters fitted.
fn scaled_description_start(problem: &Problem<'_>) -> Option<Vec<f64>> {
    // θ = B z: z = (one factor per body but the end-effector's, its ten parameters, the
    // joint-level parameters).
    let p = problem.prior.len();
    let inertial = PARAMETERS_PER_BODY * problem.bodies.len();
    let carrier = problem.model.end_effector_body();
    let bodies = problem.bodies.len();
    let columns = (bodies - 1) + PARAMETERS_PER_BODY + (p - inertial);
    let mut basis = DMatrix::zeros(p, columns);
    let mut z0 = DVector::zeros(columns);
    let mut column = 0;
    for b in (0..bodies).filter(|&b| b != carrier) {
        for i in PARAMETERS_PER_BODY * b..PARAMETERS_PER_BODY * (b + 1) {
            basis[(i, column)] = problem.prior[i];
        }
        z0[column] = 1.0;
        column += 1;
    }
    for i in (PARAMETERS_PER_BODY * carrier..PARAMETERS_PER_BODY * (carrier + 1)).chain(inertial..p) {
        // In the prior's scales, so the fit is not dominated by units.
        basis[(i, column)] = problem.scales[i];
        z0[column] = problem.prior[i] / problem.scales[i];
        column += 1;
    }
    let mut z = nearest_fit(&(&problem.a * &basis), &problem.c, &z0)?;
    // A body scaled to nothing or below has no consistent neighbour: keep a tenth of it.
    for factor in z.rows_mut(0, bodies - 1).iter_mut() {
        *factor = factor.max(0.1);
    }
    Some((&basis * z).iter().copied().collect())
}

/// The starting θs (not necessarily consistent: the estimate brings each inside first).
pub(crate) fn starts(problem: &Problem<'_>, estimate: &BaseEstimate) -> Vec<(ConsistentStart, Vec<f64>)> {
    let mut all = vec![(ConsistentStart::Description, description_start(problem, estimate))];
    if let Some(theta) = least_squares_start(problem) {
        all.push((ConsistentStart::LeastSquares, theta));
    }
    if let Some(theta) = scaled_description_start(problem) {
        all.push((ConsistentStart::ScaledDescription, theta));
    }
    all
}
