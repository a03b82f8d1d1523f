//! The constrained functions in `f64` for fixed and floating bases: each facade gathers the
//! factored mass matrix, the unconstrained acceleration, `M⁻¹ Jᵀ` and the contacts' rows at a
//! state, and the runtime's solve does the rest.

use super::error::ConstraintError;
use super::rows::{constraint_rows, ConstraintRows, ContactMotion};
use crate::dynamics::floating;
use crate::dynamics::forward_dynamics::{bias_torque, factor_mass_matrix};
use crate::dynamics::frames::FrameMotion;
use crate::dynamics::tree_ldl::TreeLdl;
use crate::dynamics::{body_poses, FloatingDynamics, FloatingState, NumericDynamics};
use crate::model::Contact;
use crate::model::Model;
use dyngen_runtime::{
    contact_inertia, placement_error, solve_contacts, ContactError, ContactSolution, Pose, ProximalSettings,
    ReferenceFrame, Stabilisation,
};
use nalgebra::{DMatrix, DVector, Dyn, Matrix3, Vector3};

/// Constrained forward dynamics of the generic dynamics: `acceleration` and `forces` of any
/// size.
pub type ConstrainedMotion = ContactSolution<Dyn, Dyn>;

/// What every constrained quantity at one state starts from.
pub(super) struct AtState {
    /// `M` factored.
    pub(super) mass: TreeLdl<f64>,
    /// `M⁻¹ (τ − b)`, zero where no torque is given.
    pub(super) free: DVector<f64>,
    pub(super) rows: ConstraintRows<f64>,
    /// `M⁻¹ Jᵀ`.
    pub(super) response: DMatrix<f64>,
    /// Each contact's frame pose, and the pose of the frame it is held to (loops).
    poses: Vec<(Pose, Option<Pose>)>,
}

impl AtState {
    fn new(
        mass: TreeLdl<f64>,
        free: Vec<f64>,
        motions: &[ContactMotion<f64>],
        contacts: &[Contact],
        v: &[f64],
    ) -> Self {
        let rows = constraint_rows(contacts, motions, v);
        AtState {
            response: mass.solve_matrix(&rows.jacobian.transpose()),
            mass,
            free: DVector::from_vec(free),
            rows,
            poses: (motions.iter())
                .map(|m| (pose_of(&m.frame), m.to.as_ref().map(pose_of)))
                .collect(),
        }
    }
}

impl NumericDynamics<'_> {
    /// `q̈` and the contact forces with `contacts` held (Pinocchio's `constraintDynamics`):
    /// exact with the default settings, proximal with `mu > 0`, pulled back to the anchors
    /// with `stabilisation`.
    pub fn constrained_forward_dynamics(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        contacts: &[Contact],
        stabilisation: Option<Stabilisation<'_>>,
        settings: &ProximalSettings,
    ) -> Result<ConstrainedMotion, ConstraintError> {
        let at = self.at_state(q, qd, Some(tau), contacts)?;
        forward(&at, contacts, stabilisation, settings)
    }

    /// The velocity just after `contacts` strike with restitution `restitution`, and the
    /// impulses (Pinocchio's `impulseDynamics`; `mu` damps redundant rows).
    pub fn impulse_dynamics(
        &self,
        q: &[f64],
        qd_before: &[f64],
        contacts: &[Contact],
        restitution: f64,
        mu: f64,
    ) -> Result<(DVector<f64>, DVector<f64>), ConstraintError> {
        let at = self.at_state(q, qd_before, None, contacts)?;
        impact(&at, qd_before, restitution, mu)
    }

    /// `(J M⁻¹ Jᵀ + ε I)⁻¹` of the contacts' rows: their operational-space inertia, `damping`
    /// `ε` keeping it finite near singular configurations (0 for the exact one).
    pub fn operational_space_inertia(
        &self,
        q: &[f64],
        contacts: &[Contact],
        damping: f64,
    ) -> Result<DMatrix<f64>, ConstraintError> {
        let at = self.at_state(q, &vec![0.0; self.model.dof()], None, contacts)?;
        operational_space_inertia(&at, damping)
    }

    pub(super) fn at_state(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: Option<&[f64]>,
        contacts: &[Contact],
    ) -> Result<AtState, ConstraintError> {
        check_contacts(self.model, contacts)?;
        assert_eq!(qd.len(), self.model.dof(), "q̇ has the wrong length");
        let x = self.configuration(q).transforms;
        let mass = factor_mass_matrix(self.model, &x, &self.inertias, &self.joint_values);
        let free = match tau {
            Some(tau) => {
                assert_eq!(tau.len(), self.model.dof(), "τ has the wrong length");
                let bias = bias_torque(self.model, &x, &self.inertias, &self.joint_values, qd);
                mass.solve(&difference(tau, &bias))
            }
            None => vec![0.0; qd.len()],
        };
        let world = body_poses(self.model, &x);
        let motions = ContactMotion::of(contacts, |k| {
            FrameMotion::new(self.model, &world, qd, &self.model.frames()[k])
        });
        Ok(AtState::new(mass, free, &motions, contacts, qd))
    }
}

