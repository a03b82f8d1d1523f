//! Oracles for the dynamics that trust no dynamics algorithm.
//!
//! Everything here is built from link poses (forward kinematics) and the model's inertial data
//! only: velocities come from differencing poses, the mass matrix from the kinetic energy,
//! `C q̇` and `g` from the Euler–Lagrange equations. So an error shared by every algorithm of
//! the project (RNEA, CRBA, Christoffel `C`, Slotine–Li, regressor, the parameter vector) still
//! shows up. The quantities under test come through the [`Dynamics`] trait, so the same suite
//! can check the generic numeric code and, later, generated code.
//!
//! # Accuracy of the differences, and the tolerances
//! Every derivative is a central difference along a unit direction, extrapolated twice
//! (Richardson on steps h, 2h, 4h with h = [`STEP`]), which leaves a truncation error of about
//! `0.013 (Ω h)⁶` relative, `Ω` being the fastest rate (rad per unit step) at which the
//! differenced function turns. Along a unit direction `Ω ≤ Σ|u_k| ≤ √n ≈ 3.2` for 10 joints, so
//! with h = 1e-2 truncation is below ~1e-11. Rounding adds `≈ 1.7 ε / h ≈ 4e-14` of the
//! function's size, and each nested difference multiplies what is below it by `1.7 / h ≈ 170`.
//! The deepest oracle is the Lagrangian `C q̇`: poses → velocities → `T` (first difference),
//! `D` by exact polarization of `T`, then `Ḋ` and `∂T/∂q` (second difference): ~7e-12 of its
//! natural size `M L² q̇²`. Worst errors observed (256 random trees, Panda, UR5, arm7): 3e-13
//! for `J`, `g` and the Lagrangian `D` and `g`; 1e-11 for `J̇`, Christoffel `C`, `C + Cᵀ` and
//! the Lagrangian `τ`; 4e-10 for the Lagrangian `C q̇`; 3e-14 for the algebraic identities. The
//! [`tolerance`]s sit 25× (Lagrangian `C q̇`) to 100× or more above these and at least 100×
//! below the 1e-6 relative error that the suite must catch (`codegen/tests/suite/oracles.rs` checks both).

