//! The derivatives of constrained forward dynamics in `f64` (`derivatives.rs` for the method):
//! each facade writes `F` and `G` on dual numbers with its own algorithms; one function turns
//! the residuals' tangents into the derivatives with the runtime's solve.

use super::derivatives::{
    constant, differentiable, point_error, seeded, seeded_pose, ConstrainedDerivatives, Residual, D1,
};
use super::error::ConstraintError;
use super::numeric::{right_hand_side, world_contacts, AtState};
use super::rows::{constraint_rows, ContactMotion};
use crate::dynamics::derivatives::lift_inertia;
use crate::dynamics::floating::{self, FloatingBase};
use crate::dynamics::frames::FrameMotion;
use crate::dynamics::joint::joint_transforms;
use crate::dynamics::joint_terms::with_joint_term_torques;
use crate::dynamics::kinematics::{body_poses, frame_pose};
use crate::dynamics::newton_euler::inverse_dynamics;
use crate::dynamics::{FloatingDynamics, FloatingState, NumericDynamics};
use crate::model::Contact;
use crate::spatial::{RigidInertia, Vec3};
use dyngen_runtime::{solve_contacts, ProximalSettings, Stabilisation};
use nalgebra::{DMatrix, DVector};

impl NumericDynamics<'_> {
    /// `∂q̈/∂(q, q̇, τ)` and `∂λ/∂(q, q̇, τ)` of [`NumericDynamics::constrained_forward_dynamics`]
    /// solved exactly (Pinocchio's `computeConstraintDynamicsDerivatives`). Stabilised frame
    /// contacts (whose error is a `log₆`) are refused.
    pub fn constrained_forward_dynamics_derivatives(
        &self,
        q: &[f64],
        qd: &[f64],
        tau: &[f64],
        contacts: &[Contact],
        stabilisation: Option<Stabilisation<'_>>,
    ) -> Result<ConstrainedDerivatives, ConstraintError> {
        let at = self.at_state(q, qd, Some(tau), contacts)?;
        let inertias: Vec<RigidInertia<D1>> = self.inertias.iter().map(lift_inertia).collect();
        let residual = |q: Vec<D1>, qd: Vec<D1>, a: &[f64], lambda: &[f64]| {
            let model = self.model;
            let x = joint_transforms(model, &q);
            let world = body_poses(model, &x);
            let a = constant(a);
            let rigid = inverse_dynamics(model, &x, &inertias, &qd, &a);
            let id = with_joint_term_torques(model, &self.joint_values, rigid, 0, (&qd, &qd, &a));
            let motions = ContactMotion::of(contacts, |k| {
                FrameMotion::new(model, &world, &qd, &model.frames()[k])
            });
            residual_of(
                id,
                &motions,
                &qd,
                a.as_slice(),
                lambda,
                tau,
                contacts,
                stabilisation,
            )
        };
        differentiate(
            &at,
            contacts,
            stabilisation,
            q.len(),
            |along, a, lambda| match along {
                Along::Configuration(k) => residual(seeded(q, Some(k)), constant(qd), a, lambda),
                Along::Velocity(k) => residual(constant(q), seeded(qd, Some(k)), a, lambda),
            },
        )
    }
}

