//! The controlled frame: the robot frame whose position (and orientation, for task dimensions 5
//! and 6) the task rows control and at whose origin the contact force acts. The end-effector
//! through [`Kinematics`] by default, for every robot; any named frame of a robot generated with
//! the group `frames` ([`FrameKinematics`]) when chosen.
//!
//! A chosen frame is kept as its index into [`RobotFrame::ALL`] and plain `fn` pointers to
//! functions monomorphised for the robot, so that the controller and the plant need no
//! `FrameKinematics` bound and a tick neither allocates nor dispatches through `dyn`.

use super::error::ConfigError;
use dyngen_runtime::{FrameKinematics, JointTrig, Kinematics, Pose, ReferenceFrame, RobotFrame};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

type PoseFn<const N: usize> = fn(usize, &JointTrig<N>) -> Pose;
type JacobianFn<const N: usize> = fn(usize, &JointTrig<N>) -> SMatrix<f64, 6, N>;
type KinematicsFn<const N: usize> =
    fn(usize, &JointTrig<N>, &SVector<f64, N>) -> (Pose, SMatrix<f64, 6, N>, SMatrix<f64, 6, N>);

/// The frame the controller controls or the plant touches the surface with: `None`, the
/// end-effector through [`Kinematics`]; or a named frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ControlledFrame<const N: usize>(Option<NamedFrame<N>>);

/// A named frame of a robot generated with the group `frames`.
#[derive(Clone, Copy, Debug)]
struct NamedFrame<const N: usize> {
    /// Index into the robot's `RobotFrame::ALL` (0 is the end-effector).
    index: usize,
    name: &'static str,
    pose: PoseFn<N>,
    jacobian: JacobianFn<N>,
    kinematics: KinematicsFn<N>,
}

impl<const N: usize> ControlledFrame<N> {
    /// The end-effector, through [`Kinematics`] (what every robot has).
    pub(crate) const END_EFFECTOR: Self = ControlledFrame(None);

    /// The frame `frame` of robot `R`.
    pub(crate) fn of<R: FrameKinematics<N>>(frame: R::Frame) -> Self {
        // Every generated frame is in `ALL`; one that is not (a hand-written `RobotFrame` that
        // breaks its contract) gets an index past the end, whose kinematics are NaN: the
        // controller refuses it (a singular start, a non-finite torque) instead of silently
        // controlling another frame.
        let index = R::Frame::ALL
            .iter()
            .position(|f| *f == frame)
            .unwrap_or(R::Frame::ALL.len());
        ControlledFrame(Some(NamedFrame {
            index,
            name: frame.name(),
            pose: frame_pose::<R, N>,
            jacobian: frame_jacobian::<R, N>,
            kinematics: frame_kinematics::<R, N>,
        }))
    }

    /// The frame's name, `None` for the end-effector taken through [`Kinematics`].
    pub(crate) fn name(&self) -> Option<&'static str> {
        self.0.map(|f| f.name)
    }

    /// The frame's pose in the base frame.
    #[inline]
    pub(crate) fn pose<R: Kinematics<N>>(&self, t: &JointTrig<N>) -> Pose {
        match self.0 {
            None => R::forward_kinematics(t),
            Some(f) => (f.pose)(f.index, t),
        }
    }

    /// The frame's Jacobian, rows `[linear; angular]` at its origin in base axes.
    #[inline]
    pub(crate) fn jacobian<R: Kinematics<N>>(&self, t: &JointTrig<N>) -> SMatrix<f64, 6, N> {
        match self.0 {
            None => R::jacobian(t),
            Some(f) => (f.jacobian)(f.index, t),
        }
    }

    /// `(pose, J, J̇)` in the convention of [`Kinematics::kinematics`].
    #[inline]
    pub(crate) fn kinematics<R: Kinematics<N>>(
        &self,
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
    ) -> (Pose, SMatrix<f64, 6, N>, SMatrix<f64, 6, N>) {
        match self.0 {
            None => R::kinematics(t, qd),
            Some(f) => (f.kinematics)(f.index, t, qd),
        }
    }
}

fn nan_pose() -> Pose {
    Pose {
        rotation: Matrix3::from_element(f64::NAN),
        translation: Vector3::from_element(f64::NAN),
    }
}

fn frame_pose<R: FrameKinematics<N>, const N: usize>(index: usize, t: &JointTrig<N>) -> Pose {
    match R::Frame::ALL.get(index) {
        Some(f) => R::frame_pose(*f, t),
        None => nan_pose(),
    }
}

fn frame_jacobian<R: FrameKinematics<N>, const N: usize>(
    index: usize,
    t: &JointTrig<N>,
) -> SMatrix<f64, 6, N> {
    match R::Frame::ALL.get(index) {
        Some(f) => R::frame_jacobian(*f, ReferenceFrame::LocalWorldAligned, t),
        None => SMatrix::from_element(f64::NAN),
    }
}

fn frame_kinematics<R: FrameKinematics<N>, const N: usize>(
    index: usize,
    t: &JointTrig<N>,
    qd: &SVector<f64, N>,
) -> (Pose, SMatrix<f64, 6, N>, SMatrix<f64, 6, N>) {
    match R::Frame::ALL.get(index) {
        Some(f) => R::frame_kinematics(*f, t, qd),
        None => (
            nan_pose(),
            SMatrix::from_element(f64::NAN),
            SMatrix::from_element(f64::NAN),
        ),
    }
}

/// The frame of robot `R` named `name` in its description (`RobotFrame::from_name`), or
/// [`ConfigError::Invalid`] naming the robot and listing its frames.
pub fn frame_named<R: FrameKinematics<N>, const N: usize>(name: &str) -> Result<R::Frame, ConfigError> {
    R::Frame::from_name(name).ok_or_else(|| ConfigError::Invalid {
        name: "frame",
        detail: format!(
            "{} has no frame '{name}'; its frames: {}",
            R::NAME,
            frame_list::<R::Frame>()
        ),
    })
}

/// `panda_hand_tcp (the end-effector), panda_link1, …`.
fn frame_list<F: RobotFrame>() -> String {
    F::ALL
        .iter()
        .enumerate()
        .map(|(i, f)| {
            if i == 0 {
                format!("{} (the end-effector)", f.name())
            } else {
                f.name().to_string()
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}
