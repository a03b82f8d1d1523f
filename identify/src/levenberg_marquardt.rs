//! Levenberg–Marquardt for a nonlinear least squares `min ‖r(x)‖²` whose rows differ by many
//! orders of magnitude: the consistent estimate's data rows weigh up to 10¹² times its prior
//! rows, and the prior's directions still have to move.
//!
//! - Each step solves the damped Gauss–Newton system from one singular value decomposition of
//!   the Jacobian in Moré's scaled coordinates (each unknown in units of the largest norm its
//!   column has had), shared by every damping tried. Normal equations would square the
//!   spread of the rows, 10²⁴, beyond double precision.
//! - The damping is chosen by a trust region on the unknowns themselves (the largest change of
//!   one in one step): the caller's unknowns are of order one, so a radius of one means the
//!   same on every one of them. The radius grows while the linear model predicts the
//!   decrease well and shrinks when it does not.
//! - It stops when even the undamped step would gain almost nothing, or when the last
//!   [`STALL_STEPS`] steps together gained less than what the caller calls negligible, or
//!   after [`MAX_ITERATIONS`] steps.

use nalgebra::{DMatrix, DVector};

/// Stop when the undamped step would lower the objective by less than this fraction of it…
const STOP_DECREASE: f64 = 1e-10;
/// … or by less than this much (absolute).
const STOP_ABSOLUTE: f64 = 1e-9;
/// … or when the last [`STALL_STEPS`] steps together lowered it by less than the caller's
/// negligible decrease. Far from a minimum the steps gain orders of magnitude, near one the
/// Gauss–Newton steps converge fast; what is left crawling is a tie-break the data cannot see
/// (an armature against the link inertia it is folded with, going to zero along its
/// logarithm), not worth hundreds of steps.
const STALL_STEPS: usize = 20;
const MAX_ITERATIONS: usize = 200;
/// Trust radii tried per step before giving up.
const MAX_TRIALS: usize = 60;
/// The first trust radius and the largest.
const FIRST_RADIUS: f64 = 1.0;
const MAX_RADIUS: f64 = 1e6;
/// Singular values below this fraction of the largest are rounding: their directions get no
/// step and do not count in the stopping test.
const SINGULAR_FLOOR: f64 = 1e-14;

/// Where the minimisation ended.
pub(crate) struct Minimum {
    pub x: Vec<f64>,
    /// `‖r(x)‖²`.
    pub cost: f64,
    pub iterations: usize,
}