impl FloatingDynamics<'_> {
    /// `∂ν̇/∂(q, ν, τ)` and `∂λ/∂(q, ν, τ)` of [`FloatingDynamics::constrained_forward_dynamics`]
    /// solved exactly, `q` moved in the tangent space (`q ⊕ δ`, `nv` columns), as Pinocchio's
    /// `computeConstraintDynamicsDerivatives`. Stabilised frame contacts are refused.
    pub fn constrained_forward_dynamics_derivatives(
        &self,
        s: &FloatingState,
        v: &[f64],
        tau: &[f64],
        contacts: &[Contact],
        stabilisation: Option<Stabilisation<'_>>,
    ) -> Result<ConstrainedDerivatives, ConstraintError> {
        let at = self.at_state(s, v, Some(tau), contacts)?;
        let inertias: Vec<RigidInertia<D1>> = self.inertias.iter().map(lift_inertia).collect();
        let base_inertia = lift_inertia(&self.base_inertia);
        let residual = |pose, joints: Vec<D1>, v: Vec<D1>, a: &[f64], lambda: &[f64]| {
            let model = self.model;
            let x = joint_transforms(model, &joints);
            let world = floating::floating_body_poses(model, &pose, &x);
            let base = FloatingBase {
                pose,
                inertia: base_inertia,
            };
            let a = constant(a);
            let rigid = floating::floating_inverse_dynamics(model, &base, &x, &inertias, &v, &a);
            let joints = (&v[6..], &v[6..], &a[6..]);
            let id = with_joint_term_torques(model, &self.joint_values, rigid, 6, joints);
            let motions = ContactMotion::of(contacts, |k| {
                let frame = &model.frames()[k];
                FrameMotion {
                    pose: frame_pose(Some(&base.pose), &world, frame),
                    jacobian: floating::floating_frame_jacobian(model, &base.pose, &world, frame),
                    jacobian_dot: floating::floating_frame_jacobian_dot(model, &base.pose, &world, &v, frame),
                }
            });
            residual_of(
                id,
                &motions,
                &v,
                a.as_slice(),
                lambda,
                tau,
                contacts,
                stabilisation,
            )
        };
        let fixed_pose = || {
            s.pose.map(|x| D1 {
                value: x,
                tangent: 0.0,
            })
        };
        differentiate(
            &at,
            contacts,
            stabilisation,
            v.len(),
            |along, a, lambda| match along {
                Along::Configuration(k @ 0..6) => residual(
                    seeded_pose(&s.pose, k),
                    constant(&s.joints),
                    constant(v),
                    a,
                    lambda,
                ),
                Along::Configuration(k) => residual(
                    fixed_pose(),
                    seeded(&s.joints, Some(k - 6)),
                    constant(v),
                    a,
                    lambda,
                ),
                Along::Velocity(k) => {
                    residual(fixed_pose(), constant(&s.joints), seeded(v, Some(k)), a, lambda)
                }
            },
        )
    }
}

/// A direction of the state: a configuration's (in the tangent space) or a velocity's.
#[derive(Clone, Copy)]
enum Along {
    Configuration(usize),
    Velocity(usize),
}

/// `F = ID − Jᵀ λ − τ` and `G = J a + drift + K_p e + K_d J ν` (module docs of
/// `derivatives.rs`), `id` inverse dynamics at `a` on the same dual state.
#[allow(clippy::too_many_arguments)]
fn residual_of(
    id: Vec<D1>,
    motions: &[ContactMotion<D1>],
    v: &[D1],
    a: &[D1],
    lambda: &[f64],
    tau: &[f64],
    contacts: &[Contact],
    stabilisation: Option<Stabilisation<'_>>,
) -> Residual {
    let rows = constraint_rows(contacts, motions, v);
    let j = &rows.jacobian;
    let lambda = constant(lambda);
    let motion = (0..id.len())
        .map(|i| {
            let jt_lambda = (0..j.nrows()).fold(D1::constant(0.0), |acc, r| acc + j[(r, i)] * lambda[r]);
            id[i] - jt_lambda - D1::constant(tau[i])
        })
        .collect();
    let mut g: Vec<D1> = (0..j.nrows())
        .map(|r| (0..j.ncols()).fold(rows.drift[r], |acc, i| acc + j[(r, i)] * a[i]))
        .collect();
    if let Some(stabilisation) = stabilisation {
        let (kp, kd) = (D1::constant(stabilisation.kp), D1::constant(stabilisation.kd));
        let (mut row, mut anchors) = (0, stabilisation.anchors.iter());
        for (contact, motion) in contacts.iter().zip(motions) {
            // Only points reach here (`differentiable`), held where the loop's other frame is or
            // at their anchor (one per contact with the world: counted by `differentiate`).
            let anchor = match &motion.to {
                Some(to) => to.pose.pos,
                None => match anchors.next() {
                    Some(anchor) => Vec3(std::array::from_fn(|i| D1::constant(anchor.translation[i]))),
                    None => break,
                },
            };
            let e = point_error(contact.reference, &motion.frame.pose, anchor);
            for k in 0..3 {
                g[row + k] = g[row + k] + kp * e[k] + kd * rows.velocity[row + k];
            }
            row += contact.kind.rows();
        }
    }
    Residual { motion, rows: g }
}

