//! The true robot: generated kinematics with the true parameters `θ_true = θ_desc + θ_payload`
//! (and, for a robot with joint-level columns, its own friction and armature), whose dynamics
//! are computed through the regressor (exact by linearity, since the generated `D, C, g` have
//! the description's parameters baked in):
//! `D_true` column i `= Y(q, 0, 0, eᵢ) θ − Y(q, 0, 0, 0) θ`, `C q̇ + g = Y(q, q̇, q̇, 0) θ`.
//! The joint-level columns come along: the armature column is `a_j`, so it lands on `D`'s
//! diagonal; the viscous column is `v_j = q̇_j` and the Coulomb column `σ(q̇_j)` of the actual
//! velocity, so the bias torque is the friction of the actual motion (the Coulomb column is
//! the description's: `sign`, or `tanh(q̇/ε)` when it sets `coulomb_smoothing`).
//! Forward dynamics: when the true robot is the description (no payload), the generated
//! `forward_dynamics` (CRBA + tree factorisation, flattened); otherwise a Cholesky solve of
//! `D_true q̈ = τ − Jᵀ F̄ − (C q̇ + g)` with `D_true` through the regressor, because the
//! generated function has the description's parameters baked in and a payload changes `D` and
//! the bias torques.
//!
//! The parameters are in the coordinates of a parameterisation `Z` (standard or base): the base
//! regressor gives exactly the torques of the standard one for every θ (`Y_b Φ θ = Y θ`), at a
//! lower cost.

use super::contact::PlaneContact;
use super::true_joint_terms::JointTermFactors;
use crate::controller::frame::ControlledFrame;
use crate::mass_matrix_through_regressor;
use dyngen_runtime::{body_parameters, FrameKinematics, JointTrig, Kinematics, Parameterization};
use nalgebra::{Cholesky, Matrix3, SMatrix, SVector, Vector3};
use std::marker::PhantomData;

/// A rigid box payload fixed to the body that carries the end-effector: mass, centre of mass
/// and box size, in that body's (joint) frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Payload {
    pub mass: f64,
    pub com: Vector3<f64>,
    pub size: Vector3<f64>,
}

impl Payload {
    /// Its ten standard parameters `[m, m·cx, m·cy, m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`, the
    /// inertia about the body frame origin: `I_O = I_C + m (cᵀc·1 − c cᵀ)`.
    pub fn parameters(&self) -> [f64; 10] {
        let m = self.mass;
        let (a, b, c) = (self.size.x, self.size.y, self.size.z);
        let i_c =
            Matrix3::from_diagonal(&Vector3::new(b * b + c * c, a * a + c * c, a * a + b * b)) * (m / 12.0);
        body_parameters(m, &self.com, &i_c)
    }
}

/// A failure of the plant (reported with the time by the run).
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
pub enum PlantError {
    #[error("the true mass matrix is not positive definite (Cholesky failed)")]
    MassMatrix,
    #[error("non-finite joint acceleration")]
    NonFinite,
}

/// Joint state of the plant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlantState<const N: usize> {
    pub q: SVector<f64, N>,
    pub qd: SVector<f64, N>,
}

impl<const N: usize> super::rk4::RkState for PlantState<N> {
    fn axpy(&self, h: f64, k: &Self) -> Self {
        PlantState {
            q: self.q + k.q * h,
            qd: self.qd + k.qd * h,
        }
    }
}

/// The true robot in contact with a plane, touching it with the origin of its contact frame:
/// the end-effector by default, or a named frame chosen with [`Plant::with_contact_frame`].
#[derive(Clone, Debug)]
pub struct Plant<Z, const N: usize, const M: usize> {
    theta: SVector<f64, M>,
    /// `θ_true` equals the description's: the generated forward dynamics are exact.
    is_description: bool,
    pub contact: PlaneContact,
    frame: ControlledFrame<N>,
    _robot: PhantomData<fn() -> Z>,
}

impl<Z: Parameterization<N, M>, const N: usize, const M: usize> Plant<Z, N, M> {
    /// A plant with parameters `theta` (in `Z`'s coordinates).
    pub fn new(theta: SVector<f64, M>, contact: PlaneContact) -> Self {
        Plant {
            is_description: theta == Z::description(),
            theta,
            contact,
            frame: ControlledFrame::END_EFFECTOR,
            _robot: PhantomData,
        }
    }

    /// Touches the plane with the origin of `frame` instead of the end-effector's: the contact
    /// force acts there, through that frame's Jacobian. ([`super::simulate`] always touches the
    /// plane with the controller's controlled frame, see
    /// [`crate::controller::HybridController::with_controlled_frame`].)
    pub fn with_contact_frame(self, frame: <Z::Robot as FrameKinematics<N>>::Frame) -> Self
    where
        Z::Robot: FrameKinematics<N>,
    {
        self.at_frame(ControlledFrame::of::<Z::Robot>(frame))
    }

