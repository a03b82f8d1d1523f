//! A physically consistent full parameter vector θ as compatible with the data as the least
//! squares allow.
//!
//! Constraints: every body is a real mass distribution, with the loader's margin
//! ([`crate::log_cholesky`]), and armature, viscous and Coulomb friction are positive. Offsets
//! are free.
//!
//! Objective ([`crate::objective`]): the whitened data misfit `‖R (θ_b(θ) − θ̂_b)‖²` (in units
//! of σ²) plus a tiny prior towards the description, which only pins what the data cannot see.
//!
//! Method: every value of the free numbers is a consistent robot with the loader's margin, so
//! the problem is an unconstrained least squares in them, minimised by Levenberg–Marquardt
//! ([`crate::levenberg_marquardt`]) with the analytic Jacobian. Two things make it reach the
//! data's minimum rather than stop far from it:
//! - Free numbers of one size on every body (a body's length scales its centre of mass and
//!   inertia), so the steps and the trust region mean the same on a wrist as on a 2 m arm.
//! - Several starts ([`crate::starts`]), since the free numbers are not convex in θ: the
//!   description, the least squares made consistent, the description scaled with a payload
//!   fitted; the lowest objective is kept. And from each, a continuation: the data counted
//!   first as known to 10⁻³, then 10⁻⁶ of each parameter, then to the floor, so that a start
//!   far off finds the valley of the data before its walls steepen (noise-free data weighs
//!   the data 10¹³ times the prior). Noisy data is unchanged by it.
//!
//! The description is the prior and the source of the starts; a description with bodies that
//! no real body can be (dyngen loads them as written, with a warning) has them replaced by
//! their nearest physical inertia first (`physical_start`).
//!
//! A consistent θ whose misfit is within the spread of a χ² with `b` degrees of freedom
//! ([`ConsistentEstimate::compatible`]) fits the data as well as the true robot would; noise-free
//! data that a consistent robot made gives that robot's base parameters.
//!
//! How sure it is: the covariance of its base parameters by linearisation at the optimum
//! ([`ConsistentEstimate::covariance`]), the Gauss–Newton map from the whitened data to the
//! free numbers carried to `θ_b`. Where no constraint binds it is the least squares'; a
//! parameter the constraints hold (a friction pressed to zero) gets next to none. Linear: when
//! a parameter's σ is of the size of its distance to a constraint, the estimates of many data
//! sets spread less than it says (the constraint truncates them).
//!
//! Why not a semidefinite program (e.g. `clarabel`): it is convex, but its PSD cones need a
//! LAPACK backend (a system library or a large build), and it returns points on the cone's
//! boundary to solver tolerance, which the loader may then reject. The free numbers need no
//! dependency and return bodies strictly inside the loader's margin.

use crate::least_squares::BaseEstimate;
use crate::log_cholesky::relative_margin;
use crate::objective::{Problem, PRECISION_FLOOR};
use crate::starts::{starts, ConsistentStart};
use dyngen_model::model::Model;
use dyngen_runtime::PARAMETERS_PER_BODY;
use nalgebra::{DMatrix, DVector};

/// The precision floors of the continuation, before the objective's own
/// ([`PRECISION_FLOOR`]).
const CONTINUATION: [f64; 2] = [1e-3, 1e-6];

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
    /// Standard deviation of each of its base parameters [`ConsistentEstimate::theta_b`], by
    /// linearisation at the optimum (see [`ConsistentEstimate::covariance`]).
    pub std_dev: Vec<f64>,
    /// The covariance of [`ConsistentEstimate::theta_b`] by linearisation at the optimum: the
    /// Gauss–Newton map `δφ = (JᵀJ)⁻¹ J_dᵀ e` from a whitened data error `e` (covariance `I`)
    /// to the free numbers (`J` the Jacobian of the whole objective, `J_d` its data rows),
    /// carried to `θ_b = K θ(φ)` by `K ∂θ/∂φ`. Where no constraint binds, it is the least
    /// squares' covariance; a parameter pressed against a constraint (a friction at zero, a
    /// body at the edge of physical validity) varies less, and its σ says so.
    pub covariance: DMatrix<f64>,
    /// Whether the misfit is within what noise explains (`b + 4√(2b)`, the far tail of a χ²
    /// with `b` degrees of freedom): else no consistent robot fits the data as well as the
    /// least squares, and the data or the model (its joint terms, its kinematics) is off.
    pub compatible: bool,
}

