//! A physically consistent full parameter vector θ near the least-squares estimate.
//!
//! Constraints: every body's pseudo-inertia `J = [[Σ, h], [hᵀ, m]]` (`Σ = ½ tr(I)·1 − I`,
//! `h = m c`, `I` about the body origin) is positive definite — the condition for a real mass
//! distribution (Wensing, Kim & Slotine 2017) — and armature, viscous and Coulomb friction are
//! positive. Offsets are free.
//!
//! Method: the log-Cholesky parameterisation (Rucker & Wensing 2022). Each body is ten free
//! numbers `(α, d₁, d₂, d₃, s₁₂, s₂₃, s₁₃, t₁, t₂, t₃)` with
//! `J = U Uᵀ`, `U = e^α [[e^{d₁}, s₁₂, s₁₃, t₁], [0, e^{d₂}, s₂₃, t₂], [0, 0, e^{d₃}, t₃], [0, 0, 0, 1]]`,
//! and each positive joint parameter is `e^u`: every value of the free numbers is a
//! consistent robot, so the constraints hold by construction, to rounding error, whatever the
//! optimiser does. The objective is the data misfit `‖R (θ_b(θ) − θ̂_b)‖²` (`RᵀR` the
//! information matrix of the least squares, so this is the weighted residual increase up to
//! a constant) plus `λ (‖(θ − θ_prior)/scale‖² + ‖φ − φ_prior‖²)` with a tiny `λ` (`φ` the
//! free numbers): the description's values pin the directions the data cannot see (the full
//! θ is not identifiable) and keep bodies away from the singular boundary, and nothing else.
//! Minimised by Levenberg–Marquardt with forward-difference Jacobians (a few hundred free
//! numbers, cheap residuals: the data enters only through `R`).
//!
//! Why not a semidefinite program (e.g. `clarabel`): it is convex, but its PSD cones need a
//! LAPACK backend (a system library or a large build), and it returns points on the cone's
//! boundary to solver tolerance, which the loader may then reject (a singular inertia with
//! mass). Log-Cholesky needs no dependency and returns strictly consistent bodies; its
//! non-convexity is benign here because it starts at the description's consistent values and
//! the data term is a positive definite quadratic in the identifiable directions. (A
//! description that is not physical is repaired before it gets here: `physical_start`.)

use crate::least_squares::BaseEstimate;
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::model::{JointTermKind, Model, PARAMS_PER_BODY};
use nalgebra::{DMatrix, DVector, Matrix3, Matrix4, Vector3};

/// Weight of the prior relative to one standard deviation of data misfit.
pub(crate) const PRIOR_WEIGHT: f64 = 1e-6;
/// Levenberg–Marquardt stops when a step lowers the cost by less than this fraction, or after
/// [`MAX_ITERATIONS`]: the cost is in units of σ², so 1e-7 of it is far below what matters.
const STOP_DECREASE: f64 = 1e-7;
const MAX_ITERATIONS: usize = 500;
/// The smallest part of a body's pseudo-inertia kept at the start (regularises massless
/// bodies of the description: log-Cholesky needs a positive definite start).
const START_FLOOR: f64 = 1e-6;

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
    pub iterations: usize,
}

/// The pseudo-inertia of one body's ten parameters `[m, mc, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`.
pub(crate) fn pseudo_inertia(p: &[f64]) -> Matrix4<f64> {
    let inertia = Matrix3::new(p[4], p[5], p[7], p[5], p[6], p[8], p[7], p[8], p[9]);
    let sigma = Matrix3::identity() * (0.5 * inertia.trace()) - inertia;
    let mut j = Matrix4::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).copy_from(&sigma);
    j.fixed_view_mut::<3, 1>(0, 3)
        .copy_from(&Vector3::new(p[1], p[2], p[3]));
    j.fixed_view_mut::<1, 3>(3, 0)
        .copy_from(&Vector3::new(p[1], p[2], p[3]).transpose());
    j[(3, 3)] = p[0];
    j
}

/// The ten parameters of a pseudo-inertia.
fn parameters_of(j: &Matrix4<f64>) -> [f64; 10] {
    let sigma = j.fixed_view::<3, 3>(0, 0).into_owned();
    let inertia = Matrix3::identity() * sigma.trace() - sigma;
    [
        j[(3, 3)],
        j[(0, 3)],
        j[(1, 3)],
        j[(2, 3)],
        inertia[(0, 0)],
        inertia[(0, 1)],
        inertia[(1, 1)],
        inertia[(0, 2)],
        inertia[(1, 2)],
        inertia[(2, 2)],
    ]
}