use crate::random_model::JointState;
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
    /// `D a + C(q, q̇) v + g`, without `g` when `gravity` is false.
    fn slotine_li(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64], gravity: bool) -> DVector<f64>;
    fn regressor(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> DMatrix<f64>;
    /// The regressor of the same model with gravity set to zero.
    fn weightless_regressor(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> DMatrix<f64>;
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
    fn slotine_li(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64], gravity: bool) -> DVector<f64> {
        NumericDynamics::slotine_li(self, q, qd, v, a, gravity)
    }
    fn regressor(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> DMatrix<f64> {
        NumericDynamics::regressor(self, q, qd, v, a)
    }
    fn weightless_regressor(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> DMatrix<f64> {
        let weightless = self
            .model
            .clone()
            .with_gravity(Vector3::zeros())
            .expect("a valid model");
        NumericDynamics::new(&weightless).regressor(q, qd, v, a)
    }
}

// ---------------------------------------------------------------------------------------------
// Finite differences

/// Base step of every difference, along a unit direction (see the module documentation).
pub const STEP: f64 = 1e-2;

/// A rotation and a translation, as `end_effector_pose` and `body_poses` return them.
pub type Pose = (Matrix3<f64>, Vector3<f64>);

/// The Jacobian of `f` at `x`: column `j` from central differences along `e_j` with steps
/// `h`, `2h`, `4h`, extrapolated ([`extrapolate`]).
pub fn jacobian_by_differences(f: impl Fn(&[f64]) -> DMatrix<f64>, x: &[f64], h: f64) -> DMatrix<f64> {
    let shifted = |j: usize, t: f64| -> Vec<f64> {
        let mut y = x.to_vec();
        y[j] += t;
        y
    };
    let columns: Vec<DMatrix<f64>> = (0..x.len())
        .map(|j| extrapolate(|t| (f(&shifted(j, t)) - f(&shifted(j, -t))) / (2.0 * t), h))
        .collect();
    DMatrix::from_fn(columns[0].nrows(), x.len(), |i, j| columns[j][(i, 0)])
}

/// `lim_{t→0} quotient(t)` for a quotient whose error is even in t (`c₂t² + c₄t⁴ + …`, as for
/// every central difference): two Richardson steps on t = h, 2h, 4h leave `O(h⁶)`.
pub fn extrapolate(quotient: impl Fn(f64) -> DMatrix<f64>, h: f64) -> DMatrix<f64> {
    let (d1, d2, d4) = (quotient(h), quotient(2.0 * h), quotient(4.0 * h));
    let r1 = (&d1 * 4.0 - &d2) / 3.0;
    let r2 = (&d2 * 4.0 - &d4) / 3.0;
    (r1 * 16.0 - r2) / 15.0
}

/// The derivative at `x` along `dir` from a central quotient `quotient(x + t u, x − t u, t)`
/// along the unit direction `u = dir / |dir|`, extrapolated, times `|dir|` (a derivative is
/// linear in the direction; a unit step keeps the truncation error bounded).
pub fn along(x: &[f64], dir: &[f64], quotient: impl Fn(&[f64], &[f64], f64) -> DMatrix<f64>) -> DMatrix<f64> {
    let norm = dir.iter().map(|d| d * d).sum::<f64>().sqrt();
    let u: Vec<f64> = dir
        .iter()
        .map(|d| if norm > 0.0 { d / norm } else { 0.0 })
        .collect();
    let at = |t: f64| -> Vec<f64> { x.iter().zip(&u).map(|(xi, ui)| xi + t * ui).collect() };
    extrapolate(|t| quotient(&at(t), &at(-t), t), STEP) * norm
}

/// Derivative of `f` at `x` along `dir`.
pub fn directional_derivative(f: impl Fn(&[f64]) -> DMatrix<f64>, x: &[f64], dir: &[f64]) -> DMatrix<f64> {
    along(x, dir, |plus, minus, t| (f(plus) - f(minus)) / (2.0 * t))
}

/// Gradient of a scalar function.
pub fn gradient(f: impl Fn(&[f64]) -> f64, x: &[f64]) -> DVector<f64> {
    let f = |y: &[f64]| DMatrix::from_element(1, 1, f(y));
    DVector::from_fn(x.len(), |k, _| {
        directional_derivative(f, x, &unit(x.len(), k))[(0, 0)]
    })
}

fn unit(n: usize, k: usize) -> Vec<f64> {
    let mut e = vec![0.0; n];
    e[k] = 1.0;
    e
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

/// Central quotient of a moving frame, `[(p₊ − p₋) / 2t; log(R₊ R₋ᵀ) / 2t]`: its linear and
/// angular velocity (world axes) up to `O(t²)`. The rotation part is odd in t too (swapping
/// ± transposes `R₊ R₋ᵀ`, which negates its log), so extrapolation applies to both.
fn pose_quotient((r_plus, p_plus): &Pose, (r_minus, p_minus): &Pose, t: f64) -> [f64; 6] {
    let v = (p_plus - p_minus) / (2.0 * t);
    let w = rotation_log(&(r_plus * r_minus.transpose())) / (2.0 * t);
    [v.x, v.y, v.z, w.x, w.y, w.z]
}

/// The velocities `[v; ω]` of frames that move with `q` when `q` changes at rate `qd`,
/// stacked frame after frame, from differenced poses.
fn frame_velocities(frames: impl Fn(&[f64]) -> Vec<Pose>, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
    along(q, qd, |plus, minus, t| {
        let (plus, minus) = (frames(plus), frames(minus));
        let stacked = plus.iter().zip(&minus).flat_map(|(p, m)| pose_quotient(p, m, t));
        DMatrix::from_iterator(6 * plus.len(), 1, stacked)
    })
}

// ---------------------------------------------------------------------------------------------
// Oracle values

/// Oracle 1: `J` from the differenced end-effector pose, column by column.
pub fn jacobian_from_pose(fk: impl Fn(&[f64]) -> Pose, q: &[f64]) -> DMatrix<f64> {
    let n = q.len();
    let mut jac = DMatrix::zeros(6, n);
    for k in 0..n {
        jac.set_column(k, &frame_velocities(|x| vec![fk(x)], q, &unit(n, k)).column(0));
    }
    jac
}

/// Oracle 2: `J̇ = (J(q + h q̇) − J(q − h q̇)) / 2h`, extrapolated.
pub fn jacobian_rate(jacobian: impl Fn(&[f64]) -> DMatrix<f64>, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
    directional_derivative(jacobian, q, qd)
}

/// Oracle 5a: `C_ij = Σ_k ½ (∂D_ij/∂q_k + ∂D_ik/∂q_j − ∂D_jk/∂q_i) q̇_k` from differenced `D`.
pub fn christoffel_coriolis(
    mass_matrix: impl Fn(&[f64]) -> DMatrix<f64>,
    q: &[f64],
    qd: &[f64],
) -> DMatrix<f64> {
    let n = q.len();
    let dd: Vec<_> = (0..n)
        .map(|k| directional_derivative(&mass_matrix, q, &unit(n, k)))
        .collect();
    DMatrix::from_fn(n, n, |i, j| {
        (0..n)
            .map(|k| 0.5 * (dd[k][(i, j)] + dd[j][(i, k)] - dd[i][(j, k)]) * qd[k])
            .sum()
    })
}

/// Oracle 5b: `Ḋ = (D(q + h q̇) − D(q − h q̇)) / 2h`, extrapolated.
pub fn mass_matrix_rate(mass_matrix: impl Fn(&[f64]) -> DMatrix<f64>, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
    directional_derivative(mass_matrix, q, qd)
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

/// Energies of a model from its link poses and inertial data (`Model::bodies`, not the
/// parameter vector) alone.
pub struct Energies<'m> {
    model: &'m Model,
    /// Used for `body_poses` only: forward kinematics, which the fixtures and the Jacobian
    /// oracle vouch for.
    kinematics: NumericDynamics<'m>,
}

impl<'m> Energies<'m> {
    pub fn new(model: &'m Model) -> Self {
        Energies {
            model,
            kinematics: NumericDynamics::new(model),
        }
    }

    /// Every body's rotation and centre of mass in the base frame.
    fn centres_of_mass(&self, q: &[f64]) -> Vec<Pose> {
        let poses = self.kinematics.body_poses(q);
        poses
            .iter()
            .zip(self.model.bodies())
            .map(|((r, p), b)| (*r, r * b.inertia.com + p))
            .collect()
    }

    /// Oracle 3: `V(q) = Σ_i −m_i gravityᵀ p_ci(q)`.
    pub fn potential(&self, q: &[f64]) -> f64 {
        let bodies = self.centres_of_mass(q).into_iter().zip(self.model.bodies());
        bodies
            .map(|((_, c), b)| -b.inertia.mass * self.model.gravity().dot(&c))
            .sum()
    }

    /// `T(q, q̇) = Σ_i ½ m_i |v_ci|² + ½ ω_iᵀ (R_i I_ci R_iᵀ) ω_i`, with the centre-of-mass and
    /// angular velocities from the body poses differenced along `q̇`.
    pub fn kinetic(&self, q: &[f64], qd: &[f64]) -> f64 {
        let velocities = frame_velocities(|x| self.centres_of_mass(x), q, qd);
        let bodies = self.centres_of_mass(q).into_iter().zip(self.model.bodies());
        (bodies.zip(velocities.as_slice().chunks_exact(6)))
            .map(|(((r, _), b), vw)| {
                let (v, w) = (
                    Vector3::from_column_slice(&vw[..3]),
                    Vector3::from_column_slice(&vw[3..]),
                );
                let inertia = r * b.inertia.inertia_com * r.transpose();
                0.5 * b.inertia.mass * v.norm_squared() + 0.5 * w.dot(&(inertia * w))
            })
            .sum()
    }

    /// `D(q)`, the Hessian of `T` in `q̇`. `T` is a quadratic form in `q̇`, so polarization is
    /// exact (no step): `D_kk = 2 T(e_k)`, `D_jk = T(e_j + e_k) − T(e_j) − T(e_k)`.
    pub fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64> {
        let n = q.len();
        let t_unit: Vec<f64> = (0..n).map(|k| self.kinetic(q, &unit(n, k))).collect();
        let mut d = DMatrix::from_fn(n, n, |j, k| if j == k { 2.0 * t_unit[j] } else { 0.0 });
        for j in 0..n {
            for k in 0..j {
                let mut e = unit(n, j);
                e[k] = 1.0;
                d[(j, k)] = self.kinetic(q, &e) - t_unit[j] - t_unit[k];
                d[(k, j)] = d[(j, k)];
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
        let c_qd = d_dot * DVector::from_column_slice(qd) - dt_dq;
        let tau = &d * DVector::from_column_slice(qdd) + &c_qd + &g;
        Lagrangian { d, c_qd, g, tau }
    }
}

// ---------------------------------------------------------------------------------------------
// Comparisons

/// Tolerances, relative to the size of the expected value (see the module documentation).
pub mod tolerance {
    /// One level of differences of a pose or of the subject's own quantity (`J`, `J̇`, `g`,
    /// Christoffel `C`, `Ḋ`).
    pub const DIFFERENCED: f64 = 1e-9;
    /// The Lagrangian: two nested levels of differences.
    pub const LAGRANGIAN: f64 = 1e-8;
    /// Algebraic identities between the subject's own quantities: rounding only.
    pub const IDENTITY: f64 = 1e-11;
}

/// Errors are relative to the larger of the expected value and this fraction of the quantity's
/// natural size (from the masses, lengths, rates and gravity of the model and state).
///
/// Some quantities vanish for physical reasons (`g ≡ 0` when every joint axis is vertical,
/// `C q̇ ≡ 0` for one joint) or nearly so at some states, and the oracles' own error is a
/// fraction of the natural size, not of the value: the Lagrangian `C q̇` is off by up to ~1e-11
/// of `M L² q̇²`. Relative to 1% of the natural size that is ~1e-9, a decade below the
/// tolerance; a 1e-6 relative error is still caught in any quantity above 1e-4 of its natural
/// size.
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
        let (name, error, tol) = (self.name, self.error, self.tolerance);
        write!(
            f,
            "{name:<34} error {error:9.2e}  tolerance {tol:7.0e}  {verdict}"
        )
    }
}

/// Natural sizes of the quantities of one model at one state (`M` total mass, `L` reach, `ω`
/// largest rate, `α` largest acceleration, `|g|` gravity).
struct Natural {
    /// `L`, of `J`.
    length: f64,
    /// `L ω`, of `J̇`.
    pose_rate: f64,
    /// `M L²`, of `D`.
    inertia: f64,
    /// `M L² ω`, of `C`.
    coriolis: f64,
    /// `M L² ω²`, of `C q̇`.
    velocity_force: f64,
    /// `M |g| L`, of `g`.
    gravity_force: f64,
    /// `M L (|g| + L (α + ω²))`, of `τ`.
    force: f64,
    /// `force / M`, of the entries of `Y` (forces per unit parameter).
    per_parameter: f64,
}

impl Natural {
    fn new(model: &Model, energies: &Energies, dynamics: &impl Dynamics, state: &JointState) -> Self {
        let bodies = energies.centres_of_mass(&state.q);
        let ee = dynamics.end_effector_pose(&state.q).1;
        let reach = bodies.iter().map(|(_, c)| c.norm()).fold(ee.norm(), f64::max);
        let largest = |vs: [&[f64]; 2]| {
            vs.iter()
                .flat_map(|v| v.iter())
                .fold(0.0, |m: f64, x| m.max(x.abs()))
        };
        let (length, mass) = (
            reach + 0.1,
            model.bodies().iter().map(|b| b.inertia.mass).sum::<f64>(),
        );
        let (rate, accel) = (largest([&state.qd, &state.v]), largest([&state.qdd, &state.a]));
        let inertia = mass * length * length;
        let per_parameter = length * (model.gravity().norm() + length * (accel + rate * rate));
        Natural {
            length,
            pose_rate: length * rate,
            inertia,
            coriolis: inertia * rate,
            velocity_force: inertia * rate * rate,
            gravity_force: mass * model.gravity().norm() * length,
            force: mass * per_parameter,
            per_parameter,
        }
    }
}

/// `|actual − expected|_max / max(|expected|_max, NEGLIGIBLE · natural)`. Vectors are n×1.
fn compare(
    name: &'static str,
    actual: &DMatrix<f64>,
    expected: &DMatrix<f64>,
    natural: f64,
    tol: f64,
) -> Check {
    assert_eq!(actual.shape(), expected.shape(), "{name}: shapes differ");
    let scale = expected.amax().max(NEGLIGIBLE * natural);
    Check {
        name,
        error: (actual - expected).amax() / scale,
        tolerance: tol,
    }
}

/// Oracle 7b: `D` positive definite: Cholesky succeeds and the smallest eigenvalue is positive.
/// The error is the condition number over 1e12, so tolerance 1 accepts up to 1e12 (real arms
/// and the random trees stay below 1e5).
fn positive_definite(d: &DMatrix<f64>) -> Check {
    let eig = d.clone().symmetric_eigenvalues();
    let error = match d.clone().cholesky() {
        Some(_) if eig.min() > 0.0 => eig.max() / eig.min() / 1e12,
        _ => f64::INFINITY,
    };
    Check {
        name: "D positive definite",
        error,
        tolerance: 1.0,
    }
}

/// The checks of one state, each with the tolerance of its kind.
#[derive(Default)]
struct Checks(Vec<Check>);

type M = DMatrix<f64>;

impl Checks {
    fn differenced(&mut self, name: &'static str, actual: &M, expected: &M, natural: f64) {
        self.0
            .push(compare(name, actual, expected, natural, tolerance::DIFFERENCED));
    }
    fn lagrangian(&mut self, name: &'static str, actual: &M, expected: &M, natural: f64) {
        self.0
            .push(compare(name, actual, expected, natural, tolerance::LAGRANGIAN));
    }
    fn identity(&mut self, name: &'static str, actual: &M, expected: &M, natural: f64) {
        self.0
            .push(compare(name, actual, expected, natural, tolerance::IDENTITY));
    }
}

/// Runs every oracle on `dynamics` (the subject) for `model` at `state`.
pub fn check_all(model: &Model, dynamics: &impl Dynamics, state: &JointState) -> Vec<Check> {
    let JointState { q, qd, qdd, v, a } = state;
    let energies = Energies::new(model);
    let s = Natural::new(model, &energies, dynamics, state);
    let column = |x: &[f64]| DMatrix::from_column_slice(x.len(), 1, x);
    let zero = vec![0.0; q.len()];
    let mut out = Checks::default();

    // 1. J against the differenced pose; 2. J̇ against the differenced J.
    let (jac, jac_dot) = (dynamics.jacobian(q), dynamics.jacobian_dot(q, qd));
    let jac_fd = jacobian_from_pose(|x| dynamics.end_effector_pose(x), q);
    out.differenced("J = ∂fk/∂q", &jac, &jac_fd, s.length);
    let jac_dot_fd = jacobian_rate(|x| dynamics.jacobian(x), q, qd);
    out.differenced("J̇ = dJ/dt", &jac_dot, &jac_dot_fd, s.pose_rate);

    // 3. g against the gradient of the potential energy.
    let g = column(dynamics.gravity_torque(q).as_slice());
    let grad_v = column(gradient(|x| energies.potential(x), q).as_slice());
    out.differenced("g = ∂V/∂q", &g, &grad_v, s.gravity_force);

    // 4. The Lagrangian: D, C q̇, g and τ from the energies alone.
    let d = dynamics.mass_matrix(q);
    let c = dynamics.coriolis_matrix(q, qd);
    let c_qd = &c * column(qd);
    let tau = column(dynamics.inverse_dynamics(q, qd, qdd).as_slice());
    let lag = energies.lagrangian(q, qd, qdd);
    let [lag_c_qd, lag_g, lag_tau] = [&lag.c_qd, &lag.g, &lag.tau].map(|x| column(x.as_slice()));
    out.lagrangian("Lagrange: D = ∂²T/∂q̇²", &d, &lag.d, s.inertia);
    out.lagrangian("Lagrange: C q̇", &c_qd, &lag_c_qd, s.velocity_force);
    out.lagrangian("Lagrange: g", &g, &lag_g, s.gravity_force);
    out.lagrangian("Lagrange: τ = ID(q, q̇, q̈)", &tau, &lag_tau, s.force);

    // 5. C against the Christoffel symbols of the differenced D; C + Cᵀ = Ḋ.
    let mass = |x: &[f64]| dynamics.mass_matrix(x);
    let christoffel = christoffel_coriolis(mass, q, qd);
    out.differenced("C = Christoffel(∂D/∂q)", &c, &christoffel, s.coriolis);
    let (c_plus_ct, d_dot) = (&c + c.transpose(), mass_matrix_rate(mass, q, qd));
    out.differenced("C + Cᵀ = Ḋ", &c_plus_ct, &d_dot, s.coriolis);

    // 6. Y θ = D a + C v + g, and Y from the inverse-dynamics regressor with and without gravity.
    let y = dynamics.regressor(q, qd, v, a);
    let dacvg = &d * column(a) + &c * column(v) + &g;
    let y_theta = &y * column(&model.parameters());
    out.identity("Y θ = D a + C v + g", &y_theta, &dacvg, s.force);
    let qd_plus_v: Vec<f64> = qd.iter().zip(v).map(|(x, y)| x + y).collect();
    let y_id0 = |x: &[f64]| dynamics.weightless_regressor(q, x, x, &zero);
    let y_idg = dynamics.regressor(q, &zero, &zero, a);
    let y_id = y_idg + (y_id0(&qd_plus_v) - y_id0(qd) - y_id0(v)) * 0.5;
    out.identity("Y = Y_id,g(0, a) + ½[Y_id,0 …]", &y, &y_id, s.per_parameter);

    // 7. D symmetric positive definite.
    out.identity("D symmetric", &d.transpose(), &d, s.inertia);
    out.0.push(positive_definite(&d));

    // 8. Slotine–Li and inverse dynamics agree; C q̇ = ID(q, q̇, 0) − g. Rounding in these is
    // relative to the forces, gravity included.
    let sl = |v: &[f64], a: &[f64], g: bool| column(dynamics.slotine_li(q, qd, v, a, g).as_slice());
    let (sl_id, sl_ref, sl_ref_0) = (sl(qd, qdd, true), sl(v, a, true), sl(v, a, false));
    out.identity("Slotine–Li(v=q̇, a=q̈) = τ", &sl_id, &tau, s.force);
    let id_0 = column(dynamics.inverse_dynamics(q, qd, &zero).as_slice()) - &g;
    out.identity("C q̇ = ID(q, q̇, 0) − g", &c_qd, &id_0, s.force);
    out.identity("Slotine–Li = D a + C v + g", &sl_ref, &dacvg, s.force);
    let dacv = &dacvg - &g;
    out.identity("Slotine–Li, g off = D a + C v", &sl_ref_0, &dacv, s.force);
    out.0
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
