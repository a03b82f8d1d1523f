//! The consistent estimate's objective, as a least squares in the free numbers `φ`:
//!
//! ```text
//! ‖A θ(φ) − c‖²  +  λ ‖(θ(φ) − θ_prior) / scale‖²  +  λ ‖φ_bodies − φ_prior‖²
//! ```
//!
//! - Data: `‖A θ − c‖² = ‖R (K θ − θ̂_b)‖²`, the whitened misfit (`RᵀR` the least squares'
//!   information matrix, `K` the folding `θ_b = K θ`): the weighted residual increase, in
//!   units of σ². `R` counts no parameter as known better than a floor of its size
//!   ([`PRECISION_FLOOR`]): noise-free data would otherwise weigh the data 10³⁰ times the
//!   prior, and no solver resolves the prior's directions under that.
//! - Prior, with a tiny `λ` ([`PRIOR_WEIGHT`]): the description's values pin the directions the
//!   data cannot see (the full θ is not identifiable) and nothing else. On the bodies' free
//!   numbers too, so that an unseen direction does not drift to a body on the edge of the
//!   cone; not on the joint terms', whose logarithm has no sensible target for a description
//!   value of zero.
//! - Free numbers of one size: a body's are of order one by construction
//!   ([`crate::log_cholesky`]); a positive joint parameter is `e^u`; an offset is in units of
//!   its size (the description's, the least squares', at least 0.1 N·m).

use crate::least_squares::BaseEstimate;
use crate::levenberg_marquardt::{minimise, Minimum};
use crate::log_cholesky::BodyMap;
use dyngen_model::base_parameters::BaseParameterSet;
use dyngen_model::model::{JointTermKind, Model};
use dyngen_runtime::PARAMETERS_PER_BODY;
use nalgebra::{DMatrix, DVector};

/// Weight of the prior relative to one σ² of data misfit.
pub(crate) const PRIOR_WEIGHT: f64 = 1e-6;
/// No base parameter counts as known better than this fraction of its size (or of a
/// thousandth of the largest contribution to the torques, for one near zero).
pub(crate) const PRECISION_FLOOR: f64 = 1e-9;
/// A decrease of the objective (in units of σ² of data misfit) that changes no prediction.
const NEGLIGIBLE: f64 = 0.05;

/// The folding matrix `K` (`θ_b = K θ`), b × P.
pub(crate) fn folding_matrix(base: &BaseParameterSet) -> DMatrix<f64> {
    let mut k = DMatrix::zeros(base.count(), base.standard_count);
    for (row, terms) in base.terms.iter().enumerate() {
        for &(i, c) in terms {
            k[(row, i)] += c;
        }
    }
    k
}

/// How one joint-level parameter is made from its free number.
#[derive(Clone, Copy, Debug)]
enum TermMap {
    /// `θ = e^u`: positive.
    Positive,
    /// `θ = scale·u`: an offset, in units of its size.
    Linear(f64),
}

/// Typical size of each parameter, for the prior's weights: the prior value, or a floor per
/// kind of quantity (0.1 kg, 0.01 kg·m, 0.001 kg·m², 0.1 for joint parameters).
fn prior_scales(model: &Model, prior: &[f64]) -> Vec<f64> {
    (0..prior.len())
        .map(|i| {
            let floor = if i >= model.inertial_parameter_count() {
                0.1
            } else {
                match i % PARAMETERS_PER_BODY {
                    0 => 0.1,
                    1..=3 => 0.01,
                    _ => 0.001,
                }
            };
            prior[i].abs().max(floor)
        })
        .collect()
}