    /// The same plant touching the plane with `frame`.
    pub(crate) fn at_frame(&self, frame: ControlledFrame<N>) -> Self {
        Plant {
            theta: self.theta,
            is_description: self.is_description,
            contact: self.contact,
            frame,
            _robot: PhantomData,
        }
    }

    /// The name of the frame chosen with [`Self::with_contact_frame`]; `None` when the
    /// end-effector touches the plane (the default).
    pub fn contact_frame(&self) -> Option<&'static str> {
        self.frame.name()
    }

    /// The description's parameters plus `payload` on the end-effector's body.
    pub fn with_payload(payload: &Payload, contact: PlaneContact) -> Self {
        Self::with_payload_and_joint_terms(payload, &JointTermFactors::NOMINAL, contact)
    }

    /// The description's parameters with its joint-level ones (armature, friction, offset)
    /// scaled by `joint_terms`, plus `payload` on the end-effector's body.
    pub fn with_payload_and_joint_terms(
        payload: &Payload,
        joint_terms: &JointTermFactors,
        contact: PlaneContact,
    ) -> Self {
        let body = <Z::Robot as Kinematics<N>>::END_EFFECTOR_BODY;
        let theta = Z::description_scaled_by_kind(|kind| joint_terms.of(kind))
            + Z::from_body_parameters(body, &payload.parameters());
        Self::new(theta, contact)
    }

    /// `θ_true`, in `Z`'s coordinates.
    pub fn parameters(&self) -> &SVector<f64, M> {
        &self.theta
    }

    /// `D_true(q)`.
    pub fn mass_matrix(&self, t: &JointTrig<N>) -> SMatrix<f64, N, N> {
        mass_matrix_through_regressor::<Z, N, M>(t, &self.theta)
    }

    /// `C_true(q, q̇) v + g_true(q)` (Slotine–Li form) through the regressor.
    pub fn slotine_li(&self, t: &JointTrig<N>, qd: &SVector<f64, N>, v: &SVector<f64, N>) -> SVector<f64, N> {
        Z::regressor(t, qd, v, &SVector::zeros()) * self.theta
    }

    /// `g_true(q)`.
    pub fn gravity(&self, t: &JointTrig<N>) -> SVector<f64, N> {
        let z = SVector::<f64, N>::zeros();
        Z::regressor(t, &z, &z, &z) * self.theta
    }

    /// The true viscous friction coefficient of each joint (0 for a robot without that
    /// column): `Y(q, 0, v, 0) θ = g + F_v v + f_o`, so joint `j`'s is the `j`-th entry of
    /// `Y(q, 0, e_j, 0) θ − Y(q, 0, 0, 0) θ` (`C(q, 0) = 0`). The closed loop dissipates
    /// `rᵀ (G + F_v) r`, not `rᵀ G r`, when the law's viscous column uses `q̇_r`
    /// (`docs/controller.md`).
    pub fn viscous_friction(&self, t: &JointTrig<N>) -> SVector<f64, N> {
        let z = SVector::<f64, N>::zeros();
        let rest = Z::regressor(t, &z, &z, &z) * self.theta;
        SVector::from_fn(|j, _| {
            let e = SVector::<f64, N>::from_fn(|k, _| f64::from(u8::from(k == j)));
            (Z::regressor(t, &z, &e, &z) * self.theta - rest)[j]
        })
    }

    /// `F̄` at `q`: the force the contact frame's origin exerts on the plane.
    pub fn contact_force(&self, t: &JointTrig<N>) -> Vector3<f64> {
        self.contact
            .force_on_environment(&self.frame.pose::<Z::Robot>(t).translation)
    }

    /// `q̈` and `F̄` under torque `tau`.
    pub fn acceleration(
        &self,
        s: &PlantState<N>,
        tau: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, Vector3<f64>), PlantError> {
        let t = JointTrig::new(&s.q);
        let force = self.contact_force(&t);
        let j: SMatrix<f64, 3, N> = self
            .frame
            .jacobian::<Z::Robot>(&t)
            .fixed_rows::<3>(0)
            .into_owned();
        let applied = tau - j.tr_mul(&force);
        let qdd = if self.is_description {
            Z::description_forward_dynamics(&t, &s.qd, &applied)
        } else {
            let rhs = applied - self.slotine_li(&t, &s.qd, &s.qd);
            Cholesky::new(self.mass_matrix(&t))
                .ok_or(PlantError::MassMatrix)?
                .solve(&rhs)
        };
        if !qdd.iter().all(|x| x.is_finite()) {
            return Err(PlantError::NonFinite);
        }
        Ok((qdd, force))
    }

    /// `ẋ` of the plant state under a held torque.
    pub fn derivative(&self, s: &PlantState<N>, tau: &SVector<f64, N>) -> Result<PlantState<N>, PlantError> {
        let (qdd, _) = self.acceleration(s, tau)?;
        Ok(PlantState { q: s.qd, qd: qdd })
    }
}
