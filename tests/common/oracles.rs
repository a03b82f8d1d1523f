//! Oracles for the dynamics that trust no dynamics algorithm.
//!
//! Everything here is built from link poses (forward kinematics) and the model's inertial data
//! only: velocities come from differencing poses, the mass matrix from the kinetic energy,
//! `C q̇` and `g` from the Euler–Lagrange equations. So an error shared by every algorithm of
//! the project (RNEA, CRBA, Christoffel `C`, Slotine–Li, regressor) still shows up. The
//! quantities under test come through the [`Dynamics`] trait so that the same suite can check
//! the generic numeric code and, later, generated code.
//!
//! # Accuracy of the differences
//! Every derivative is a central difference extrapolated twice (Richardson, steps h, 2h, 4h),
//! which leaves a truncation error `≈ 0.013 (Ω h)⁶` relative, where `Ω` is the fastest rate at
//! which the differenced function turns per unit step. The step is taken along a unit
//! direction, so `Ω ≤ Σ|u_k| ≤ √n ≈ 3.2` rad per unit for 10 joints: with `h = 1e-2` the
//! truncation is ~1e-11. Rounding contributes `≈ 1.7 ε / h ≈ 4e-14` relative per level of
//! differencing, times `1.7 / h ≈ 170` for each nested level: the Lagrangian `C q̇` (poses → T →
//! D → Ḋ) is the deepest at three levels, about 1e-11. The tolerances below sit two to three
//! orders of magnitude above the errors observed over hundreds of random trees and two to three
//! below the 1e-6 relative error that the suite must catch (`tests/oracles.rs` checks both).

use super::random_model::JointState;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::Model;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use std::collections::BTreeMap;
use std::fmt;

