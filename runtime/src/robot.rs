//! The interface between generated dynamics and everything that uses them.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Joint positions with their sines and cosines, computed once per control tick and shared by
/// every quantity (they are a large share of the cost of kinematics and gravity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JointTrig<const N: usize> {
    pub q: [f64; N],
    pub sin: [f64; N],
    pub cos: [f64; N],
}

impl<const N: usize> JointTrig<N> {
    pub fn new(q: &SVector<f64, N>) -> Self {
        let q: [f64; N] = q.data.0[0];
        // One range reduction for both: a third cheaper than separate `sin` and `cos`, and
        // sines and cosines are most of the cost of kinematics and gravity.
        let both = q.map(libm::sincos);
        JointTrig {
            q,
            sin: both.map(|(s, _)| s),
            cos: both.map(|(_, c)| c),
        }
    }
}

/// A rigid placement in the base frame: `p_base = rotation · p + translation`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub rotation: Matrix3<f64>,
    pub translation: Vector3<f64>,
}

/// Rigid-body dynamics of one robot with `N` joints and `P` standard inertial parameters.
///
/// Conventions: `J` is the 6×N geometric Jacobian of the end-effector frame origin, rows
/// `[linear; angular]` in base axes (Pinocchio's `LOCAL_WORLD_ALIGNED`); `C` is the
/// Christoffel-consistent Coriolis matrix, so `Ḋ − 2C` is skew-symmetric; the regressor
/// satisfies `Y(q, q̇, v, a) θ = D a + C v + g` with `θ = Self::parameters()`, ten parameters
/// per body `[m, m·cx, m·cy, m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]` about the joint frame origin.
pub trait RobotDynamics<const N: usize, const P: usize> {
    /// Robot name from its description.
    const NAME: &'static str;
    /// Joint names, in the order of `q`.
    const JOINT_NAMES: [&'static str; N];
    /// Names of the entries of θ, e.g. `"mcx[link3]"`.
    const PARAMETER_NAMES: [&'static str; P];

    /// The standard inertial parameters θ of the description.
    fn parameters() -> SVector<f64, P>;
    /// End-effector pose in the base frame.
    fn forward_kinematics(t: &JointTrig<N>) -> Pose;
    /// End-effector geometric Jacobian `J(q)`.
    fn jacobian(t: &JointTrig<N>) -> SMatrix<f64, 6, N>;
    /// Its time derivative `J̇(q, q̇)`.
    fn jacobian_dot(t: &JointTrig<N>, qd: &SVector<f64, N>) -> SMatrix<f64, 6, N>;
    /// Joint-space inertia matrix `D(q)`.
    fn mass_matrix(t: &JointTrig<N>) -> SMatrix<f64, N, N>;
    /// Christoffel-consistent Coriolis matrix `C(q, q̇)`.
    fn coriolis_matrix(t: &JointTrig<N>, qd: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// Generalized gravity `g(q)`.
    fn gravity(t: &JointTrig<N>) -> SVector<f64, N>;
    /// Inverse dynamics `τ = D q̈ + C q̇ + g`.
    fn inverse_dynamics(t: &JointTrig<N>, qd: &SVector<f64, N>, qdd: &SVector<f64, N>) -> SVector<f64, N>;
    /// Slotine–Li torque `D a + C v + g` at the reference velocity `v` and acceleration `a`.
    fn slotine_li(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SVector<f64, N>;
    /// Slotine–Li regressor `Y(q, q̇, v, a)` with `Y θ = D a + C v + g`.
    fn regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, P>;
    /// Forward dynamics `q̈ = D⁻¹ (τ − C q̇ − g)`.
    fn forward_dynamics(t: &JointTrig<N>, qd: &SVector<f64, N>, tau: &SVector<f64, N>) -> SVector<f64, N>;
    /// The inverse inertia matrix `D(q)⁻¹`.
    fn mass_matrix_inverse(t: &JointTrig<N>) -> SMatrix<f64, N, N>;
    /// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics at `(q, q̇, q̈)`; entry `(i, j)` is `∂τ_i/∂x_j`
    /// (`∂τ/∂q̈ = D`).
    fn inverse_dynamics_derivatives(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
    ) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>);
    /// `(∂q̈/∂q, ∂q̈/∂q̇)` of forward dynamics at `(q, q̇, τ)` (`∂q̈/∂τ = D⁻¹`).
    fn forward_dynamics_derivatives(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>);
}