fn upper_factor(phi: &[f64]) -> Matrix4<f64> {
    let [alpha, d1, d2, d3, s12, s23, s13, t1, t2, t3] = std::array::from_fn(|k| phi[k]);
    Matrix4::new(
        d1.exp(),
        s12,
        s13,
        t1, //
        0.0,
        d2.exp(),
        s23,
        t2, //
        0.0,
        0.0,
        d3.exp(),
        t3, //
        0.0,
        0.0,
        0.0,
        1.0,
    ) * alpha.exp()
}

/// Log-Cholesky coordinates of a positive definite pseudo-inertia.
fn log_cholesky(j: &Matrix4<f64>) -> [f64; 10] {
    // J = U Uᵀ with U upper triangular: the Cholesky factor of J with rows and columns reversed.
    let p = Matrix4::from_fn(|r, c| j[(3 - r, 3 - c)]);
    let l = p.cholesky().map(|c| c.l()).unwrap_or_else(Matrix4::identity);
    let u = Matrix4::from_fn(|r, c| l[(3 - r, 3 - c)]);
    let e = u[(3, 3)];
    [
        e.ln(),
        (u[(0, 0)] / e).ln(),
        (u[(1, 1)] / e).ln(),
        (u[(2, 2)] / e).ln(),
        u[(0, 1)] / e,
        u[(1, 2)] / e,
        u[(0, 2)] / e,
        u[(0, 3)] / e,
        u[(1, 3)] / e,
        u[(2, 3)] / e,
    ]
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

/// Free numbers ↔ θ for one model.
struct Layout<'m> {
    model: &'m Model,
}

impl Layout<'_> {
    fn theta(&self, phi: &[f64]) -> Vec<f64> {
        let n = self.model.dof();
        let mut theta = Vec::with_capacity(self.model.parameter_count());
        for b in 0..n {
            let u = upper_factor(&phi[PARAMS_PER_BODY * b..PARAMS_PER_BODY * (b + 1)]);
            theta.extend(parameters_of(&(u * u.transpose())));
        }
        for j in 0..n {
            for &kind in &self.model.joint_terms().kinds {
                let i = self
                    .model
                    .joint_term_index(j, kind)
                    .expect("a column of the model");
                theta.push(match kind {
                    JointTermKind::Offset => phi[i],
                    _ => phi[i].exp(),
                });
            }
        }
        theta
    }

    fn phi(&self, theta: &[f64]) -> Vec<f64> {
        let n = self.model.dof();
        let mut phi = Vec::with_capacity(theta.len());
        for b in 0..n {
            let p = &theta[PARAMS_PER_BODY * b..PARAMS_PER_BODY * (b + 1)];
            let j = pseudo_inertia(p);
            let floor = START_FLOOR * (1.0 + j.trace());
            phi.extend(log_cholesky(&(j + Matrix4::identity() * floor)));
        }
        for j in 0..n {
            for &kind in &self.model.joint_terms().kinds {
                let i = self
                    .model
                    .joint_term_index(j, kind)
                    .expect("a column of the model");
                phi.push(match kind {
                    JointTermKind::Offset => theta[i],
                    _ => theta[i].max(START_FLOOR).ln(),
                });
            }
        }
        phi
    }
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