/// The quantities under test, from whichever implementation computes them.
pub trait Dynamics {
    fn end_effector_pose(&self, q: &[f64]) -> (Matrix3<f64>, Vector3<f64>);
    fn jacobian(&self, q: &[f64]) -> DMatrix<f64>;
    fn jacobian_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64>;
    fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64>;
    fn coriolis_matrix(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64>;
    fn gravity_torque(&self, q: &[f64]) -> DVector<f64>;
    fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DVector<f64>;
    fn slotine_li(
        &self,
        q: &[f64],
        qd: &[f64],
        v: &[f64],
        a: &[f64],
        with_gravity: bool,
    ) -> DVector<f64>;
    fn regressor(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> DMatrix<f64>;
    /// The regressor of the same model with gravity set to zero.
    fn regressor_without_gravity(
        &self,
        q: &[f64],
        qd: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> DMatrix<f64>;
}

impl Dynamics for NumericDynamics<'_> {
    fn end_effector_pose(&self, q: &[f64]) -> (Matrix3<f64>, Vector3<f64>) {
        NumericDynamics::end_effector_pose(self, q)
    }
    fn jacobian(&self, q: &[f64]) -> DMatrix<f64> {
        NumericDynamics::jacobian(self, q)
    }
    fn jacobian_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
        NumericDynamics::jacobian_dot(self, q, qd)
    }
    fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64> {
        NumericDynamics::mass_matrix(self, q)
    }
    fn coriolis_matrix(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
        NumericDynamics::coriolis_matrix(self, q, qd)
    }
    fn gravity_torque(&self, q: &[f64]) -> DVector<f64> {
        NumericDynamics::gravity_torque(self, q)
    }
    fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DVector<f64> {
        NumericDynamics::inverse_dynamics(self, q, qd, qdd)
    }
    fn slotine_li(
        &self,
        q: &[f64],
        qd: &[f64],
        v: &[f64],
        a: &[f64],
        with_gravity: bool,
    ) -> DVector<f64> {
        NumericDynamics::slotine_li(self, q, qd, v, a, with_gravity)
    }
    fn regressor(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> DMatrix<f64> {
        NumericDynamics::regressor(self, q, qd, v, a)
    }
    fn regressor_without_gravity(
        &self,
        q: &[f64],
        qd: &[f64],
        v: &[f64],
        a: &[f64],
    ) -> DMatrix<f64> {
        let mut weightless = self.model.clone();
        weightless.gravity = Vector3::zeros();
        NumericDynamics::new(&weightless).regressor(q, qd, v, a)
    }
}

// ---------------------------------------------------------------------------------------------
// Finite differences

/// Base step of every difference, along a unit direction (see the module documentation).
pub const STEP: f64 = 1e-2;

/// `lim_{t→0} quotient(t)` for a quotient whose error is even in t (`c₂t² + c₄t⁴ + …`, as for
/// every central difference): two Richardson steps on t = h, 2h, 4h leave `O(h⁶)`.
pub fn extrapolate(quotient: impl Fn(f64) -> DMatrix<f64>, h: f64) -> DMatrix<f64> {
    let (d1, d2, d4) = (quotient(h), quotient(2.0 * h), quotient(4.0 * h));
    let r1 = (&d1 * 4.0 - &d2) / 3.0;
    let r2 = (&d2 * 4.0 - &d4) / 3.0;
    (r1 * 16.0 - r2) / 15.0
}

fn shifted(x: &[f64], dir: &[f64], t: f64) -> Vec<f64> {
    x.iter().zip(dir).map(|(xi, di)| xi + t * di).collect()
}

fn unit(n: usize, k: usize) -> Vec<f64> {
    let mut e = vec![0.0; n];
    e[k] = 1.0;
    e
}

/// Derivative of `f` at `x` along `dir` (differenced along the unit direction, then scaled,
/// since the derivative is linear in the direction).
pub fn directional_derivative(
    f: impl Fn(&[f64]) -> DMatrix<f64>,
    x: &[f64],
    dir: &[f64],
) -> DMatrix<f64> {
    let norm = dir.iter().map(|d| d * d).sum::<f64>().sqrt();
    if norm == 0.0 {
        return f(x) * 0.0;
    }
    let u: Vec<f64> = dir.iter().map(|d| d / norm).collect();
    extrapolate(
        |t| (f(&shifted(x, &u, t)) - f(&shifted(x, &u, -t))) / (2.0 * t),
        STEP,
    ) * norm
}

/// Gradient of a scalar function by central differences along each coordinate.
pub fn gradient(f: impl Fn(&[f64]) -> f64, x: &[f64]) -> DVector<f64> {
    let scalar = |y: &[f64]| DMatrix::from_element(1, 1, f(y));
    DVector::from_fn(x.len(), |k, _| {
        directional_derivative(scalar, x, &unit(x.len(), k))[(0, 0)]
    })
}

/// The rotation vector `w` with `R = exp([w]×)`, for rotations well below a half turn.
pub fn rotation_log(r: &Matrix3<f64>) -> Vector3<f64> {
    // (R − Rᵀ)/2 = sin θ [axis]×, (tr R − 1)/2 = cos θ; atan2 keeps small angles accurate.
    let sin_axis = Vector3::new(
        r[(2, 1)] - r[(1, 2)],
        r[(0, 2)] - r[(2, 0)],
        r[(1, 0)] - r[(0, 1)],
    ) * 0.5;
    let sin = sin_axis.norm();
    let theta = sin.atan2((r.trace() - 1.0) * 0.5);
    if sin == 0.0 {
        sin_axis
    } else {
        sin_axis * (theta / sin)
    }
}

fn amax(m: &DMatrix<f64>) -> f64 {
    m.amax()
}

fn col(v: &[f64]) -> DMatrix<f64> {
    DMatrix::from_column_slice(v.len(), 1, v)
}

// ---------------------------------------------------------------------------------------------
// Oracle values

/// Oracle 1: `J` from central differences of the end-effector pose. Linear rows: `∂p/∂q_k`;
/// angular rows: `log(R(q + t e_k) R(q − t e_k)ᵀ) / 2t`, which is odd in t, so extrapolation
/// applies to it as to any central difference.
pub fn jacobian_from_pose(
    fk: impl Fn(&[f64]) -> (Matrix3<f64>, Vector3<f64>),
    q: &[f64],
) -> DMatrix<f64> {
    let n = q.len();
    let mut jac = DMatrix::zeros(6, n);
    for k in 0..n {
        let e = unit(n, k);
        let column = extrapolate(
            |t| {
                let (r_plus, p_plus) = fk(&shifted(q, &e, t));
                let (r_minus, p_minus) = fk(&shifted(q, &e, -t));
                let lin = (p_plus - p_minus) / (2.0 * t);
                let ang = rotation_log(&(r_plus * r_minus.transpose())) / (2.0 * t);
                DMatrix::from_iterator(6, 1, lin.iter().chain(ang.iter()).copied())
            },
            STEP,
        );
        jac.set_column(k, &column.column(0));
    }
    jac
}

/// Oracle 2: `J̇ = (J(q + h q̇) − J(q − h q̇)) / 2h`, extrapolated.
pub fn jacobian_rate(
    jacobian: impl Fn(&[f64]) -> DMatrix<f64>,
    q: &[f64],
    qd: &[f64],
) -> DMatrix<f64> {
    directional_derivative(jacobian, q, qd)
}

/// Oracle 5a: `C_ij = Σ_k ½ (∂D_ij/∂q_k + ∂D_ik/∂q_j − ∂D_jk/∂q_i) q̇_k` from differenced `D`.
pub fn christoffel_coriolis(
    mass_matrix: impl Fn(&[f64]) -> DMatrix<f64>,
    q: &[f64],
    qd: &[f64],
) -> DMatrix<f64> {
    let n = q.len();
    let dd: Vec<DMatrix<f64>> = (0..n)
        .map(|k| directional_derivative(&mass_matrix, q, &unit(n, k)))
        .collect();
    DMatrix::from_fn(n, n, |i, j| {
        (0..n)
            .map(|k| 0.5 * (dd[k][(i, j)] + dd[j][(i, k)] - dd[i][(j, k)]) * qd[k])
            .sum()
    })
}

/// Oracle 5b: `Ḋ = (D(q + h q̇) − D(q − h q̇)) / 2h`, extrapolated.
pub fn mass_matrix_rate(
    mass_matrix: impl Fn(&[f64]) -> DMatrix<f64>,
    q: &[f64],
    qd: &[f64],
) -> DMatrix<f64> {
    directional_derivative(mass_matrix, q, qd)
}

/// Energies of a model from its link poses and inertial data alone.
pub struct Energies<'m> {
    model: &'m Model,
    /// Used for `body_poses` only (forward kinematics, which the Jacobian oracle vouches for).
    kinematics: NumericDynamics<'m>,
}

/// Oracle 4: the terms of the Euler–Lagrange equations `τ = d/dt ∂L/∂q̇ − ∂L/∂q`, `L = T − V`.
#[derive(Clone, Debug)]
pub struct Lagrangian {
    /// Hessian of `T` in `q̇`.
    pub d: DMatrix<f64>,
    /// `Ḋ q̇ − ∂T/∂q`, the velocity terms (`= C q̇`).
    pub c_qd: DVector<f64>,
    /// `∂V/∂q`.
    pub g: DVector<f64>,
    /// `D q̈ + C q̇ + g`.
    pub tau: DVector<f64>,
}

impl<'m> Energies<'m> {
    pub fn new(model: &'m Model) -> Self {
        Energies {
            model,
            kinematics: NumericDynamics::new(model),
        }
    }

