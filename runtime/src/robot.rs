//! The traits generated robots implement.

use crate::joint::{JointLimits, JointTrig};
use crate::parameter::ParameterKind;
use crate::ResultBuffer;
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// A rigid placement of a child frame in a parent frame: a point `p` of the child frame is
/// `rotation · p + translation` in the parent (the base frame, for generated kinematics).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    pub rotation: Matrix3<f64>,
    pub translation: Vector3<f64>,
}

impl Default for Pose {
    fn default() -> Self {
        Pose::identity()
    }
}

impl Pose {
    pub fn identity() -> Pose {
        Pose {
            rotation: Matrix3::identity(),
            translation: Vector3::zeros(),
        }
    }

    /// `self ∘ other`: `other` is given in the frame that `self` places.
    pub fn compose(&self, other: &Pose) -> Pose {
        Pose {
            rotation: self.rotation * other.rotation,
            translation: self.rotation * other.translation + self.translation,
        }
    }

    pub fn transform_point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.rotation * p + self.translation
    }
}

/// The kinematics of one robot with `N` moving joints: what a task-space controller needs, and
/// what does not depend on the inertial parameters.
///
/// `J` is the 6×N geometric Jacobian of the end-effector frame origin, rows `[linear; angular]`
/// in base axes (Pinocchio's `LOCAL_WORLD_ALIGNED`).
pub trait Kinematics<const N: usize> {
    /// Robot name from its description.
    const NAME: &'static str;
    /// Joint names, in the order of `q`.
    const JOINT_NAMES: [&'static str; N];
    /// Joint limits from the description, in the order of `q`.
    const JOINT_LIMITS: [JointLimits; N];
    /// Index of the body (= of its joint) that carries the end-effector frame.
    const END_EFFECTOR_BODY: usize;

    /// End-effector pose in the base frame.
    fn forward_kinematics(t: &JointTrig<N>) -> Pose;
    /// End-effector geometric Jacobian `J(q)`.
    fn jacobian(t: &JointTrig<N>) -> SMatrix<f64, 6, N>;
    /// Its time derivative `J̇(q, q̇)`.
    fn jacobian_dot(t: &JointTrig<N>, qd: &SVector<f64, N>) -> SMatrix<f64, 6, N>;
    /// The three at once, `(pose, J, J̇)`, as a control tick needs them: generated robots
    /// compute the joint transforms and body poses they share once.
    fn kinematics(t: &JointTrig<N>, qd: &SVector<f64, N>) -> (Pose, SMatrix<f64, 6, N>, SMatrix<f64, 6, N>) {
        (
            Self::forward_kinematics(t),
            Self::jacobian(t),
            Self::jacobian_dot(t, qd),
        )
    }
}

/// Rigid-body dynamics of one robot with `N` joints and `P` standard parameters.
///
/// Conventions: `C` is the Christoffel-consistent Coriolis matrix, so `Ḋ − 2C` is
/// skew-symmetric; `θ = Self::parameters()` holds ten parameters per body `[m, m·cx, m·cy,
/// m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]` about the joint frame origin, then the joint-level
/// parameters the description chose.
///
/// Every generated robot implements this trait and [`Kinematics`]; the others
/// ([`Regressors`], [`ForwardDynamics`], [`DynamicsDerivatives`],
/// [`BaseParameters`](crate::BaseParameters), [`LaneDynamics`](crate::LaneDynamics)) exist
/// when the description chose their group of functions.
pub trait RobotDynamics<const N: usize, const P: usize>: Kinematics<N> {
    /// Names of the entries of θ, e.g. `"mcx[link3]"`.
    const PARAMETER_NAMES: [&'static str; P];
    /// The kind of each entry of θ.
    const PARAMETER_KINDS: [ParameterKind; P];

    /// The standard parameters θ of the description.
    fn parameters() -> SVector<f64, P>;
    /// Joint-space mass matrix `D(q)`.
    fn mass_matrix(t: &JointTrig<N>) -> SMatrix<f64, N, N>;
    /// [`Self::mass_matrix`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn mass_matrix_into(t: &JointTrig<N>, out: &mut ResultBuffer<SMatrix<f64, N, N>>) {
        out.replace(Self::mass_matrix(t));
    }
    /// Christoffel-consistent Coriolis matrix `C(q, q̇)`.
    fn coriolis_matrix(t: &JointTrig<N>, qd: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// [`Self::coriolis_matrix`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn coriolis_matrix_into(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        out: &mut ResultBuffer<SMatrix<f64, N, N>>,
    ) {
        out.replace(Self::coriolis_matrix(t, qd));
    }
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
}

/// The regressor of the standard parameters: `Y(q, q̇, v, a) θ = D a + C v + g`, the functions
/// of the group `regressors`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `regressors`",
    note = "add `regressors` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait Regressors<const N: usize, const P: usize>: RobotDynamics<N, P> {
    /// Slotine–Li regressor `Y(q, q̇, v, a)` with `Y θ = D a + C v + g`.
    fn regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, P>;
    /// [`Self::regressor`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn regressor_into(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
        out: &mut ResultBuffer<SMatrix<f64, N, P>>,
    ) {
        out.replace(Self::regressor(t, qd, v, a));
    }
    /// `(Y θ, Yᵀ r)` with `Y = Y(q, q̇, v, a)`: what an adaptive law needs each tick (the
    /// torque `Y θ̂` and the adaptation's `Yᵀ r`). Generated robots compute both without
    /// forming `Y`: one force per column and no carrying of it up the tree.
    fn regressor_products(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
        theta: &SVector<f64, P>,
        r: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, P>) {
        products_of(&Self::regressor(t, qd, v, a), theta, r)
    }
    /// The regressor in torque form, `Y(q, q̇, q̇, q̈)` with `Y θ = τ` (what identification
    /// stacks). Generated robots emit it as its own function, smaller than [`Self::regressor`]:
    /// at `v = q̇` each body force takes the classical `v ×* I v` form.
    fn torque_regressor(t: &JointTrig<N>, qd: &SVector<f64, N>, qdd: &SVector<f64, N>) -> SMatrix<f64, N, P> {
        Self::regressor(t, qd, qd, qdd)
    }
    /// [`Self::torque_regressor`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn torque_regressor_into(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
        out: &mut ResultBuffer<SMatrix<f64, N, P>>,
    ) {
        out.replace(Self::torque_regressor(t, qd, qdd));
    }
}

