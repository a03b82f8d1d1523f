//! The generic algorithms instantiated with `f64`: dyngen's reference dynamics for any model,
//! and the baseline that generated code is benchmarked against.

use super::*;
use crate::model::Model;
use crate::spatial::{RigidInertia, Transform, Vec3};
use dyngen_runtime::ReferenceFrame;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};

/// Numeric dynamics of one model. Holds the model's inertias so calls do not rebuild them.
#[derive(Clone, Debug)]
pub struct NumericDynamics<'m> {
    pub model: &'m Model,
    pub(super) inertias: Vec<RigidInertia<f64>>,
    /// Joint-level values that act (chosen kinds; others 0).
    pub(super) joint_values: Vec<crate::model::JointTermValues>,
}

/// One frame's kinematics at one state, from [`NumericDynamics::frame_motion`].
pub struct FrameValues {
    motion: FrameMotion<f64>,
    qd: Vec<f64>,
}

impl FrameValues {
    /// The frame's pose in the base frame (rotation, translation).
    pub fn pose(&self) -> (Matrix3<f64>, Vector3<f64>) {
        (
            to_matrix3(&self.motion.pose),
            Vector3::from(self.motion.pose.pos.0),
        )
    }

    /// `J` (6×n, rows `[linear; angular]`) in `reference`.
    pub fn jacobian(&self, reference: ReferenceFrame) -> DMatrix<f64> {
        self.motion.jacobian_in(reference)
    }

    /// `J̇` in `reference`, the time derivative of [`FrameValues::jacobian`].
    pub fn jacobian_time_variation(&self, reference: ReferenceFrame) -> DMatrix<f64> {
        self.motion.jacobian_dot_in(reference, &self.qd)
    }

    /// The frame's velocity `J q̇` in `reference`, `[linear; angular]`.
    pub fn velocity(&self, reference: ReferenceFrame) -> Vector6<f64> {
        Vector6::from(self.motion.velocity_in(reference, &self.qd))
    }

    /// The classical acceleration at `q̈` in `reference`.
    pub fn classical_acceleration(&self, reference: ReferenceFrame, qdd: &[f64]) -> Vector6<f64> {
        Vector6::from(self.motion.classical_acceleration_in(reference, &self.qd, qdd))
    }
}

/// The joint transforms at one `q`. Each method builds its own from the `q` it is given (no
/// method takes one), so it is internal: callers that need several quantities at one `q` in a
/// control loop use generated code, where `JointTrig` is shared.
#[derive(Clone, Debug)]
pub(super) struct Configuration {
    pub(super) transforms: Vec<Transform<f64>>,
}

fn to_matrix3(t: &Transform<f64>) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| t.rot.0[i][j])
}

impl<'m> NumericDynamics<'m> {
    pub fn new(model: &'m Model) -> Self {
        NumericDynamics {
            model,
            inertias: body_inertias(model),
            joint_values: joint_term_values(model),
        }
    }

    /// The same model with other parameters θ (as [`Model::parameters`]: ten per body, then
    /// the joint-level ones).
    pub fn with_parameters(model: &'m Model, theta: &[f64]) -> Self {
        assert_eq!(theta.len(), model.parameter_count(), "θ has the wrong length");
        NumericDynamics {
            model,
            inertias: inertias_from_parameters(&theta[..model.inertial_parameter_count()]),
            joint_values: model.joint_term_values_from(theta),
        }
    }

    pub(super) fn configuration(&self, q: &[f64]) -> Configuration {
        assert_eq!(q.len(), self.model.dof(), "q has the wrong length");
        Configuration {
            transforms: joint_transforms(self.model, q),
        }
    }

    /// Every body's pose in the base frame (rotation, translation).
    pub fn body_poses(&self, q: &[f64]) -> Vec<(Matrix3<f64>, Vector3<f64>)> {
        let world = body_poses(self.model, &self.configuration(q).transforms);
        world
            .iter()
            .map(|t| (to_matrix3(t), Vector3::from(t.pos.0)))
            .collect()
    }

    /// End-effector pose in the base frame (rotation, translation).
    pub fn end_effector_pose(&self, q: &[f64]) -> (Matrix3<f64>, Vector3<f64>) {
        let world = body_poses(self.model, &self.configuration(q).transforms);
        let t = end_effector_pose(self.model, &world);
        (to_matrix3(&t), Vector3::from(t.pos.0))
    }

    pub fn jacobian(&self, q: &[f64]) -> DMatrix<f64> {
        jacobian(
            self.model,
            &body_poses(self.model, &self.configuration(q).transforms),
        )
    }

    pub fn jacobian_dot(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
        jacobian_dot(
            self.model,
            &body_poses(self.model, &self.configuration(q).transforms),
            qd,
        )
    }

    /// Pose, `J` and `J̇` of the frame named `frame` at `(q, q̇)`; `None` if the model has no
    /// such frame. Its methods give every frame quantity in any reference frame.
    pub fn frame_motion(&self, frame: &str, q: &[f64], qd: &[f64]) -> Option<FrameValues> {
        let frame = self.model.frames().iter().find(|f| f.name == frame)?;
        let world = body_poses(self.model, &self.configuration(q).transforms);
        Some(FrameValues {
            motion: FrameMotion::new(self.model, &world, qd, frame),
            qd: qd.to_vec(),
        })
    }

    /// `D(q)`, with the armature on the diagonal when the model has that column.
    pub fn mass_matrix(&self, q: &[f64]) -> DMatrix<f64> {
        let mut d = mass_matrix(self.model, &self.configuration(q).transforms, &self.inertias);
        add_armature(self.model, &self.joint_values, &mut d);
        d
    }

    pub fn coriolis_matrix(&self, q: &[f64], qd: &[f64]) -> DMatrix<f64> {
        coriolis_matrix(self.model, &self.configuration(q).transforms, &self.inertias, qd)
    }

    pub fn gravity_torque(&self, q: &[f64]) -> DVector<f64> {
        DVector::from_vec(gravity_torque(
            self.model,
            &self.configuration(q).transforms,
            &self.inertias,
        ))
    }

    /// `τ(q, q̇, q̈)`, joint-level terms included.
    pub fn inverse_dynamics(&self, q: &[f64], qd: &[f64], qdd: &[f64]) -> DVector<f64> {
        let x = self.configuration(q).transforms;
        let rigid = inverse_dynamics(self.model, &x, &self.inertias, qd, qdd);
        let joint = joint_term_torques(self.model, &self.joint_values, qd, qd, qdd);
        DVector::from_vec(add_torques(rigid, &joint))
    }

    /// `D(q) a + C(q, q̇) v + g(q)` plus the joint-level terms, with gravity switched off when
    /// `with_gravity` is false.
    pub fn slotine_li(
        &self,
        q: &[f64],
        qd: &[f64],
        v: &[f64],
        a: &[f64],
        with_gravity: bool,
    ) -> DVector<f64> {
        let x = self.configuration(q).transforms;
        let g = with_gravity.then(|| Vec3(self.model.gravity().into()));
        let rigid = slotine_li(self.model, &x, &self.inertias, qd, v, a, g);
        let joint = joint_term_torques(self.model, &self.joint_values, qd, v, a);
        DVector::from_vec(add_torques(rigid, &joint))
    }

    /// Slotine–Li regressor `Y(q, q̇, v, a)`, n × P (`10n` plus the joint-level columns).
    pub fn regressor(&self, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> DMatrix<f64> {
        regressor(self.model, &self.configuration(q).transforms, qd, v, a)
    }
}
