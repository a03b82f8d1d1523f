//! The constrained algorithms in `f64` for fixed and floating bases: each facade gathers the
//! factored mass matrix, the unconstrained acceleration and the contacts' rows at a state, and
//! one solver does the rest.

use super::contact::{ConstraintError, Contact, ProximalSettings, Stabilisation};
use super::delassus::Delassus;
use super::placement_error::placement_error;
use super::rows::{constraint_rows, ConstraintRows};
use crate::dynamics::floating;
use crate::dynamics::forward_dynamics::{bias_torque, factor_mass_matrix};
use crate::dynamics::frames::FrameMotion;
use crate::dynamics::tree_ldl::TreeLdl;
use crate::dynamics::{body_poses, FloatingDynamics, FloatingState, NumericDynamics};
use crate::model::Model;
use dyngen_runtime::ReferenceFrame;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// Constrained forward dynamics at one state.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstrainedMotion {
    /// `a` (`q̈`, or `ν̇` on a floating base).
    pub acceleration: DVector<f64>,
    /// `λ`: each contact's force (a point's three, a frame's six, linear first), in its
    /// reference axes, acting on the robot.
    pub forces: DVector<f64>,
    /// Proximal iterations run.
    pub iterations: usize,
    /// `‖J a − rhs‖∞` at the end: how well the rows hold.
    pub residual: f64,
}

/// The velocity after an impact and the impulses that made it.
#[derive(Clone, Debug, PartialEq)]
pub struct Impact {
    pub velocity: DVector<f64>,
    /// Each contact's impulse, in its reference axes, as [`ConstrainedMotion::forces`].
    pub impulses: DVector<f64>,
}

/// What every constrained quantity at one state starts from.
struct AtState {
    mass: TreeLdl<f64>,
    /// `M⁻¹ (τ − b)`, zero where no torque is given.
    free: Vec<f64>,
    rows: ConstraintRows<f64>,
    poses: Vec<(Matrix3<f64>, Vector3<f64>)>,
}

impl NumericDynamics<'_> {
    /// `q̈` and the contact forces with `contacts` held (Pinocchio's `constraintDynamics`).
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
        forward(at, contacts, qd, stabilisation, settings)
    }

    /// The velocity just after `contacts` strike with restitution `restitution`
    /// (Pinocchio's `impulseDynamics`; `mu` damps redundant rows).
    pub fn impulse_dynamics(
        &self,
        q: &[f64],
        qd_before: &[f64],
        contacts: &[Contact],
        restitution: f64,
        mu: f64,
    ) -> Result<Impact, ConstraintError> {
        let at = self.at_state(q, qd_before, None, contacts)?;
        impact(at, qd_before, restitution, mu)
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
        operational_space_inertia(at, damping)
    }

    fn at_state(
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
                let rhs: Vec<f64> = tau.iter().zip(&bias).map(|(t, b)| t - b).collect();
                mass.solve(&rhs)
            }
            None => vec![0.0; qd.len()],
        };
        let world = body_poses(self.model, &x);
        let motions: Vec<FrameMotion<f64>> = contacts
            .iter()
            .map(|c| FrameMotion::new(self.model, &world, qd, &self.model.frames()[c.frame]))
            .collect();
        Ok(AtState {
            mass,
            free,
            rows: constraint_rows(contacts, &motions, qd),
            poses: motions.iter().map(pose_of).collect(),
        })
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
        forward(at, contacts, v, stabilisation, settings)
    }

    /// The velocity just after `contacts` strike (Pinocchio's `impulseDynamics`).
    pub fn impulse_dynamics(
        &self,
        s: &FloatingState,
        v_before: &[f64],
        contacts: &[Contact],
        restitution: f64,
        mu: f64,
    ) -> Result<Impact, ConstraintError> {
        let at = self.at_state(s, v_before, None, contacts)?;
        impact(at, v_before, restitution, mu)
    }

    /// `(J M⁻¹ Jᵀ + ε I)⁻¹` of the contacts' rows.
    pub fn operational_space_inertia(
        &self,
        s: &FloatingState,
        contacts: &[Contact],
        damping: f64,
    ) -> Result<DMatrix<f64>, ConstraintError> {
        let at = self.at_state(s, &vec![0.0; self.model.nv()], None, contacts)?;
        operational_space_inertia(at, damping)
    }

    fn at_state(
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
        let mass = floating::factor(self.model, &base, x, inertias);
        let free = match tau {
            Some(tau) => {
                assert_eq!(tau.len(), self.model.nv(), "τ has the wrong length");
                let zero = vec![0.0; v.len()];
                let bias = floating::floating_inverse_dynamics(self.model, &base, x, inertias, v, &zero);
                let rhs: Vec<f64> = tau.iter().zip(&bias).map(|(t, b)| t - b).collect();
                mass.solve(&rhs)
            }
            None => vec![0.0; v.len()],
        };
        let motions: Vec<FrameMotion<f64>> = contacts
            .iter()
            .map(|c| self.frame_motion(s, v, c.frame))
            .collect();
        Ok(AtState {
            mass,
            free,
            rows: constraint_rows(contacts, &motions, v),
            poses: motions.iter().map(pose_of).collect(),
        })
    }
}

fn pose_of(m: &FrameMotion<f64>) -> (Matrix3<f64>, Vector3<f64>) {
    (
        Matrix3::from_fn(|i, j| m.pose.rot.0[i][j]),
        Vector3::from(m.pose.pos.0),
    )
}