/// Forward dynamics and the inverse mass matrix: the group `forward_dynamics`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `forward_dynamics`",
    note = "add `forward_dynamics` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait ForwardDynamics<const N: usize, const P: usize>: RobotDynamics<N, P> {
    /// Forward dynamics `q̈ = D⁻¹ (τ − C q̇ − g)`.
    fn forward_dynamics(t: &JointTrig<N>, qd: &SVector<f64, N>, tau: &SVector<f64, N>) -> SVector<f64, N>;
    /// The inverse mass matrix `D(q)⁻¹`.
    fn mass_matrix_inverse(t: &JointTrig<N>) -> SMatrix<f64, N, N>;
    /// [`Self::mass_matrix_inverse`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn mass_matrix_inverse_into(t: &JointTrig<N>, out: &mut ResultBuffer<SMatrix<f64, N, N>>) {
        out.replace(Self::mass_matrix_inverse(t));
    }
}

/// The derivatives of inverse and forward dynamics with respect to the state: the group
/// `derivatives`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `derivatives`",
    note = "add `derivatives` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait DynamicsDerivatives<const N: usize, const P: usize>: RobotDynamics<N, P> {
    /// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics at `(q, q̇, q̈)`; entry `(i, j)` is `∂τ_i/∂x_j`
    /// (`∂τ/∂q̈ = D`).
    fn inverse_dynamics_derivatives(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
    ) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>);
    /// [`Self::inverse_dynamics_derivatives`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn inverse_dynamics_derivatives_into(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
        out: &mut ResultBuffer<(SMatrix<f64, N, N>, SMatrix<f64, N, N>)>,
    ) {
        out.replace(Self::inverse_dynamics_derivatives(t, qd, qdd));
    }
    /// `(∂q̈/∂q, ∂q̈/∂q̇)` of forward dynamics at `(q, q̇, τ)` (`∂q̈/∂τ = D⁻¹`).
    fn forward_dynamics_derivatives(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>);
    /// [`Self::forward_dynamics_derivatives`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn forward_dynamics_derivatives_into(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        tau: &SVector<f64, N>,
        out: &mut ResultBuffer<(SMatrix<f64, N, N>, SMatrix<f64, N, N>)>,
    ) {
        out.replace(Self::forward_dynamics_derivatives(t, qd, tau));
    }
}

/// `(Y θ, Yᵀ r)` of a regressor already formed: what the products default to where a robot's
/// code does not compute them without `Y`.
pub(crate) fn products_of<const N: usize, const M: usize>(
    y: &SMatrix<f64, N, M>,
    theta: &SVector<f64, M>,
    r: &SVector<f64, N>,
) -> (SVector<f64, N>, SVector<f64, M>) {
    (y * theta, y.tr_mul(r))
}
