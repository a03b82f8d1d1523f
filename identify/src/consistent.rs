//! A physically consistent full parameter vector θ as compatible with the data as the least
//! squares allow.
//!
//! Constraints: every body is a real mass distribution, with the loader's margin
//! ([`crate::log_cholesky`]), and armature, viscous and Coulomb friction are positive. Offsets
//! are free.
//!
//! Objective: the whitened data misfit `‖R (θ_b(θ) − θ̂_b)‖²` (`RᵀR` the information matrix
//! of the least squares: the weighted residual increase, in units of σ²) plus
//! `λ (‖(θ − θ_prior)/scale‖² + ‖φ − φ_prior‖²)` with a tiny `λ` ([`PRIOR_WEIGHT`], `φ` the free
//! numbers): the description's values pin the directions the data cannot see (the full θ is
//! not identifiable) and nothing else. `R` counts no parameter as known better than
//! [`PRECISION_FLOOR`] of its size: noise-free data would otherwise weigh the data 10³⁰ times
//! the prior, and no solver resolves the prior's directions under that.
//!
//! Method: every value of the free numbers is a consistent robot, so the constraints hold
//! whatever the optimiser does, and the problem is an unconstrained least squares in them,
//! minimised by Levenberg–Marquardt with the analytic Jacobian, each step from the singular
//! value decomposition of the whole residual's Jacobian (the data and prior rows differ by
//! 10¹², beyond what normal equations keep) with Moré's column scaling. The free numbers are
//! not convex in θ, so the start matters: it runs from several ([`crate::starts`]) and keeps
//! the lowest objective. A consistent θ whose misfit is within the spread of a χ² with `b`
//! degrees of freedom ([`ConsistentEstimate::compatible`]) fits the data as well as the true
//! robot would.
//!
//! Why not a semidefinite program (e.g. `clarabel`): it is convex, but its PSD cones need a
//! LAPACK backend (a system library or a large build), and it returns points on the cone's
//! boundary to solver tolerance, which the loader may then reject. The free numbers need no
//! dependency and return bodies strictly inside the loader's margin.

use crate::least_squares::BaseEstimate;
use crate::levenberg_marquardt::minimise;
use crate::log_cholesky::{relative_margin, BodyMap};
use crate::starts::{starts, ConsistentStart};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::model::{JointTermKind, Model, PARAMS_PER_BODY};
use nalgebra::{DMatrix, DVector};

/// The precision floors of the continuation, before [`PRECISION_FLOOR`].
const CONTINUATION: [f64; 2] = [1e-3, 1e-6];
/// A decrease of the objective (in units of σ² of data misfit) that changes no prediction.
const NEGLIGIBLE: f64 = 0.05;
/// Weight of the prior relative to one standard deviation of data misfit.
pub(crate) const PRIOR_WEIGHT: f64 = 1e-6;
/// No base parameter counts as known better than this fraction of its size (or of a
/// thousandth of the largest contribution to the torques, for one near zero).
pub(crate) const PRECISION_FLOOR: f64 = 1e-9;

/// The consistent estimate.
#[derive(Clone, Debug)]
pub struct ConsistentEstimate {
    /// Full θ (as [`Model::parameters`]).
    pub theta: Vec<f64>,
    /// Its base parameters.
    pub theta_b: Vec<f64>,
    /// Whitened data misfit `‖R (θ_b − θ̂_b)‖²` (in units of σ²: below about `b`, the
    /// consistent estimate is as compatible with the data as the unconstrained one).
    pub misfit: f64,
    /// Levenberg–Marquardt steps from the start that was kept.
    pub iterations: usize,
    /// The start that was kept, and the misfit reached from every start tried.
    pub start: ConsistentStart,
    pub misfits: Vec<(ConsistentStart, f64)>,
    /// Whether the misfit is within what noise explains (`b + 4√(2b)`, the far tail of a χ²
    /// with `b` degrees of freedom): else no consistent robot fits the data as well as the
    /// least squares, and the data or the model (its joint terms, its kinematics) is off.
    pub compatible: bool,
}

