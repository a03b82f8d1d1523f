//! The traits a generated floating-base robot implements, and the configuration its functions
//! take: the base pose with the joints' sines and cosines, computed once per tick.
//!
//! Layout (Pinocchio's `JointModelFreeFlyer`): `q = [x, y, z, qx, qy, qz, qw, q_joints…]`
//! (`NQ = N + 7`), `ν = [v; ω; q̇]` with the base twist in the base frame (`NV = N + 6`); the
//! first six entries of a generalised force are the base wrench `[f; n]` in the base frame,
//! about its origin. Generated modules name the sizes (`DOF`, `NV`, `NQ`) and the types
//! (`Configuration`, `Velocity`, `MassMatrix`, …).

use crate::floating::{BasePose, NonUnitQuaternion};
use crate::frames::{ReferenceFrame, RobotFrame};
use crate::joint::{JointLimits, JointTrig};
use crate::robot::Pose;
use crate::ResultBuffer;
use nalgebra::{SMatrix, SVector, Vector3};

/// Why a configuration vector was refused ([`FloatingTrig::from_configuration`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConfigurationError {
    /// `q` does not have `N + 7` entries.
    Length { expected: usize, found: usize },
    /// The base quaternion is not a unit quaternion.
    NonUnitQuaternion(NonUnitQuaternion),
}

impl core::fmt::Display for ConfigurationError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ConfigurationError::Length { expected, found } => write!(
                f,
                "a floating-base configuration has {expected} entries (base position, quaternion x y z w, joints), not {found}"
            ),
            ConfigurationError::NonUnitQuaternion(e) => e.fmt(f),
        }
    }
}

/// A floating-base configuration prepared for generated functions: the base pose (its rotation
/// matrix from the quaternion) and the joints' sines and cosines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FloatingTrig<const N: usize> {
    pub base: BasePose,
    pub joints: JointTrig<N>,
}

impl<const N: usize> FloatingTrig<N> {
    /// The base at `base`, the joints at `q`.
    pub fn new(base: BasePose, q: &SVector<f64, N>) -> Self {
        FloatingTrig {
            base,
            joints: JointTrig::new(q),
        }
    }

    /// From a configuration in Pinocchio's layout (`N + 7` entries), checked.
    pub fn from_configuration(q: &[f64]) -> Result<Self, ConfigurationError> {
        if q.len() != N + 7 {
            return Err(ConfigurationError::Length {
                expected: N + 7,
                found: q.len(),
            });
        }
        let base = BasePose::from_configuration(q).map_err(ConfigurationError::NonUnitQuaternion)?;
        let Ok(joints) = <&[f64; N]>::try_from(&q[7..]) else {
            unreachable!("the length was checked")
        };
        Ok(FloatingTrig {
            base,
            joints: crate::trig::joint_trig(joints),
        })
    }
}

/// Rigid-body dynamics of a robot on a free-flying base: `N` joints, `NV = N + 6` velocity
/// coordinates, `P = 10 (N + 1)` inertial parameters (the base body's ten first).
///
/// `C` satisfies `Ḋ = C + Cᵀ` (with the base twist in the base frame it is not the matrix of
/// Christoffel symbols of `D`, whose base rows miss the twist's own terms; it is Pinocchio's).
pub trait FloatingBaseDynamics<const N: usize, const NV: usize, const P: usize> {
    /// Robot name from its description.
    const NAME: &'static str;
    /// Names of the moving joints, in the order of `q` after the base's seven entries.
    const JOINT_NAMES: [&'static str; N];
    /// Joint limits from the description.
    const JOINT_LIMITS: [JointLimits; N];
    /// Names of the entries of θ, e.g. `"mcx[trunk]"`.
    const PARAMETER_NAMES: [&'static str; P];

    /// The standard parameters θ of the description: the base body's ten, then ten per body.
    fn parameters() -> SVector<f64, P>;
    /// The mass matrix `D(q)` (`NV × NV`).
    fn mass_matrix(t: &FloatingTrig<N>) -> SMatrix<f64, NV, NV>;
    /// [`Self::mass_matrix`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn mass_matrix_into(t: &FloatingTrig<N>, out: &mut ResultBuffer<SMatrix<f64, NV, NV>>) {
        out.replace(Self::mass_matrix(t));
    }
    /// The Coriolis matrix `C(q, ν)`.
    fn coriolis_matrix(t: &FloatingTrig<N>, v: &SVector<f64, NV>) -> SMatrix<f64, NV, NV>;
    /// [`Self::coriolis_matrix`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn coriolis_matrix_into(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        out: &mut ResultBuffer<SMatrix<f64, NV, NV>>,
    ) {
        out.replace(Self::coriolis_matrix(t, v));
    }
    /// The generalised gravity `g(q)`: the base rows hold the weight of the whole robot.
    fn gravity(t: &FloatingTrig<N>) -> SVector<f64, NV>;
    /// Inverse dynamics `D ν̇ + C ν + g`: the base wrench, then the joint torques.
    fn inverse_dynamics(t: &FloatingTrig<N>, v: &SVector<f64, NV>, a: &SVector<f64, NV>) -> SVector<f64, NV>;
    /// The Slotine–Li torque `D a_r + C(q, ν) v_r + g`.
    fn slotine_li(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        vr: &SVector<f64, NV>,
        ar: &SVector<f64, NV>,
    ) -> SVector<f64, NV>;
    /// The centre of mass in the world.
    fn center_of_mass(t: &FloatingTrig<N>) -> Vector3<f64>;
    /// The centroidal momentum matrix `A_g(q)` (`6 × NV`): `A_g ν` is the linear momentum and
    /// the angular momentum about the centre of mass, in world axes (Pinocchio's `ccrba`).
    fn centroidal_momentum_matrix(t: &FloatingTrig<N>) -> SMatrix<f64, 6, NV>;
    /// `Ȧ_g(q, ν) ν`, the rate of the centroidal momentum at zero acceleration.
    fn centroidal_bias(t: &FloatingTrig<N>, v: &SVector<f64, NV>) -> SVector<f64, 6>;
}