impl FloatingDynamics<'_> {
    /// `ν̇` and the contact forces with `contacts` held (Pinocchio's `constraintDynamics`).
    pub fn constrained_forward_dynamics(
        &self,
        s: &FloatingState,
        v: &[f64],
        tau: &[f64],
        contacts: &[Contact],
        stabilisation: Option<Stabilisation<'_>>,
        settings: &ProximalSettings,
    ) -> Result<ConstrainedMotion, ConstraintError> {
        let at = self.at_state(s, v, Some(tau), contacts)?;
        forward(&at, contacts, stabilisation, settings)
    }

    /// The velocity just after `contacts` strike, and the impulses (Pinocchio's
    /// `impulseDynamics`).
    pub fn impulse_dynamics(
        &self,
        s: &FloatingState,
        v_before: &[f64],
        contacts: &[Contact],
        restitution: f64,
        mu: f64,
    ) -> Result<(DVector<f64>, DVector<f64>), ConstraintError> {
        let at = self.at_state(s, v_before, None, contacts)?;
        impact(&at, v_before, restitution, mu)
    }

    /// `(J M⁻¹ Jᵀ + ε I)⁻¹` of the contacts' rows.
    pub fn operational_space_inertia(
        &self,
        s: &FloatingState,
        contacts: &[Contact],
        damping: f64,
    ) -> Result<DMatrix<f64>, ConstraintError> {
        let at = self.at_state(s, &vec![0.0; self.model.nv()], None, contacts)?;
        operational_space_inertia(&at, damping)
    }

    /// What the contacts' rows `J a` are at `a = 0` (`J̇ ν` for rows to the world; the
    /// generated `contact_drift`), from each frame's `J̇`.
    pub fn contact_drift(
        &self,
        s: &FloatingState,
        v: &[f64],
        contacts: &[Contact],
    ) -> Result<DVector<f64>, ConstraintError> {
        Ok(DVector::from_vec(self.at_state(s, v, None, contacts)?.rows.drift))
    }

    pub(super) fn at_state(
        &self,
        s: &FloatingState,
        v: &[f64],
        tau: Option<&[f64]>,
        contacts: &[Contact],
    ) -> Result<AtState, ConstraintError> {
        check_contacts(self.model, contacts)?;
        assert_eq!(v.len(), self.model.nv(), "ν has the wrong length");
        let base = self.base(s);
        let (x, inertias) = (&s.transforms, &self.inertias);
        let mass = floating::factor(self.model, &base, x, inertias, &self.joint_values);
        let free = match tau {
            Some(tau) => {
                assert_eq!(tau.len(), self.model.nv(), "τ has the wrong length");
                let bias = floating::floating_bias(self.model, &base, x, inertias, &self.joint_values, v);
                mass.solve(&difference(tau, &bias))
            }
            None => vec![0.0; v.len()],
        };
        let motions = ContactMotion::of(contacts, |k| self.frame_motion(s, v, k));
        Ok(AtState::new(mass, free, &motions, contacts, v))
    }
}