/// The largest misfit noise explains for `b` base parameters (see
/// [`ConsistentEstimate::compatible`]).
pub(crate) fn misfit_bound(b: usize) -> f64 {
    b as f64 + 4.0 * (2.0 * b as f64).sqrt()
}

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
                match i % PARAMS_PER_BODY {
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
/// it carries and the end effector on it (at least 1 cm).
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
    lengths[ee.parent] = lengths[ee.parent].max(ee.placement.translation.norm());
    lengths.iter().map(|l| l.max(0.01)).collect()
}

/// The whitened data term `(A, c)`, `‖A θ − c‖²`, of the least squares `estimate` (its
/// covariance in column-scaled coordinates given), no parameter counted as known better than
/// `floor` of its size (or of a thousandth of the largest contribution to the torques).
fn whitened(
    k: &DMatrix<f64>,
    estimate: &BaseEstimate,
    covariance: &DMatrix<f64>,
    floor: f64,
) -> (DMatrix<f64>, DVector<f64>) {
    let b = k.nrows();
    // x = θ_b / scale are the least squares' column-scaled coordinates.
    let x_hat: Vec<f64> = (0..b).map(|i| estimate.theta_b[i] / estimate.scale[i]).collect();
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
    let r = DMatrix::from_fn(b, b, |i, j| r_x[(i, j)] / estimate.scale[j]);
    (&r * k, &r * DVector::from_column_slice(&estimate.theta_b))
}

