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
//!
//! The surface is compliant (the force a function of the position, `F̄` above) or rigid
//! ([`Surface::Rigid`]: the force a constraint's, solved with the dynamics, in `rigid`).

mod rigid;

use super::rk4::rk4_step;
use super::surface::Surface;
use super::true_joint_terms::JointTermFactors;
use crate::controller::frame::ControlledFrame;
use crate::mass_matrix_through_regressor;
use dyngen_runtime::{
    body_parameters, ContactError, FrameKinematics, JointTrig, Kinematics, Parameterization,
};
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
    /// A rigid plane the plant cannot simulate ([`super::RigidPlane::check`]).
    #[error("{0}")]
    RigidPlane(&'static str),
    /// On a rigid plane, the contact point cannot move along the normal at this posture (a
    /// singular configuration): no force can hold it on the plane.
    #[error("the contact point cannot move along the rigid plane's normal (a singular posture)")]
    SingularContact,
    /// The rigid plane's contact solve refused its input.
    #[error("rigid contact: {0}")]
    Contact(ContactError),
}

/// Joint state of the plant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlantState<const N: usize> {
    pub q: SVector<f64, N>,
    pub qd: SVector<f64, N>,
}

impl<const N: usize> PlantState<N> {
    /// At rest at `q`.
    pub fn at_rest(q: SVector<f64, N>) -> Self {
        PlantState {
            q,
            qd: SVector::zeros(),
        }
    }
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
    pub contact: Surface,
    frame: ControlledFrame<N>,
    _robot: PhantomData<fn() -> Z>,
}

impl<Z: Parameterization<N, M>, const N: usize, const M: usize> Plant<Z, N, M> {
    /// A plant with parameters `theta` (in `Z`'s coordinates) touching `contact`, a
    /// [`super::PlaneContact`] (compliant) or a [`super::RigidPlane`].
    pub fn new(theta: SVector<f64, M>, contact: impl Into<Surface>) -> Self {
        Plant {
            is_description: theta == Z::description(),
            theta,
            contact: contact.into(),
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
    pub fn with_payload(payload: &Payload, contact: impl Into<Surface>) -> Self {
        Self::with_payload_and_joint_terms(payload, &JointTermFactors::NOMINAL, contact)
    }

    /// The description's parameters with its joint-level ones (armature, friction, offset)
    /// scaled by `joint_terms`, plus `payload` on the end-effector's body.
    pub fn with_payload_and_joint_terms(
        payload: &Payload,
        joint_terms: &JointTermFactors,
        contact: impl Into<Surface>,
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

    /// `F̄`: the force the contact frame's origin exerts on the surface at state `s` under the
    /// joint torque `tau`. On a compliant plane a function of the position alone,
    /// [`super::PlaneContact::force_on_environment`]; on a rigid plane the constraint's force,
    /// solved with the dynamics (zero while the point is off the plane or would be pulled).
    pub fn contact_force(
        &self,
        s: &PlantState<N>,
        tau: &SVector<f64, N>,
    ) -> Result<Vector3<f64>, PlantError> {
        match &self.contact {
            Surface::Compliant(plane) => {
                let t = JointTrig::new(&s.q);
                Ok(plane.force_on_environment(&self.frame.pose::<Z::Robot>(&t).translation))
            }
            Surface::Rigid(_) => Ok(self.acceleration(s, tau)?.1),
        }
    }

    /// `q̈` and `F̄` under torque `tau`. On a rigid plane: the constrained acceleration while
    /// the point is on the plane and the plane pushes it, the free one otherwise (a point on the
    /// plane and moving into it is struck first, see [`Self::impact`] and [`Self::step`]).
    pub fn acceleration(
        &self,
        s: &PlantState<N>,
        tau: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, Vector3<f64>), PlantError> {
        let (qdd, force) = match &self.contact {
            Surface::Compliant(plane) => {
                let t = JointTrig::new(&s.q);
                let pose = self.frame.pose::<Z::Robot>(&t);
                let force = plane.force_on_environment(&pose.translation);
                let applied = tau - self.linear_jacobian(&t).tr_mul(&force);
                (self.forward_dynamics(&t, &s.qd, &applied, None)?.0, force)
            }
            Surface::Rigid(plane) => self.on_rigid_plane(plane, s, tau)?,
        };
        if !qdd.iter().all(|x| x.is_finite()) {
            return Err(PlantError::NonFinite);
        }
        Ok((qdd, force))
    }

    /// The contact frame's linear-velocity rows `J_v` (3 × N, base axes).
    pub(crate) fn linear_jacobian(&self, t: &JointTrig<N>) -> SMatrix<f64, 3, N> {
        self.frame.jacobian::<Z::Robot>(t).fixed_rows::<3>(0).into_owned()
    }

    /// `q̈ = D_true⁻¹ (applied − (C q̇ + g)_true)`, and `D_true⁻¹ y` for `Some(y)` (zero for
    /// `None`), from one factorisation of `D_true` on the regressor path; through the generated
    /// forward dynamics, `D⁻¹ y = q̈(applied + y) − q̈(applied)`, exact since `q̈` is affine in
    /// the torque.
    fn forward_dynamics(
        &self,
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        applied: &SVector<f64, N>,
        y: Option<&SVector<f64, N>>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>), PlantError> {
        if self.is_description {
            let qdd = Z::description_forward_dynamics(t, qd, applied);
            let response = y.map_or_else(SVector::zeros, |y| {
                Z::description_forward_dynamics(t, qd, &(applied + y)) - qdd
            });
            Ok((qdd, response))
        } else {
            let rhs = applied - self.slotine_li(t, qd, qd);
            let d = Cholesky::new(self.mass_matrix(t)).ok_or(PlantError::MassMatrix)?;
            let response = y.map_or_else(SVector::zeros, |y| d.solve(y));
            Ok((d.solve(&rhs), response))
        }
    }

    /// `ẋ` of the plant state under a held torque (the instantaneous [`Self::acceleration`]).
    pub fn derivative(&self, s: &PlantState<N>, tau: &SVector<f64, N>) -> Result<PlantState<N>, PlantError> {
        let (qdd, _) = self.acceleration(s, tau)?;
        Ok(PlantState { q: s.qd, qd: qdd })
    }

    /// One step of length `h` under a held torque. On a compliant plane one RK4 step of
    /// [`Self::derivative`]; on a rigid plane RK4 steps whose contact is decided at their start,
    /// with the impact where the point reaches the plane (`rigid`).
    pub fn step(
        &self,
        s: &PlantState<N>,
        tau: &SVector<f64, N>,
        h: f64,
    ) -> Result<PlantState<N>, PlantError> {
        match &self.contact {
            Surface::Compliant(_) => rk4_step(0.0, s, h, |_, x| self.derivative(x, tau)),
            Surface::Rigid(plane) => self.step_on_rigid_plane(plane, s, tau, h),
        }
    }

    /// The velocity jump when the contact point strikes a rigid plane at state `s` (on the
    /// plane and moving into it): `D (q̇⁺ − q̇⁻) = Jᵀ n Λ` with `nᵀ J q̇⁺ = 0`, a perfectly
    /// plastic impact. Returns the state after and the impulse `Λ` (N·s, ≥ 0); `s` and 0 when
    /// the surface is compliant or the point is not striking the plane.
    pub fn impact(&self, s: &PlantState<N>) -> Result<(PlantState<N>, f64), PlantError> {
        match &self.contact {
            Surface::Compliant(_) => Ok((*s, 0.0)),
            Surface::Rigid(plane) => self.strike(plane, s),
        }
    }
}