impl ConsistentEstimate {
    /// Relative standard deviation `σ/|θ_b|` of its base parameter `k` (∞ for θ_b = 0).
    pub fn relative_std_dev(&self, k: usize) -> f64 {
        self.std_dev[k] / self.theta_b[k].abs()
    }
}

/// The largest misfit noise explains for `b` base parameters (see
/// [`ConsistentEstimate::compatible`]).
pub(crate) fn misfit_bound(b: usize) -> f64 {
    b as f64 + 4.0 * (2.0 * b as f64).sqrt()
}

/// The consistent θ closest (in whitened data misfit) to the least-squares `estimate`, with
/// the description's θ as the tie-breaking prior, from the best of several starts; see the
/// module docs.
pub(crate) fn consistent_estimate(problem: &Problem<'_>, estimate: &BaseEstimate) -> ConsistentEstimate {
    // The continuation (module docs).
    let stages: Vec<Problem<'_>> = CONTINUATION
        .iter()
        .filter(|&&floor| floor > PRECISION_FLOOR)
        .map(|&floor| problem.with_precision_floor(floor))
        .collect();
    // The best end so far: cost, θ, free numbers, iterations, start.
    type End = (f64, Vec<f64>, Vec<f64>, usize, ConsistentStart);
    let mut best: Option<End> = None;
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
            best = Some((cost, theta, phi, iterations, start));
        }
    }
    let (_, theta, phi, iterations, start) = best.expect("at least one start");
    let covariance = linearised_covariance(problem, &phi);
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
        std_dev: (0..covariance.nrows())
            .map(|k| covariance[(k, k)].max(0.0).sqrt())
            .collect(),
        covariance,
        compatible: misfit <= misfit_bound(problem.c.len()),
    }
}

/// Singular values of the objective's Jacobian below this fraction of the largest carry no
/// information: their directions get no variance.
const SINGULAR_FLOOR: f64 = 1e-14;

/// The covariance of the consistent estimate's base parameters by linearisation at the free
/// numbers `phi` (see [`ConsistentEstimate::covariance`]). `(JᵀJ)⁻¹ J_dᵀ` is the data
/// columns of the pseudo-inverse `J⁺`, computed from a singular value decomposition of `J`:
/// the data rows weigh up to 10¹² times the prior's, which `JᵀJ` would square past double
/// precision. The free numbers are of one size by construction (a unit change of one is a
/// change of its body or term by a factor of order e), so `J` is not rescaled: a direction
/// in which a unit change moves the data less than the prior does (a friction pressed to
/// zero, `θ = e^u` with `u` far below zero; a body on the edge of validity) gets the prior's
/// small variance, and through `∂θ/∂φ ≈ 0` next to none in `θ_b`.
fn linearised_covariance(problem: &Problem<'_>, phi: &[f64]) -> DMatrix<f64> {
    let b = problem.c.len();
    let jacobian = problem.jacobian(phi);
    let p = jacobian.ncols();
    let svd = jacobian.svd(true, true);
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        return DMatrix::from_element(b, b, f64::NAN);
    };
    let sigma = &svd.singular_values;
    let resolved = SINGULAR_FLOOR * sigma.max();
    // δφ = V Σ⁻¹ U_dᵀ e, U_d the data rows of U.
    let mut map = DMatrix::zeros(p, b);
    for k in (0..sigma.len()).filter(|&k| sigma[k] > resolved) {
        let v = v_t.row(k);
        let u_d = u.view((0, k), (b, 1));
        for i in 0..p {
            let vi = v[i] / sigma[k];
            for j in 0..b {
                map[(i, j)] += vi * u_d[j];
            }
        }
    }
    let to_base = &problem.k * problem.theta_jacobian(phi) * map;
    &to_base * to_base.transpose()
}

/// Smallest eigenvalue of each body's pseudo-inertia in `theta`, relative to its largest
/// (non-negative for a consistent θ).
pub fn pseudo_inertia_margins(model: &Model, theta: &[f64]) -> Vec<f64> {
    (0..model.bodies().len())
        .map(|b| {
            let j = crate::log_cholesky::pseudo_inertia(
                &theta[PARAMETERS_PER_BODY * b..PARAMETERS_PER_BODY * (b + 1)],
            );
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
        .map(|b| relative_margin(&theta[PARAMETERS_PER_BODY * b..PARAMETERS_PER_BODY * (b + 1)]))
        .collect()
}