fn difference(a: &[f64], b: &[f64]) -> Vec<f64> {
    a.iter().zip(b).map(|(x, y)| x - y).collect()
}

fn pose_of(m: &FrameMotion<f64>) -> Pose {
    Pose {
        rotation: Matrix3::from_fn(|i, j| m.pose.rot.0[i][j]),
        translation: Vector3::from(m.pose.pos.0),
    }
}

fn check_contacts(model: &Model, contacts: &[Contact]) -> Result<(), ConstraintError> {
    for (k, c) in contacts.iter().enumerate() {
        for frame in std::iter::once(c.frame).chain(c.to) {
            if frame >= model.frames().len() {
                return Err(ConstraintError::FrameIndex(frame));
            }
        }
        if c.reference == ReferenceFrame::World {
            return Err(ContactError::WorldReference(k).into());
        }
    }
    Ok(())
}

/// The rows' right-hand side: `−drift`, less the Baumgarte terms when stabilised.
pub(super) fn right_hand_side(
    at: &AtState,
    contacts: &[Contact],
    stabilisation: Option<Stabilisation<'_>>,
) -> Result<DVector<f64>, ContactError> {
    let mut rhs = -DVector::from_column_slice(&at.rows.drift);
    let Some(stabilisation) = stabilisation else {
        return Ok(rhs);
    };
    stabilisation.check(world_contacts(contacts))?;
    let (mut row, mut anchors) = (0, stabilisation.anchors.iter());
    for (contact, (pose, to)) in contacts.iter().zip(&at.poses) {
        // A loop is held where its other frame is; a contact with the world, at its anchor.
        let anchor = match to {
            Some(to) => to,
            // One per contact with the world: counted above.
            None => anchors
                .next()
                .ok_or(ContactError::Settings("an anchor is missing"))?,
        };
        let error = placement_error(contact.kind, contact.reference, pose, anchor);
        for k in 0..contact.kind.rows() {
            rhs[row + k] -= stabilisation.kp * error[k] + stabilisation.kd * at.rows.velocity[row + k];
        }
        row += contact.kind.rows();
    }
    Ok(rhs)
}

/// How many of `contacts` hold their frame to the world (each one anchor when stabilised).
pub(super) fn world_contacts(contacts: &[Contact]) -> usize {
    contacts.iter().filter(|c| c.to.is_none()).count()
}

fn forward(
    at: &AtState,
    contacts: &[Contact],
    stabilisation: Option<Stabilisation<'_>>,
    settings: &ProximalSettings,
) -> Result<ConstrainedMotion, ConstraintError> {
    let rhs = right_hand_side(at, contacts, stabilisation)?;
    Ok(solve_contacts(
        &at.rows.jacobian,
        &at.response,
        &at.free,
        &rhs,
        settings,
        None,
    )?)
}

fn impact(
    at: &AtState,
    before: &[f64],
    restitution: f64,
    mu: f64,
) -> Result<(DVector<f64>, DVector<f64>), ConstraintError> {
    if !(0.0..=1.0).contains(&restitution) {
        return Err(ContactError::Restitution(restitution).into());
    }
    // `J Δν = −(1 + r) J ν⁻` with `Δν = M⁻¹ Jᵀ Λ`: one solve, damped by `mu`.
    let rhs = -(1.0 + restitution) * DVector::from_column_slice(&at.rows.velocity);
    let settings = ProximalSettings {
        mu,
        max_iterations: 1,
        accuracy: 0.0,
    };
    let zero = DVector::zeros(before.len());
    let change = solve_contacts(&at.rows.jacobian, &at.response, &zero, &rhs, &settings, None)?;
    Ok((
        DVector::from_column_slice(before) + change.acceleration,
        change.forces,
    ))
}

fn operational_space_inertia(at: &AtState, damping: f64) -> Result<DMatrix<f64>, ConstraintError> {
    Ok(contact_inertia(&at.rows.jacobian, &at.response, damping)?)
}