/// The consistent θ closest (in whitened data misfit) to the least-squares `estimate`, with
/// `model`'s θ as the start and tie-breaking prior; see the module docs. `model`'s bodies must
/// be physical (a pseudo-inertia that is not positive semi-definite has no log-Cholesky
/// coordinates).
pub(crate) fn consistent_estimate(
    model: &Model,
    base: &BaseParameterSet,
    estimate: &BaseEstimate,
) -> ConsistentEstimate {
    let k = folding_matrix(base);
    let b = base.count();
    // R with RᵀR = information in θ_b units: information_scaled is in x = θ_b / scale.
    let r_scaled = estimate
        .information_scaled
        .clone()
        .cholesky()
        .map(|c| c.l().transpose())
        .unwrap_or_else(|| DMatrix::identity(b, b));
    let r = DMatrix::from_fn(b, b, |i, j| r_scaled[(i, j)] / estimate.scale[j]);
    let theta_hat = DVector::from_vec(estimate.theta_b.clone());
    let prior = model.parameters();
    let scales = prior_scales(model, &prior);
    let layout = Layout { model };
    // The prior also acts on the free numbers themselves: directions the data cannot see
    // would otherwise let a log-Cholesky diagonal drift towards −∞ (a body that tends to a
    // singular inertia changes θ less and less, so θ's prior alone does not stop it).
    let phi_prior = layout.phi(&prior);
    let p = prior.len();
    // The data residual is `A θ(φ) − c` with `A = R K`; `θ(φ)` is block diagonal in φ (a
    // body's ten numbers make its ten parameters; a joint parameter its own), so the
    // Jacobian is `A · ∂θ/∂φ` with a block-diagonal `∂θ/∂φ` taken by differences per block.
    let a_data = &r * &k;
    let c_data = &r * &theta_hat;
    let gram = a_data.tr_mul(&a_data);
    let blocks: Vec<(usize, usize)> = (0..model.dof())
        .map(|b| (PARAMS_PER_BODY * b, PARAMS_PER_BODY))
        .chain((model.inertial_parameter_count()..p).map(|i| (i, 1)))
        .collect();
    let cost_of = |phi: &[f64]| -> (f64, Vec<f64>) {
        let theta = layout.theta(phi);
        let data = &a_data * DVector::from_column_slice(&theta) - &c_data;
        let mut cost = data.norm_squared();
        for i in 0..p {
            cost += PRIOR_WEIGHT
                * (((theta[i] - prior[i]) / scales[i]).powi(2) + (phi[i] - phi_prior[i]).powi(2));
        }
        (cost, theta)
    };
    // Start: the prior, with joint parameters that stand alone as base parameters taken
    // from the least squares (where they are clearly determined).
    let mut start = prior.clone();
    for (row, terms) in base.terms.iter().enumerate() {
        if let [(i, c)] = terms[..] {
            if i >= model.inertial_parameter_count() && c == 1.0 {
                start[i] = estimate.theta_b[row];
            }
        }
    }
    let mut phi = layout.phi(&start);
    let (mut cost, mut theta) = cost_of(&phi);
    let mut mu = 1e-3;
    let mut iterations = 0;
    for it in 0..MAX_ITERATIONS {
        iterations = it + 1;
        // ∂θ/∂φ, block by block.
        let mut d = DMatrix::zeros(p, p);
        for &(first, len) in &blocks {
            for i in first..first + len {
                let h = 1e-7 * (1.0 + phi[i].abs());
                let mut q = phi.clone();
                q[i] += h;
                let shifted = layout.theta(&q);
                for row in first..first + len {
                    d[(row, i)] = (shifted[row] - theta[row]) / h;
                }
            }
        }
        let data = &a_data * DVector::from_column_slice(&theta) - &c_data;
        // Gradient and Gauss–Newton matrix of the cost (data + the two priors).
        let mut g = d.tr_mul(&a_data.tr_mul(&data));
        let mut jtj = d.tr_mul(&(&gram * &d));
        for i in 0..p {
            let w = PRIOR_WEIGHT / (scales[i] * scales[i]);
            // θ-prior: Σ_i w (θ_i − prior_i)², gradient through column i of ∂θ/∂φ (row i).
            let row = d.row(i).into_owned();
            g += row.transpose() * (w * (theta[i] - prior[i]));
            jtj += row.transpose() * row * w;
            g[i] += PRIOR_WEIGHT * (phi[i] - phi_prior[i]);
            jtj[(i, i)] += PRIOR_WEIGHT;
        }
        let mut improved = false;
        for _ in 0..20 {
            let mut lhs = jtj.clone();
            for i in 0..p {
                lhs[(i, i)] += mu * (jtj[(i, i)] + 1e-12);
            }
            let Some(chol) = lhs.cholesky() else {
                mu *= 10.0;
                continue;
            };
            let step = chol.solve(&(-&g));
            let trial: Vec<f64> = phi.iter().zip(step.iter()).map(|(p, s)| p + s).collect();
            let (ct, tt) = cost_of(&trial);
            if ct.is_finite() && ct < cost {
                let decrease = cost - ct;
                phi = trial;
                theta = tt;
                cost = ct;
                mu = (mu / 3.0).max(1e-12);
                improved = decrease > STOP_DECREASE * (1.0 + cost);
                break;
            }
            mu *= 10.0;
        }
        if !improved {
            break;
        }
    }
    let theta_b = (&k * DVector::from_column_slice(&theta))
        .iter()
        .copied()
        .collect::<Vec<_>>();
    let misfit = (&a_data * DVector::from_column_slice(&theta) - &c_data).norm_squared();
    ConsistentEstimate {
        theta,
        theta_b,
        misfit,
        iterations,
    }
}

/// Smallest eigenvalue of each body's pseudo-inertia in `theta`, relative to its largest
/// (non-negative for a consistent θ).
pub fn pseudo_inertia_margins(model: &Model, theta: &[f64]) -> Vec<f64> {
    (0..model.dof())
        .map(|b| {
            let j = pseudo_inertia(&theta[PARAMS_PER_BODY * b..PARAMS_PER_BODY * (b + 1)]);
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