fn check_contacts(model: &Model, contacts: &[Contact]) -> Result<(), ConstraintError> {
    for (k, c) in contacts.iter().enumerate() {
        if c.frame >= model.frames().len() {
            return Err(ConstraintError::FrameIndex(c.frame));
        }
        if c.reference == ReferenceFrame::World {
            return Err(ConstraintError::WorldReference(k));
        }
    }
    Ok(())
}

/// The rows' right-hand side: `−drift`, less the Baumgarte terms when stabilised.
fn right_hand_side(
    at: &AtState,
    contacts: &[Contact],
    stabilisation: Option<Stabilisation<'_>>,
) -> Result<Vec<f64>, ConstraintError> {
    let mut rhs: Vec<f64> = at.rows.drift.iter().map(|d| -d).collect();
    let Some(stabilisation) = stabilisation else {
        return Ok(rhs);
    };
    if stabilisation.anchors.len() != contacts.len() {
        return Err(ConstraintError::Anchors {
            contacts: contacts.len(),
            anchors: stabilisation.anchors.len(),
        });
    }
    if !(stabilisation.kp.is_finite() && stabilisation.kd.is_finite()) {
        return Err(ConstraintError::Settings("the Baumgarte gains must be finite"));
    }
    let mut row = 0;
    for ((contact, anchor), (rotation, translation)) in
        contacts.iter().zip(stabilisation.anchors).zip(&at.poses)
    {
        let error = placement_error(contact.kind, contact.reference, (rotation, translation), anchor);
        for (k, e) in error.iter().enumerate() {
            rhs[row + k] -= stabilisation.kp * e + stabilisation.kd * at.rows.velocity[row + k];
        }
        row += error.len();
    }
    Ok(rhs)
}

fn delassus(at: &AtState, mu: f64) -> Result<Delassus<f64>, ConstraintError> {
    let delassus = Delassus::new(&at.mass, at.rows.jacobian.clone(), mu);
    if mu == 0.0 {
        // A pivot at rounding level against the largest: a row the others already fix.
        let largest = delassus.pivots().iter().fold(0.0_f64, |m, p| m.max(p.abs()));
        if let Some(row) = delassus.pivots().iter().position(|p| p.is_nan() || *p <= 1e-12 * largest) {
            return Err(ConstraintError::Redundant { row });
        }
    }
    Ok(delassus)
}

fn forward(
    at: AtState,
    contacts: &[Contact],
    qd: &[f64],
    stabilisation: Option<Stabilisation<'_>>,
    settings: &ProximalSettings,
) -> Result<ConstrainedMotion, ConstraintError> {
    if !(settings.mu >= 0.0 && settings.mu.is_finite()) {
        return Err(ConstraintError::Settings("mu must be finite and not negative"));
    }
    if settings.max_iterations == 0 {
        return Err(ConstraintError::Settings("at least one iteration is needed"));
    }
    debug_assert_eq!(qd.len(), at.free.len());
    let rhs = right_hand_side(&at, contacts, stabilisation)?;
    let solver = delassus(&at, settings.mu)?;
    let mut lambda = vec![0.0; rhs.len()];
    let (mut iterations, mut residual) = (0, f64::INFINITY);
    while iterations < settings.max_iterations {
        iterations += 1;
        let next = solver.multipliers(&at.free, &rhs, &lambda);
        let change = next
            .iter()
            .zip(&lambda)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        lambda = next;
        let acceleration = solver.motion(&at.free, &lambda);
        residual = solver
            .rows_times(&acceleration)
            .iter()
            .zip(&rhs)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        if residual <= settings.accuracy || change <= settings.accuracy {
            break;
        }
    }
    Ok(ConstrainedMotion {
        acceleration: DVector::from_vec(solver.motion(&at.free, &lambda)),
        forces: DVector::from_vec(lambda),
        iterations,
        residual,
    })
}

fn impact(at: AtState, before: &[f64], restitution: f64, mu: f64) -> Result<Impact, ConstraintError> {
    if !(0.0..=1.0).contains(&restitution) {
        return Err(ConstraintError::Restitution(restitution));
    }
    if !(mu >= 0.0 && mu.is_finite()) {
        return Err(ConstraintError::Settings("mu must be finite and not negative"));
    }
    let solver = delassus(&at, mu)?;
    // The velocity change `Δν = M⁻¹ Jᵀ Λ` with `J Δν = −(1 + r) J ν⁻`: one (damped) solve.
    let rhs: Vec<f64> = at
        .rows
        .velocity
        .iter()
        .map(|v| -(1.0 + restitution) * v)
        .collect();
    let zero = vec![0.0; before.len()];
    let impulses = solver.multipliers(&zero, &rhs, &vec![0.0; rhs.len()]);
    let change = solver.motion(&zero, &impulses);
    Ok(Impact {
        velocity: DVector::from_iterator(before.len(), before.iter().zip(change).map(|(v, d)| v + d)),
        impulses: DVector::from_vec(impulses),
    })
}

fn operational_space_inertia(at: AtState, damping: f64) -> Result<DMatrix<f64>, ConstraintError> {
    if !(damping >= 0.0 && damping.is_finite()) {
        return Err(ConstraintError::Settings(
            "the damping must be finite and not negative",
        ));
    }
    Ok(delassus(&at, damping)?.inverse())
}
