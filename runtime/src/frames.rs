//! Named frames: the kinematics of any frame a description names (the group `frames`), and the
//! external wrenches applied at them.

use crate::robot::{ForwardDynamics, Kinematics, Pose, RobotDynamics};
use crate::JointTrig;
use nalgebra::{SMatrix, SVector, Vector3, Vector6};

/// How a frame's velocity, acceleration, Jacobian or an applied wrench is expressed; the three
/// conventions of Pinocchio's `ReferenceFrame`, with the same meaning. Six-vectors are
/// `[linear; angular]` (motions) and `[force; moment]` (wrenches).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ReferenceFrame {
    /// In the frame's own axes, at its origin: the body velocity.
    Local,
    /// In base axes, at the base origin: the spatial velocity (the linear part is the velocity
    /// of the body point that passes through the base origin).
    World,
    /// In base axes, at the frame's origin: the linear part is the velocity of the frame's
    /// origin. What [`Kinematics::jacobian`] gives for the end-effector.
    LocalWorldAligned,
}

impl ReferenceFrame {
    /// All three, in declaration order.
    pub const ALL: [ReferenceFrame; 3] = [
        ReferenceFrame::Local,
        ReferenceFrame::World,
        ReferenceFrame::LocalWorldAligned,
    ];

    /// `local`, `world`, `local_world_aligned`.
    pub fn keyword(self) -> &'static str {
        match self {
            ReferenceFrame::Local => "local",
            ReferenceFrame::World => "world",
            ReferenceFrame::LocalWorldAligned => "local_world_aligned",
        }
    }
}

/// The frames of one generated robot: an enum with one variant per frame, the end-effector
/// first (generated as `Frame` in the robot's module).
pub trait RobotFrame: Copy + Eq + core::fmt::Debug + 'static {
    /// Every frame, the end-effector first.
    const ALL: &'static [Self];
    /// The frame's name in the description.
    fn name(self) -> &'static str;
    /// The frame named `name`, if the robot was generated with it.
    fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|f| f.name() == name)
    }
}

/// A wrench that the environment applies to the robot at a frame: `[force; moment]`, the
/// moment about the point that `reference` names (the frame's origin for
/// [`ReferenceFrame::Local`] and [`ReferenceFrame::LocalWorldAligned`], the base origin for
/// [`ReferenceFrame::World`]). A contact force the robot exerts on the environment is its
/// negative.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExternalWrench<F> {
    pub frame: F,
    pub reference: ReferenceFrame,
    pub force: Vector3<f64>,
    pub moment: Vector3<f64>,
}

impl<F> ExternalWrench<F> {
    /// A pure force `force` at the origin of `frame`, in base axes.
    pub fn force_at(frame: F, force: Vector3<f64>) -> Self {
        ExternalWrench {
            frame,
            reference: ReferenceFrame::LocalWorldAligned,
            force,
            moment: Vector3::zeros(),
        }
    }

    /// `[force; moment]` as one six-vector.
    pub fn vector(&self) -> Vector6<f64> {
        let (f, m) = (self.force, self.moment);
        Vector6::new(f.x, f.y, f.z, m.x, m.y, m.z)
    }
}