/// Minimises `‖residual(x)‖²` from `x`; `jacobian(x)` is the residual's Jacobian; a decrease
/// below `negligible` changes nothing the caller cares about.
pub(crate) fn minimise(
    residual: impl Fn(&[f64]) -> DVector<f64>,
    jacobian: impl Fn(&[f64]) -> DMatrix<f64>,
    mut x: Vec<f64>,
    negligible: f64,
) -> Minimum {
    let p = x.len();
    let mut r = residual(&x);
    let mut cost = r.norm_squared();
    if !cost.is_finite() {
        return Minimum {
            x,
            cost: f64::INFINITY,
            iterations: 0,
        };
    }
    let mut column_scale = vec![0.0f64; p];
    let mut radius = FIRST_RADIUS;
    let mut history = vec![cost];
    let mut iterations = 0;
    while iterations < MAX_ITERATIONS {
        let jac = jacobian(&x);
        for (i, s) in column_scale.iter_mut().enumerate() {
            *s = s.max(jac.column(i).norm()).max(f64::MIN_POSITIVE);
        }
        let scaled = DMatrix::from_fn(jac.nrows(), p, |i, j| jac[(i, j)] / column_scale[j]);
        let svd = scaled.svd(true, true);
        let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
            break;
        };
        let sigma = svd.singular_values;
        let largest = sigma.max();
        let ut_r = u.tr_mul(&r);
        let resolved = SINGULAR_FLOOR * largest;
        let gauss_newton_gain: f64 = (0..sigma.len())
            .filter(|&i| sigma[i] > resolved)
            .map(|i| ut_r[i] * ut_r[i])
            .sum();
        if gauss_newton_gain.is_nan() || gauss_newton_gain <= STOP_DECREASE * cost + STOP_ABSOLUTE {
            break;
        }
        iterations += 1;
        // The step of a damping (in the unknowns' own units), its coefficients on the singular
        // vectors, and its length (largest change of one unknown).
        let step_for = |damping: f64| {
            let coefficients = DVector::from_fn(sigma.len(), |i, _| {
                -sigma[i] / (sigma[i] * sigma[i] + damping) * ut_r[i]
            });
            let step: Vec<f64> = v_t
                .tr_mul(&coefficients)
                .iter()
                .zip(&column_scale)
                .map(|(s, c)| s / c)
                .collect();
            let length = step.iter().map(|s| s.abs()).fold(0.0, f64::max);
            (step, coefficients, length)
        };
        let mut accepted = false;
        for _ in 0..MAX_TRIALS {
            // The least damping whose step stays within the trust radius (the step's length
            // falls as the damping grows: bisection on its logarithm).
            let (mut step, mut coefficients, mut length) = step_for(resolved * resolved);
            if length.is_nan() || length > radius {
                let (mut lo, mut hi) = (
                    (resolved * resolved).max(f64::MIN_POSITIVE).ln(),
                    (1e30 * largest * largest).ln(),
                );
                for _ in 0..64 {
                    let mid = 0.5 * (lo + hi);
                    let candidate = step_for(mid.exp());
                    if candidate.2 <= radius {
                        hi = mid;
                        (step, coefficients, length) = candidate;
                    } else {
                        lo = mid;
                    }
                    if hi - lo < 0.1 && length <= radius {
                        break;
                    }
                }
                if length.is_nan() || length > radius {
                    break;
                }
            }
            let fitted = sigma.component_mul(&coefficients);
            let predicted = -(2.0 * ut_r.dot(&fitted) + fitted.norm_squared());
            let trial: Vec<f64> = x.iter().zip(&step).map(|(a, s)| a + s).collect();
            let rt = residual(&trial);
            let ct = rt.norm_squared();
            let ratio = (cost - ct) / predicted;
            if ratio.is_nan() || ratio < 0.25 {
                radius = 0.25 * length.min(radius);
            } else if ratio > 0.75 && length >= 0.5 * radius {
                radius = (2.0 * radius).min(MAX_RADIUS);
            }
            if ct < cost {
                x = trial;
                r = rt;
                cost = ct;
                accepted = true;
                break;
            }
            if radius < 1e-12 {
                break;
            }
        }
        if !accepted {
            break;
        }
        history.push(cost);
        if history.len() > STALL_STEPS && history[history.len() - 1 - STALL_STEPS] - cost < negligible {
            break;
        }
    }
    Minimum { x, cost, iterations }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rows 10⁹ apart (normal equations would square that past double precision): both
    /// directions found, the weak one too.
    #[test]
    fn resolves_rows_of_very_different_weight() {
        let residual = |x: &[f64]| DVector::from_vec(vec![1e6 * (x[0] + x[1] - 2.0), 1e-3 * (x[0] - x[1])]);
        let jacobian = |_: &[f64]| DMatrix::from_row_slice(2, 2, &[1e6, 1e6, 1e-3, -1e-3]);
        let m = minimise(residual, jacobian, vec![5.0, -7.0], 0.0);
        assert!(
            (m.x[0] - 1.0).abs() < 1e-8 && (m.x[1] - 1.0).abs() < 1e-8,
            "{:?}",
            m.x
        );
    }

    /// Rosenbrock's valley as a least squares: the minimum (1, 1) from the classic start.
    #[test]
    fn follows_a_curved_valley() {
        let residual = |x: &[f64]| DVector::from_vec(vec![10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]]);
        let jacobian = |x: &[f64]| DMatrix::from_row_slice(2, 2, &[-20.0 * x[0], 10.0, -1.0, 0.0]);
        let m = minimise(residual, jacobian, vec![-1.2, 1.0], 0.0);
        assert!(
            (m.x[0] - 1.0).abs() < 1e-8 && (m.x[1] - 1.0).abs() < 1e-8,
            "{:?} after {}",
            m.x,
            m.iterations
        );
    }
}