/// The derivatives from the residuals' tangents along each direction (`residual(along, a, λ)`),
/// with `n` velocity coordinates, at the exact solution of `at`.
fn differentiate(
    at: &AtState,
    contacts: &[Contact],
    stabilisation: Option<Stabilisation<'_>>,
    n: usize,
    residual: impl Fn(Along, &[f64], &[f64]) -> Residual,
) -> Result<ConstrainedDerivatives, ConstraintError> {
    if !differentiable(contacts, stabilisation.is_some()) {
        return Err(ConstraintError::Unsupported(
            "the derivatives of a stabilised frame contact (its error is a log₆)",
        ));
    }
    if let Some(s) = stabilisation {
        if s.anchors.len() != world_contacts(contacts) {
            return Err(dyngen_runtime::ContactError::Anchors {
                contacts: world_contacts(contacts),
                anchors: s.anchors.len(),
            }
            .into());
        }
    }
    let exact = ProximalSettings::default();
    let rhs = right_hand_side(at, contacts, stabilisation)?;
    let solved = solve_contacts(&at.rows.jacobian, &at.response, &at.free, &rhs, &exact, None)?;
    let (a, lambda) = (solved.acceleration.as_slice(), solved.forces.as_slice());
    let rows = at.rows.jacobian.nrows();
    let mut out = ConstrainedDerivatives {
        acceleration_q: DMatrix::zeros(n, n),
        acceleration_v: DMatrix::zeros(n, n),
        acceleration_tau: DMatrix::zeros(n, n),
        forces_q: DMatrix::zeros(rows, n),
        forces_v: DMatrix::zeros(rows, n),
        forces_tau: DMatrix::zeros(rows, n),
    };
    // `M ȧ − Jᵀ λ̇ = −Ḟ`, `J ȧ = −Ġ`: forward dynamics' system with `M⁻¹(−Ḟ)` for the free part.
    let change = |f_dot: Vec<f64>, g_dot: Vec<f64>| {
        let free = DVector::from_vec(at.mass.solve(&f_dot.iter().map(|x| -x).collect::<Vec<f64>>()));
        let rhs = -DVector::from_vec(g_dot);
        solve_contacts(&at.rows.jacobian, &at.response, &free, &rhs, &exact, None)
    };
    for k in 0..n {
        for (along, (acceleration, forces)) in [
            (
                Along::Configuration(k),
                (&mut out.acceleration_q, &mut out.forces_q),
            ),
            (Along::Velocity(k), (&mut out.acceleration_v, &mut out.forces_v)),
        ] {
            let r = residual(along, a, lambda);
            let tangents = |x: &[D1]| x.iter().map(|d| d.tangent).collect::<Vec<f64>>();
            let solved = change(tangents(&r.motion), tangents(&r.rows))?;
            acceleration.set_column(k, &solved.acceleration);
            forces.set_column(k, &solved.forces);
        }
        // Along `τ_k`: `Ḟ = −e_k`, `Ġ = 0`.
        let mut f_dot = vec![0.0; n];
        f_dot[k] = -1.0;
        let solved = change(f_dot, vec![0.0; rows])?;
        out.acceleration_tau.set_column(k, &solved.acceleration);
        out.forces_tau.set_column(k, &solved.forces);
    }
    Ok(out)
}