/// The kinematics of every frame the description named (the group `frames`): pose, Jacobian
/// and its time derivative, velocity and classical acceleration, each in the
/// [`ReferenceFrame`] asked for, with Pinocchio's definitions (`getFramePlacement`,
/// `getFrameJacobian`, `getFrameJacobianTimeVariation`, `getFrameVelocity`,
/// `getFrameClassicalAcceleration`). Each frame and convention is its own straight-line
/// function; these methods choose it with a `match`.
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `frames`",
    note = "add `frames` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait FrameKinematics<const N: usize>: Kinematics<N> {
    /// The robot's frames (the generated `Frame` enum).
    type Frame: RobotFrame;

    /// The frame's pose in the base frame.
    fn frame_pose(frame: Self::Frame, t: &JointTrig<N>) -> Pose;
    /// The frame's Jacobian `J` (6×N, rows `[linear; angular]`): its velocity is `J q̇`.
    fn frame_jacobian(frame: Self::Frame, reference: ReferenceFrame, t: &JointTrig<N>) -> SMatrix<f64, 6, N>;
    /// `J̇(q, q̇)`, the time derivative of [`Self::frame_jacobian`] in the same convention.
    fn frame_jacobian_time_variation(
        frame: Self::Frame,
        reference: ReferenceFrame,
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
    ) -> SMatrix<f64, 6, N>;
    /// The frame's velocity `J q̇`, `[linear; angular]`.
    fn frame_velocity(
        frame: Self::Frame,
        reference: ReferenceFrame,
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
    ) -> Vector6<f64>;
    /// The frame's classical acceleration: the spatial acceleration `J q̈ + J̇ q̇` with `ω × v`
    /// added to its linear part, so that with [`ReferenceFrame::LocalWorldAligned`] it is the
    /// acceleration of the frame's origin, `d²p/dt²`, and the angular acceleration.
    fn frame_classical_acceleration(
        frame: Self::Frame,
        reference: ReferenceFrame,
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
    ) -> Vector6<f64>;
    /// `(pose, J, J̇)` of one frame in [`ReferenceFrame::LocalWorldAligned`], computed together
    /// as [`Kinematics::kinematics`] does for the end-effector: what a task-space controller
    /// of that frame needs each tick.
    fn frame_kinematics(
        frame: Self::Frame,
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
    ) -> (Pose, SMatrix<f64, 6, N>, SMatrix<f64, 6, N>);

    /// The joint torques `Σ Jₖᵀ wₖ` that external wrenches produce, each through its frame's
    /// Jacobian in the wrench's reference frame.
    fn wrench_torques(t: &JointTrig<N>, wrenches: &[ExternalWrench<Self::Frame>]) -> SVector<f64, N> {
        let mut tau = SVector::zeros();
        for w in wrenches {
            tau += Self::frame_jacobian(w.frame, w.reference, t).tr_mul(&w.vector());
        }
        tau
    }
}

/// Dynamics with external wrenches at named frames: `D q̈ + C q̇ + g = τ + Σ Jₖᵀ wₖ`. Every
/// robot generated with the groups `dynamics` and `frames` has it.
pub trait WrenchDynamics<const N: usize, const P: usize>: FrameKinematics<N> + RobotDynamics<N, P> {
    /// The joint torques that produce `q̈` while the wrenches act: Pinocchio's
    /// `rnea(model, data, q, v, a, fext)`.
    fn inverse_dynamics_with_wrenches(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
        wrenches: &[ExternalWrench<Self::Frame>],
    ) -> SVector<f64, N> {
        Self::inverse_dynamics(t, qd, qdd) - Self::wrench_torques(t, wrenches)
    }

    /// The Slotine–Li torque `D a + C v + g − Σ Jₖᵀ wₖ`: an adaptive law's model torque that
    /// compensates known or measured wrenches.
    fn slotine_li_with_wrenches(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
        wrenches: &[ExternalWrench<Self::Frame>],
    ) -> SVector<f64, N> {
        Self::slotine_li(t, qd, v, a) - Self::wrench_torques(t, wrenches)
    }

    /// Forward dynamics while the wrenches act: `q̈ = D⁻¹ (τ + Σ Jₖᵀ wₖ − C q̇ − g)`,
    /// Pinocchio's `aba(model, data, q, v, tau, fext)`.
    fn forward_dynamics_with_wrenches(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        tau: &SVector<f64, N>,
        wrenches: &[ExternalWrench<Self::Frame>],
    ) -> SVector<f64, N>
    where
        Self: ForwardDynamics<N, P>,
    {
        Self::forward_dynamics(t, qd, &(tau + Self::wrench_torques(t, wrenches)))
    }
}

impl<R, const N: usize, const P: usize> WrenchDynamics<N, P> for R where
    R: FrameKinematics<N> + RobotDynamics<N, P>
{
}