    /// World centre of mass and rotation of every body.
    fn bodies(&self, q: &[f64]) -> Vec<(Vector3<f64>, Matrix3<f64>)> {
        let poses = self.kinematics.body_poses(q);
        poses
            .iter()
            .zip(&self.model.bodies)
            .map(|((r, p), b)| (r * b.inertia.com + p, *r))
            .collect()
    }

    /// Oracle 3: `V(q) = Σ_i −m_i gravityᵀ p_ci(q)`.
    pub fn potential(&self, q: &[f64]) -> f64 {
        let g = self.model.gravity;
        self.bodies(q)
            .iter()
            .zip(&self.model.bodies)
            .map(|((c, _), b)| -b.inertia.mass * g.dot(c))
            .sum()
    }

    /// Every body's centre-of-mass velocity and angular velocity (world axes) when the joints
    /// move at `qd`, by differencing the link poses along `qd`.
    pub fn body_velocities(&self, q: &[f64], qd: &[f64]) -> Vec<(Vector3<f64>, Vector3<f64>)> {
        let stacked = directional_poses_rate(|x| self.bodies(x), q, qd);
        (0..self.model.bodies.len())
            .map(|i| {
                let s = stacked.rows(6 * i, 6);
                (
                    Vector3::new(s[0], s[1], s[2]),
                    Vector3::new(s[3], s[4], s[5]),
                )
            })
            .collect()
    }