/// A body's length: the farthest of its centre of mass, its radius of gyration, the joints
/// it carries and the end-effector on it (at least 1 cm).
fn body_lengths(model: &Model) -> Vec<f64> {
    let mut lengths: Vec<f64> = model
        .bodies()
        .iter()
        .map(|b| {
            let i = &b.inertia;
            let gyration = if i.mass > 0.0 {
                (0.5 * i.inertia_com.trace().max(0.0) / i.mass).sqrt()
            } else {
                0.0
            };
            i.com.norm().max(gyration)
        })
        .collect();
    for joint in model.joints() {
        if let Some(p) = joint.parent {
            lengths[p] = lengths[p].max(joint.origin.translation.norm());
        }
    }
    let ee = model.end_effector();
    let body = model.end_effector_body();
    lengths[body] = lengths[body].max(ee.placement.translation.norm());
    lengths.iter().map(|l| l.max(0.01)).collect()
}

/// The whitened data term `(A, c)`, `‖A θ − c‖²`, of the least-squares estimate `theta_hat`
/// (its covariance in the column-scaled coordinates `θ_b / column_scale`), no parameter
/// counted as known better than `floor` of its size (or of a thousandth of the largest
/// contribution to the torques).
fn whitened(
    k: &DMatrix<f64>,
    theta_hat: &[f64],
    column_scale: &[f64],
    covariance: &DMatrix<f64>,
    floor: f64,
) -> (DMatrix<f64>, DVector<f64>) {
    let b = k.nrows();
    let x_hat: Vec<f64> = (0..b).map(|i| theta_hat[i] / column_scale[i]).collect();
    let largest = x_hat.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let floored = DMatrix::from_fn(b, b, |i, j| {
        let f = floor * x_hat[i].abs().max(1e-3 * largest);
        covariance[(i, j)] + if i == j { f * f } else { 0.0 }
    });
    let information = floored
        .cholesky()
        .map(|c| c.inverse())
        .unwrap_or_else(|| DMatrix::identity(b, b));
    let information = (&information + information.transpose()) * 0.5;
    let r_x = information
        .cholesky()
        .map(|c| c.l().transpose())
        .unwrap_or_else(|| DMatrix::identity(b, b));
    let r = DMatrix::from_fn(b, b, |i, j| r_x[(i, j)] / column_scale[j]);
    (&r * k, &r * DVector::from_column_slice(theta_hat))
}

/// The consistent-estimate problem: free numbers ↔ θ, the whitened data term and the prior.
#[derive(Clone)]
pub(crate) struct Problem<'m> {
    pub model: &'m Model,
    pub bodies: Vec<BodyMap>,
    terms: Vec<TermMap>,
    /// Whitened data term `‖A θ − c‖²`.
    pub a: DMatrix<f64>,
    pub c: DVector<f64>,
    pub k: DMatrix<f64>,
    /// The least squares: covariance in its column-scaled coordinates, estimate, scales.
    covariance: DMatrix<f64>,
    theta_hat: Vec<f64>,
    column_scale: Vec<f64>,
    pub prior: Vec<f64>,
    pub scales: Vec<f64>,
    pub phi_prior: Vec<f64>,
}

impl<'m> Problem<'m> {
    pub fn new(model: &'m Model, base: &BaseParameterSet, estimate: &BaseEstimate) -> Problem<'m> {
        let k = folding_matrix(base);
        let b = base.count();
        let covariance = estimate
            .information_scaled
            .clone()
            .cholesky()
            .map(|c| c.inverse())
            .unwrap_or_else(|| DMatrix::zeros(b, b));
        let (a, c) = whitened(
            &k,
            &estimate.theta_b,
            &estimate.scale,
            &covariance,
            PRECISION_FLOOR,
        );
        let prior = model.parameters();
        let scales = prior_scales(model, &prior);
        // An offset's free number is in units of its size: the description's, the least
        // squares' when the offset is a base parameter alone, at least 0.1 N·m.
        let standalone = |i: usize| {
            (0..b)
                .find(|&row| base.terms[row][..] == [(i, 1.0)])
                .map_or(0.0, |row| estimate.theta_b[row].abs())
        };
        let terms = (model.inertial_parameter_count()..model.parameter_count())
            .map(|i| match model.joint_term_of_column(i) {
                (_, JointTermKind::Offset) => TermMap::Linear(scales[i].max(standalone(i))),
                _ => TermMap::Positive,
            })
            .collect();
        let mut problem = Problem {
            model,
            bodies: body_lengths(model)
                .into_iter()
                .map(|length| BodyMap { length })
                .collect(),
            terms,
            a,
            c,
            k,
            covariance,
            theta_hat: estimate.theta_b.clone(),
            column_scale: estimate.scale.clone(),
            scales,
            phi_prior: Vec::new(),
            prior,
        };
        problem.phi_prior = problem.free_numbers(&problem.prior, None);
        problem
    }

    /// The same problem with the data counting no parameter as known better than `floor` of
    /// its size.
    pub fn with_precision_floor(&self, floor: f64) -> Problem<'m> {
        let mut problem = self.clone();
        (problem.a, problem.c) = whitened(
            &self.k,
            &self.theta_hat,
            &self.column_scale,
            &self.covariance,
            floor,
        );
        problem
    }