/// The consistent-estimate problem: free numbers ↔ θ, the whitened data term and the prior.
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
        let (a, c) = whitened(&k, estimate, &covariance, PRECISION_FLOOR);
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
    fn with_precision_floor(&self, floor: f64) -> Problem<'m> {
        let estimate = BaseEstimate {
            theta_b: self.theta_hat.clone(),
            scale: self.column_scale.clone(),
            ..BaseEstimate::empty()
        };
        let (a, c) = whitened(&self.k, &estimate, &self.covariance, floor);
        Problem {
            model: self.model,
            bodies: self.bodies.clone(),
            terms: self.terms.clone(),
            a,
            c,
            k: self.k.clone(),
            covariance: self.covariance.clone(),
            theta_hat: self.theta_hat.clone(),
            column_scale: self.column_scale.clone(),
            prior: self.prior.clone(),
            scales: self.scales.clone(),
            phi_prior: self.phi_prior.clone(),
        }
    }

    fn inertial(&self) -> usize {
        PARAMS_PER_BODY * self.bodies.len()
    }

    /// θ of free numbers `phi`.
    pub fn theta(&self, phi: &[f64]) -> Vec<f64> {
        let mut theta = Vec::with_capacity(phi.len());
        for (b, map) in self.bodies.iter().enumerate() {
            theta.extend(map.parameters(&phi[PARAMS_PER_BODY * b..PARAMS_PER_BODY * (b + 1)]));
        }
        let first = self.inertial();
        theta.extend(self.terms.iter().enumerate().map(|(k, map)| match map {
            TermMap::Positive => phi[first + k].exp(),
            TermMap::Linear(scale) => scale * phi[first + k],
        }));
        theta
    }

    /// Free numbers of the consistent θ nearest `theta` (bodies brought inside the margin,
    /// positive parameters at least `floor` of their size). A body with nothing positive takes
    /// `fallback`'s (the prior's), or a small ball at its origin.
    pub fn free_numbers(&self, theta: &[f64], fallback: Option<&[f64]>) -> Vec<f64> {
        let mut phi = Vec::with_capacity(theta.len());
        let masses: Vec<f64> = (0..self.bodies.len())
            .map(|b| theta[PARAMS_PER_BODY * b])
            .filter(|m| *m > 0.0)
            .collect();
        let typical_mass = if masses.is_empty() {
            1.0
        } else {
            masses.iter().sum::<f64>() / masses.len() as f64
        };
        for (b, map) in self.bodies.iter().enumerate() {
            let range = PARAMS_PER_BODY * b..PARAMS_PER_BODY * (b + 1);
            match (map.free_numbers(&theta[range.clone()]), fallback) {
                (Some(p), _) => phi.extend(p),
                (None, Some(f)) => phi.extend_from_slice(&f[range]),
                (None, None) => {
                    // A ball of a thousandth of the typical mass, a third of the body's length.
                    let mut p = [0.0; PARAMS_PER_BODY];
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

    /// The residual's Jacobian by the free numbers.
    fn jacobian(&self, phi: &[f64]) -> DMatrix<f64> {
        let (b, p) = (self.c.len(), phi.len());
        let w = PRIOR_WEIGHT.sqrt();
        let mut jac = DMatrix::zeros(b + 2 * p, p);
        for (body, map) in self.bodies.iter().enumerate() {
            let first = PARAMS_PER_BODY * body;
            let d = map.jacobian(&phi[first..first + PARAMS_PER_BODY]);
            let block = self.a.columns(first, PARAMS_PER_BODY) * d;
            jac.view_mut((0, first), (b, PARAMS_PER_BODY)).copy_from(&block);
            for row in 0..PARAMS_PER_BODY {
                for col in 0..PARAMS_PER_BODY {
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
    fn minimise(&self, phi: Vec<f64>) -> crate::levenberg_marquardt::Minimum {
        minimise(|x| self.residual(x).0, |x| self.jacobian(x), phi, NEGLIGIBLE)
    }

    /// Whitened data misfit of θ.
    pub fn misfit(&self, theta: &[f64]) -> f64 {
        (&self.a * DVector::from_column_slice(theta) - &self.c).norm_squared()
    }
}

/// The consistent θ closest (in whitened data misfit) to the least-squares `estimate`, with
/// the description's θ as the tie-breaking prior, from the best of several starts; see the
/// module docs.
pub(crate) fn consistent_estimate(problem: &Problem<'_>, estimate: &BaseEstimate) -> ConsistentEstimate {
    // Continuation: the data counted first as known to 10⁻³, then 10⁻⁶ of each parameter, so
    // that a start far off first finds the valley of the data before its walls steepen
    // (noise-free data weighs the data 10¹³ times the prior); noisy data is unchanged by it.
    let stages: Vec<Problem<'_>> = CONTINUATION
        .iter()
        .filter(|&&floor| floor > PRECISION_FLOOR)
        .map(|&floor| problem.with_precision_floor(floor))
        .collect();
    let mut best: Option<(f64, Vec<f64>, usize, ConsistentStart)> = None;
    let mut misfits = Vec::new();
    for (start, theta) in starts(problem, estimate) {
        let mut phi = problem.free_numbers(&theta, Some(&problem.phi_prior));
        let mut iterations = 0;
        for stage in &stages {
            let m = stage.minimise(phi);
            phi = m.x;
            iterations += m.iterations;
        }
        let m = problem.minimise(phi);
        let (phi, cost) = (m.x, m.cost);
        iterations += m.iterations;
        let theta = problem.theta(&phi);
        misfits.push((start, problem.misfit(&theta)));
        if best.as_ref().is_none_or(|b| cost < b.0) {
            best = Some((cost, theta, iterations, start));
        }
    }
    let (_, theta, iterations, start) = best.expect("at least one start");
    let theta_b: Vec<f64> = (&problem.k * DVector::from_column_slice(&theta))
        .iter()
        .copied()
        .collect();
    let misfit = problem.misfit(&theta);
    ConsistentEstimate {
        theta,
        theta_b,
        misfit,
        iterations,
        start,
        misfits,
        compatible: misfit <= misfit_bound(problem.c.len()),
    }
}

/// Smallest eigenvalue of each body's pseudo-inertia in `theta`, relative to its largest
/// (non-negative for a consistent θ).
pub fn pseudo_inertia_margins(model: &Model, theta: &[f64]) -> Vec<f64> {
    (0..model.bodies().len())
        .map(|b| {
            let j = crate::log_cholesky::pseudo_inertia(&theta[PARAMS_PER_BODY * b..PARAMS_PER_BODY * (b + 1)]);
            let e = j.symmetric_eigenvalues();
            let (lo, hi) = (e.min(), e.max());
            if hi > 0.0 {
                lo / hi
            } else {
                lo
            }
        })
        .collect()
}

/// Each body's relative margin `min σ(Σ_c) / tr(Σ_c)` in `theta` (at least the consistent
/// estimate's margin, 10⁻⁵, for every body it makes).
pub(crate) fn body_margins(model: &Model, theta: &[f64]) -> Vec<f64> {
    (0..model.bodies().len())
        .map(|b| relative_margin(&theta[PARAMS_PER_BODY * b..PARAMS_PER_BODY * (b + 1)]))
        .collect()
}