    /// `T(q, q̇) = Σ_i ½ m_i |v_ci|² + ½ ω_iᵀ (R_i I_ci R_iᵀ) ω_i`.
    pub fn kinetic(&self, q: &[f64], qd: &[f64]) -> f64 {
        let rotations = self.bodies(q);
        let velocities = self.body_velocities(q, qd);
        (self.model.bodies.iter().zip(&rotations).zip(&velocities))
            .map(|((b, (_, r)), (v, w))| {
                let inertia = r * b.inertia.inertia_com * r.transpose();
                0.5 * b.inertia.mass * v.norm_squared() + 0.5 * w.dot(&(inertia * w))
            })
            .sum()
    }

    /// `D(q)`, the Hessian of `T` in `q̇`. `T` is a quadratic form in `q̇`, so polarization is
    /// exact: `D_kk = 2 T(e_k)`, `D_jk = T(e_j + e_k) − T(e_j) − T(e_k)`.
    pub fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64> {
        let n = q.len();
        let t_unit: Vec<f64> = (0..n).map(|k| self.kinetic(q, &unit(n, k))).collect();
        let mut d = DMatrix::zeros(n, n);
        for j in 0..n {
            d[(j, j)] = 2.0 * t_unit[j];
            for k in 0..j {
                let mut e = unit(n, j);
                e[k] = 1.0;
                let djk = self.kinetic(q, &e) - t_unit[j] - t_unit[k];
                d[(j, k)] = djk;
                d[(k, j)] = djk;
            }
        }
        d
    }