    fn inertial(&self) -> usize {
        PARAMETERS_PER_BODY * self.bodies.len()
    }

    /// θ of free numbers `phi`.
    pub fn theta(&self, phi: &[f64]) -> Vec<f64> {
        let mut theta = Vec::with_capacity(phi.len());
        for (b, map) in self.bodies.iter().enumerate() {
            theta.extend(map.parameters(&phi[PARAMETERS_PER_BODY * b..PARAMETERS_PER_BODY * (b + 1)]));
        }
        let first = self.inertial();
        theta.extend(self.terms.iter().enumerate().map(|(k, map)| match map {
            TermMap::Positive => phi[first + k].exp(),
            TermMap::Linear(scale) => scale * phi[first + k],
        }));
        theta
    }

    /// Free numbers of the consistent θ nearest `theta`: bodies brought inside the margin (a
    /// body with nothing positive takes `fallback`'s, the prior's, or is a small ball at its
    /// origin), a positive joint parameter at or below zero at a thousandth of `fallback`'s
    /// (at least 10⁻⁹).
    pub fn free_numbers(&self, theta: &[f64], fallback: Option<&[f64]>) -> Vec<f64> {
        let mut phi = Vec::with_capacity(theta.len());
        let masses: Vec<f64> = (0..self.bodies.len())
            .map(|b| theta[PARAMETERS_PER_BODY * b])
            .filter(|m| *m > 0.0)
            .collect();
        let typical_mass = if masses.is_empty() {
            1.0
        } else {
            masses.iter().sum::<f64>() / masses.len() as f64
        };
        for (b, map) in self.bodies.iter().enumerate() {
            let range = PARAMETERS_PER_BODY * b..PARAMETERS_PER_BODY * (b + 1);
            match (map.free_numbers(&theta[range.clone()]), fallback) {
                (Some(p), _) => phi.extend(p),
                (None, Some(f)) => phi.extend_from_slice(&f[range]),
                (None, None) => {
                    // A ball of a thousandth of the typical mass, a third of the body's length.
                    let mut p = [0.0; PARAMETERS_PER_BODY];
                    p[0] = 0.5 * (1e-3 * typical_mass).ln();
                    for d in &mut p[1..4] {
                        *d = (1.0f64 / 3.0).ln();
                    }
                    phi.extend(p);
                }
            }
        }
        let first = self.inertial();
        for (k, map) in self.terms.iter().enumerate() {
            let value = theta[first + k];
            phi.push(match map {
                TermMap::Positive => {
                    let floor = fallback.map_or(1e-9, |f| f[first + k].exp() * 1e-3).max(1e-9);
                    value.max(floor).ln()
                }
                TermMap::Linear(scale) => value / scale,
            });
        }
        phi
    }