/// The regressors of a floating-base robot: `Y θ` is the Slotine–Li torque or inverse dynamics,
/// base wrench first (the group `regressors`).
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `regressors`",
    note = "add `regressors` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait FloatingRegressors<const N: usize, const NV: usize, const P: usize>:
    FloatingBaseDynamics<N, NV, P>
{
    /// The regressor `Y(q, ν, v_r, a_r)` with `Y θ` the Slotine–Li torque.
    fn regressor(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        vr: &SVector<f64, NV>,
        ar: &SVector<f64, NV>,
    ) -> SMatrix<f64, NV, P>;
    /// [`Self::regressor`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn regressor_into(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        vr: &SVector<f64, NV>,
        ar: &SVector<f64, NV>,
        out: &mut ResultBuffer<SMatrix<f64, NV, P>>,
    ) {
        out.replace(Self::regressor(t, v, vr, ar));
    }
    /// The regressor in torque form, `Y(q, ν, ν, ν̇)` with `Y θ` inverse dynamics (what
    /// identification stacks), smaller than [`Self::regressor`].
    fn torque_regressor(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> SMatrix<f64, NV, P>;
    /// [`Self::torque_regressor`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn torque_regressor_into(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
        out: &mut ResultBuffer<SMatrix<f64, NV, P>>,
    ) {
        out.replace(Self::torque_regressor(t, v, a));
    }
}

/// Forward dynamics of a floating-base robot and its inverse mass matrix (the group
/// `forward_dynamics`).
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `forward_dynamics`",
    note = "add `forward_dynamics` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait FloatingForwardDynamics<const N: usize, const NV: usize, const P: usize>:
    FloatingBaseDynamics<N, NV, P>
{
    /// Forward dynamics `ν̇ = D⁻¹ (τ − C ν − g)`, `tau` the base wrench and joint torques.
    fn forward_dynamics(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        tau: &SVector<f64, NV>,
    ) -> SVector<f64, NV>;
    /// `D(q)⁻¹`.
    fn mass_matrix_inverse(t: &FloatingTrig<N>) -> SMatrix<f64, NV, NV>;
    /// [`Self::mass_matrix_inverse`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn mass_matrix_inverse_into(t: &FloatingTrig<N>, out: &mut ResultBuffer<SMatrix<f64, NV, NV>>) {
        out.replace(Self::mass_matrix_inverse(t));
    }
}