    /// The Euler–Lagrange terms at `(q, q̇, q̈)`. Since `T = ½ q̇ᵀ D q̇`, `∂T/∂q̇ = D q̇` and
    /// `d/dt ∂T/∂q̇ = D q̈ + Ḋ q̇`; `Ḋ` and `∂T/∂q`, `∂V/∂q` are differenced.
    pub fn lagrangian(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> Lagrangian {
        let d = self.mass_matrix(q);
        let d_dot = directional_derivative(|x| self.mass_matrix(x), q, qd);
        let dt_dq = gradient(|x| self.kinetic(x, qd), q);
        let g = gradient(|x| self.potential(x), q);
        let qd = DVector::from_column_slice(qd);
        let c_qd = &d_dot * &qd - dt_dq;
        let tau = &d * DVector::from_column_slice(qdd) + &c_qd + &g;
        Lagrangian { d, c_qd, g, tau }
    }
}

/// Rates of (centre of mass, rotation) pairs along `qd`, stacked `[v; ω]` per body.
fn directional_poses_rate(
    bodies: impl Fn(&[f64]) -> Vec<(Vector3<f64>, Matrix3<f64>)>,
    q: &[f64],
    qd: &[f64],
) -> DMatrix<f64> {
    let norm = qd.iter().map(|d| d * d).sum::<f64>().sqrt();
    let count = 6 * bodies(q).len();
    if norm == 0.0 {
        return DMatrix::zeros(count, 1);
    }
    let u: Vec<f64> = qd.iter().map(|d| d / norm).collect();
    let rates = extrapolate(
        |t| {
            let plus = bodies(&shifted(q, &u, t));
            let minus = bodies(&shifted(q, &u, -t));
            let per_body = plus.iter().zip(&minus).flat_map(|((cp, rp), (cm, rm))| {
                let v = (cp - cm) / (2.0 * t);
                let w = rotation_log(&(rp * rm.transpose())) / (2.0 * t);
                [v.x, v.y, v.z, w.x, w.y, w.z]
            });
            DMatrix::from_iterator(count, 1, per_body)
        },
        STEP,
    );
    rates * norm
}

// ---------------------------------------------------------------------------------------------
// Comparisons

/// Tolerances, relative to the size of the expected value (see the module documentation).
pub mod tolerance {
    /// Single-level differences of the pose or of a subject's own quantity (J, J̇, g, Christoffel
    /// `C`, `Ḋ`): errors observed ≲ 1e-11.
    pub const DIFFERENCED: f64 = 1e-9;
    /// The Lagrangian (up to three nested differences, observed ≲ 1e-10).
    pub const LAGRANGIAN: f64 = 1e-8;
    /// Algebraic identities between the subject's own quantities (rounding only, ≲ 1e-14).
    pub const IDENTITY: f64 = 1e-11;
}

/// Errors are relative to the larger of the expected value and this fraction of the quantity's
/// natural size (from the masses, lengths, rates and gravity of the model and state).
///
/// Some quantities vanish for physical reasons (`g ≡ 0` when every joint axis is vertical,
/// `C q̇ ≡ 0` for one joint) or nearly so at some states, and the oracles' own error is a
/// fraction of the natural size, not of the value: the Lagrangian `C q̇` is off by up to ~1e-11
/// of `M L² q̇²` over the random trees. Relative to 1% of the natural size that is ~1e-9, a
/// decade below the tolerance; a 1e-6 relative error is still caught in any quantity larger
/// than 1e-4 of its natural size.
pub const NEGLIGIBLE: f64 = 1e-2;

/// One comparison: its name, the relative error observed and the tolerance.
#[derive(Clone, Debug)]
pub struct Check {
    pub name: &'static str,
    pub error: f64,
    pub tolerance: f64,
}

impl Check {
    /// NaN fails.
    pub fn passed(&self) -> bool {
        self.error <= self.tolerance
    }
}

impl fmt::Display for Check {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let verdict = if self.passed() { "ok" } else { "FAILED" };
        write!(
            f,
            "{:<34} error {:9.2e}  tolerance {:7.0e}  {verdict}",
            self.name, self.error, self.tolerance
        )
    }
}

/// Natural sizes of the quantities of one model at one state, so that a quantity that is zero
/// for physical reasons is compared absolutely instead of relative to rounding noise.
struct Scales {
    length: f64,
    mass: f64,
    gravity: f64,
    rate: f64,
    accel: f64,
}

impl Scales {
    fn new(model: &Model, dynamics: &impl Dynamics, state: &JointState) -> Scales {
        let poses = NumericDynamics::new(model).body_poses(&state.q);
        let reach = poses
            .iter()
            .zip(&model.bodies)
            .flat_map(|((r, p), b)| [p.norm(), (r * b.inertia.com + p).norm()])
            .chain([dynamics.end_effector_pose(&state.q).1.norm()])
            .fold(0.0, f64::max);
        let inf = |v: &[f64]| v.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
        Scales {
            length: reach + 0.1,
            mass: model.bodies.iter().map(|b| b.inertia.mass).sum(),
            gravity: model.gravity.norm(),
            rate: inf(&state.qd).max(inf(&state.v)),
            accel: inf(&state.qdd).max(inf(&state.a)),
        }
    }
    fn inertia(&self) -> f64 {
        self.mass * self.length * self.length
    }
    fn force(&self) -> f64 {
        self.mass
            * self.length
            * (self.gravity + self.length * (self.accel + self.rate * self.rate))
    }
}

/// `|actual − expected|_max / max(|expected|_max, NEGLIGIBLE · natural)`.
fn compare(
    name: &'static str,
    actual: &DMatrix<f64>,
    expected: &DMatrix<f64>,
    natural: f64,
    tol: f64,
) -> Check {
    assert_eq!(actual.shape(), expected.shape(), "{name}: shapes differ");
    let scale = amax(expected).max(NEGLIGIBLE * natural);
    Check {
        name,
        error: amax(&(actual - expected)) / scale,
        tolerance: tol,
    }
}

fn vcompare(
    name: &'static str,
    actual: &DVector<f64>,
    expected: &DVector<f64>,
    natural: f64,
    tol: f64,
) -> Check {
    compare(
        name,
        &col(actual.as_slice()),
        &col(expected.as_slice()),
        natural,
        tol,
    )
}

/// Oracle 7: `D` symmetric, and positive definite (Cholesky succeeds, smallest eigenvalue > 0).
/// The positive-definiteness check reports `λ_max/λ_min / 1e12` as its error, i.e. it accepts
/// a condition number up to 1e12 (the random trees stay below ~1e6).
fn positive_definite(d: &DMatrix<f64>) -> Check {
    let name = "D positive definite";
    let max_condition = 1e12;
    let error = match d.clone().cholesky() {
        None => f64::INFINITY,
        Some(_) => {
            let eig = d.clone().symmetric_eigenvalues();
            let (lo, hi) = (eig.min(), eig.max());
            if lo > 0.0 {
                hi / lo / max_condition
            } else {
                f64::INFINITY
            }
        }
    };
    Check {
        name,
        error,
        tolerance: 1.0,
    }
}

/// Runs every oracle on `dynamics` (the subject) for `model` at `state`.
pub fn check_all(model: &Model, dynamics: &impl Dynamics, state: &JointState) -> Vec<Check> {
    use tolerance::*;
    let JointState { q, qd, qdd, v, a } = state;
    let s = Scales::new(model, dynamics, state);
    let dv = |x: &[f64]| DVector::from_column_slice(x);
    let mut checks = Vec::new();

    // 1. J against the differenced pose; 2. J̇ against the differenced J.
    let jac = dynamics.jacobian(q);
    let jac_fd = jacobian_from_pose(|x| dynamics.end_effector_pose(x), q);
    checks.push(compare("J = ∂fk/∂q", &jac, &jac_fd, s.length, DIFFERENCED));
    let jdot_fd = jacobian_rate(|x| dynamics.jacobian(x), q, qd);
    checks.push(compare(
        "J̇ = dJ/dt",
        &dynamics.jacobian_dot(q, qd),
        &jdot_fd,
        s.length * s.rate,
        DIFFERENCED,
    ));

    // 3. g against the gradient of the potential energy.
    let energies = Energies::new(model);
    let g = dynamics.gravity_torque(q);
    let g_fd = gradient(|x| energies.potential(x), q);
    let natural_g = s.mass * s.gravity * s.length;
    checks.push(vcompare("g = ∂V/∂q", &g, &g_fd, natural_g, DIFFERENCED));

    // 4. The Lagrangian: D, C q̇, g and τ from the energies alone.
    let d = dynamics.mass_matrix(q);
    let c = dynamics.coriolis_matrix(q, qd);
    let tau = dynamics.inverse_dynamics(q, qd, qdd);
    let lag = energies.lagrangian(q, qd, qdd);
    let c_qd = &c * dv(qd);
    checks.push(compare(
        "Lagrange: D = ∂²T/∂q̇²",
        &d,
        &lag.d,
        s.inertia(),
        LAGRANGIAN,
    ));
    checks.push(vcompare(
        "Lagrange: C q̇",
        &c_qd,
        &lag.c_qd,
        s.inertia() * s.rate * s.rate,
        LAGRANGIAN,
    ));
    checks.push(vcompare("Lagrange: g", &g, &lag.g, natural_g, LAGRANGIAN));
    checks.push(vcompare(
        "Lagrange: τ = ID(q, q̇, q̈)",
        &tau,
        &lag.tau,
        s.force(),
        LAGRANGIAN,
    ));

    // 5. C against the Christoffel symbols of the differenced D; C + Cᵀ = Ḋ.
    let mass = |x: &[f64]| dynamics.mass_matrix(x);
    let c_fd = christoffel_coriolis(mass, q, qd);
    checks.push(compare(
        "C = Christoffel(∂D/∂q)",
        &c,
        &c_fd,
        s.inertia() * s.rate,
        DIFFERENCED,
    ));
    let d_dot = mass_matrix_rate(mass, q, qd);
    checks.push(compare(
        "C + Cᵀ = Ḋ",
        &(&c + c.transpose()),
        &d_dot,
        s.inertia() * s.rate,
        DIFFERENCED,
    ));

    // 6. Y θ = D a + C v + g, and Y from the inverse-dynamics regressor with and without gravity.
    let theta = dv(&model.parameters());
    let y = dynamics.regressor(q, qd, v, a);
    let cv = dynamics.coriolis_matrix(q, qd) * dv(v);
    let dacvg = &d * dv(a) + &cv + &g;
    checks.push(vcompare(
        "Y θ = D a + C v + g",
        &(&y * &theta),
        &dacvg,
        s.force(),
        IDENTITY,
    ));
    let zero = vec![0.0; q.len()];
    let qd_plus_v: Vec<f64> = qd.iter().zip(v).map(|(x, y)| x + y).collect();
    let y_id0 = |x: &[f64]| dynamics.regressor_without_gravity(q, x, x, &zero);
    let y_identity =
        dynamics.regressor(q, &zero, &zero, a) + (y_id0(&qd_plus_v) - y_id0(qd) - y_id0(v)) * 0.5;
    // Regressor entries are forces per unit parameter: accelerations times lengths.
    let per_parameter = s.force() / s.mass;
    checks.push(compare(
        "Y = Y_id,g(0, a) + ½[Y_id,0 …]",
        &y,
        &y_identity,
        per_parameter,
        IDENTITY,
    ));

    // 7. D symmetric positive definite.
    checks.push(compare(
        "D symmetric",
        &d.transpose(),
        &d,
        s.inertia(),
        IDENTITY,
    ));
    checks.push(positive_definite(&d));

    // 8. Slotine–Li and inverse dynamics agree; C q̇ = ID(q, q̇, 0) − g.
    let sl_at_qd = dynamics.slotine_li(q, qd, qd, qdd, true);
    checks.push(vcompare(
        "Slotine–Li(v=q̇, a=q̈) = τ",
        &sl_at_qd,
        &tau,
        s.force(),
        IDENTITY,
    ));
    let id0 = dynamics.inverse_dynamics(q, qd, &zero) - &g;
    // Rounding in ID(q, q̇, 0) − g is relative to the forces, gravity included.
    checks.push(vcompare(
        "C q̇ = ID(q, q̇, 0) − g",
        &c_qd,
        &id0,
        s.force(),
        IDENTITY,
    ));
    let sl = dynamics.slotine_li(q, qd, v, a, true);
    checks.push(vcompare(
        "Slotine–Li = D a + C v + g",
        &sl,
        &dacvg,
        s.force(),
        IDENTITY,
    ));
    let sl0 = dynamics.slotine_li(q, qd, v, a, false);
    checks.push(vcompare(
        "Slotine–Li, no gravity = D a + C v",
        &sl0,
        &(&dacvg - &g),
        s.force(),
        IDENTITY,
    ));
    checks
}

/// Largest error seen per check over many runs, for the margins report.
#[derive(Default, Debug)]
pub struct Summary {
    worst: BTreeMap<&'static str, (f64, f64, usize)>,
}

impl Summary {
    pub fn record(&mut self, checks: &[Check]) {
        for c in checks {
            let entry = self.worst.entry(c.name).or_insert((0.0, c.tolerance, 0));
            entry.0 = entry.0.max(c.error);
            entry.2 += 1;
        }
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (name, (worst, tol, runs)) in &self.worst {
            writeln!(
                f,
                "  {name:<34} worst {worst:9.2e}  tolerance {tol:7.0e}  ({runs} runs)"
            )?;
        }
        Ok(())
    }
}

/// Panics with every failed check when any check failed.
pub fn assert_passed(context: &str, checks: &[Check]) {
    let failed: Vec<String> = checks
        .iter()
        .filter(|c| !c.passed())
        .map(|c| format!("  {c}"))
        .collect();
    assert!(
        failed.is_empty(),
        "{context}: oracle checks failed:\n{}",
        failed.join("\n")
    );
}