    /// The residual `[A θ − c; √λ (θ − θ_prior)/scale; √λ (φ − φ_prior)]` and θ.
    fn residual(&self, phi: &[f64]) -> (DVector<f64>, Vec<f64>) {
        let theta = self.theta(phi);
        let (b, p) = (self.c.len(), phi.len());
        let mut r = DVector::zeros(b + 2 * p);
        let data = &self.a * DVector::from_column_slice(&theta) - &self.c;
        r.rows_mut(0, b).copy_from(&data);
        let w = PRIOR_WEIGHT.sqrt();
        for i in 0..p {
            r[b + i] = w * (theta[i] - self.prior[i]) / self.scales[i];
            if i < self.inertial() {
                r[b + p + i] = w * (phi[i] - self.phi_prior[i]);
            }
        }
        (r, theta)
    }

    /// `∂θ/∂φ`, block diagonal: a body's ten parameters depend on its ten free numbers, a
    /// joint parameter on its own.
    pub fn theta_jacobian(&self, phi: &[f64]) -> DMatrix<f64> {
        let p = phi.len();
        let mut d = DMatrix::zeros(p, p);
        for (body, map) in self.bodies.iter().enumerate() {
            let first = PARAMETERS_PER_BODY * body;
            let block = map.jacobian(&phi[first..first + PARAMETERS_PER_BODY]);
            for row in 0..PARAMETERS_PER_BODY {
                for col in 0..PARAMETERS_PER_BODY {
                    d[(first + row, first + col)] = block[(row, col)];
                }
            }
        }
        let first = self.inertial();
        for (k, map) in self.terms.iter().enumerate() {
            let i = first + k;
            d[(i, i)] = match map {
                TermMap::Positive => phi[i].exp(),
                TermMap::Linear(scale) => *scale,
            };
        }
        d
    }

    /// The residual's Jacobian by the free numbers: its first `b` rows are the whitened data
    /// term's, the rest the prior's.
    pub fn jacobian(&self, phi: &[f64]) -> DMatrix<f64> {
        let (b, p) = (self.c.len(), phi.len());
        let w = PRIOR_WEIGHT.sqrt();
        let mut jac = DMatrix::zeros(b + 2 * p, p);
        for (body, map) in self.bodies.iter().enumerate() {
            let first = PARAMETERS_PER_BODY * body;
            let d = map.jacobian(&phi[first..first + PARAMETERS_PER_BODY]);
            let block = self.a.columns(first, PARAMETERS_PER_BODY) * d;
            jac.view_mut((0, first), (b, PARAMETERS_PER_BODY))
                .copy_from(&block);
            for row in 0..PARAMETERS_PER_BODY {
                for col in 0..PARAMETERS_PER_BODY {
                    jac[(b + first + row, first + col)] = w * d[(row, col)] / self.scales[first + row];
                }
            }
        }
        let first = self.inertial();
        for (k, map) in self.terms.iter().enumerate() {
            let i = first + k;
            let d = match map {
                TermMap::Positive => phi[i].exp(),
                TermMap::Linear(scale) => *scale,
            };
            jac.view_mut((0, i), (b, 1)).copy_from(&(self.a.column(i) * d));
            jac[(b + i, i)] = w * d / self.scales[i];
        }
        for i in 0..self.inertial() {
            jac[(b + p + i, i)] = w;
        }
        jac
    }

    /// The consistent θ nearest `theta` (see [`Problem::free_numbers`]).
    pub fn consistent_point(&self, theta: &[f64]) -> Vec<f64> {
        self.theta(&self.free_numbers(theta, Some(&self.phi_prior)))
    }

    /// The free numbers minimising the objective from `phi` (see `levenberg_marquardt.rs`).
    pub fn minimise(&self, phi: Vec<f64>) -> Minimum {
        minimise(|x| self.residual(x).0, |x| self.jacobian(x), phi, NEGLIGIBLE)
    }

    /// Whitened data misfit of θ.
    pub fn misfit(&self, theta: &[f64]) -> f64 {
        (&self.a * DVector::from_column_slice(theta) - &self.c).norm_squared()
    }
}