/// The base (minimal, identifiable) parameters of a floating-base robot: `B` combinations of
/// the standard ones that span every base wrench and joint torque it can produce. A floating
/// base makes more of them identifiable than a fixed one: the base body's ten, and every body's
/// mass through the base rows.
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `base_parameters`",
    note = "add `base_parameters` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait FloatingBaseParameters<const N: usize, const NV: usize, const P: usize, const B: usize>:
    FloatingRegressors<N, NV, P>
{
    /// Readable names that show what each base parameter combines.
    const BASE_PARAMETER_NAMES: [&'static str; B];
    /// `θ_b = Φ θ`, a constant linear map fixed by the kinematics.
    fn base_parameters(theta: &SVector<f64, P>) -> SVector<f64, B>;
    /// `Y_b(q, ν, v_r, a_r)` with `Y_b θ_b = Y θ`, the Slotine–Li torque.
    fn base_regressor(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        vr: &SVector<f64, NV>,
        ar: &SVector<f64, NV>,
    ) -> SMatrix<f64, NV, B>;
    /// [`Self::base_regressor`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn base_regressor_into(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        vr: &SVector<f64, NV>,
        ar: &SVector<f64, NV>,
        out: &mut ResultBuffer<SMatrix<f64, NV, B>>,
    ) {
        out.replace(Self::base_regressor(t, v, vr, ar));
    }
    /// `Y_b(q, ν, ν, ν̇)` with `Y_b θ_b` inverse dynamics: what identification stacks.
    fn base_torque_regressor(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> SMatrix<f64, NV, B>;
    /// [`Self::base_torque_regressor`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn base_torque_regressor_into(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
        out: &mut ResultBuffer<SMatrix<f64, NV, B>>,
    ) {
        out.replace(Self::base_torque_regressor(t, v, a));
    }
}

/// The derivatives of a floating-base robot's inverse and forward dynamics in the tangent
/// space, in Pinocchio's layout: column `c` is the derivative along `q ⊕ e_c` (the base
/// translation's three, the base rotation's three in the base frame, then the joints) or along
/// `ν`'s entry `c`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `derivatives`",
    note = "add `derivatives` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait FloatingDynamicsDerivatives<const N: usize, const NV: usize, const P: usize>:
    FloatingBaseDynamics<N, NV, P>
{
    /// `(∂τ/∂q, ∂τ/∂ν)` of inverse dynamics at `(q, ν, ν̇)` (`∂τ/∂ν̇ = D`); the base
    /// translation's columns of `∂τ/∂q` are zero.
    fn inverse_dynamics_derivatives(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> (SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>);
    /// [`Self::inverse_dynamics_derivatives`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn inverse_dynamics_derivatives_into(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
        out: &mut ResultBuffer<(SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>)>,
    ) {
        out.replace(Self::inverse_dynamics_derivatives(t, v, a));
    }
    /// `(∂ν̇/∂q, ∂ν̇/∂ν)` of forward dynamics at `(q, ν, τ)` (`∂ν̇/∂τ = D⁻¹`).
    fn forward_dynamics_derivatives(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        tau: &SVector<f64, NV>,
    ) -> (SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>);
    /// [`Self::forward_dynamics_derivatives`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn forward_dynamics_derivatives_into(
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        tau: &SVector<f64, NV>,
        out: &mut ResultBuffer<(SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>)>,
    ) {
        out.replace(Self::forward_dynamics_derivatives(t, v, tau));
    }
}

/// Any named frame of a floating-base robot (feet, hands, sensors), in the world, in any
/// [`ReferenceFrame`]; `J` is `6 × NV`, its first six columns the base's.
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `frames`",
    note = "add `frames` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait FloatingFrameKinematics<const N: usize, const NV: usize> {
    /// The robot's frame enum.
    type Frame: RobotFrame;
    /// The frame's pose in the world.
    fn frame_pose(frame: Self::Frame, t: &FloatingTrig<N>) -> Pose;
    /// The frame's Jacobian in `reference`.
    fn frame_jacobian(
        frame: Self::Frame,
        reference: ReferenceFrame,
        t: &FloatingTrig<N>,
    ) -> SMatrix<f64, 6, NV>;
    /// Its time derivative along `ν`.
    fn frame_jacobian_time_variation(
        frame: Self::Frame,
        reference: ReferenceFrame,
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
    ) -> SMatrix<f64, 6, NV>;
    /// The frame's velocity `J ν`, `[linear; angular]`.
    fn frame_velocity(
        frame: Self::Frame,
        reference: ReferenceFrame,
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
    ) -> SVector<f64, 6>;
    /// The frame's classical acceleration at `ν̇ = a`.
    fn frame_classical_acceleration(
        frame: Self::Frame,
        reference: ReferenceFrame,
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> SVector<f64, 6>;
    /// `(pose, J, J̇)` in `LOCAL_WORLD_ALIGNED`, sharing what the three compute.
    fn frame_kinematics(
        frame: Self::Frame,
        t: &FloatingTrig<N>,
        v: &SVector<f64, NV>,
    ) -> (Pose, SMatrix<f64, 6, NV>, SMatrix<f64, 6, NV>);
}
