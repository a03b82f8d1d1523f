//! Energy regressors: the total energy `H = T + V` and the power of the dissipative joint
//! terms, linear in θ, for identification without accelerations.
//!
//! - Kinetic: `T = Σ_i ½ v_iᵀ I_i v_i` with `v_i` body `i`'s spatial velocity in its own frame
//!   and `I_i` its inertia about the frame origin, which is linear in the body's ten
//!   parameters: `m·½|v|² + h·(v × ω) + ½ ωᵀ I_o ω`. The armature adds `½ I_a q̇_j²` (a rotor
//!   spinning with its joint). So `T = e_T(q, q̇)·θ = ½ q̇ᵀ D(q) q̇`.
//! - Potential: `V = −Σ_i gᵀ (m_i p_i + R_i h_i)`, the bodies' mass centres in the base frame,
//!   so `∂V/∂q = g(q)`. It is defined up to a constant: a parameter whose potential column is
//!   constant (the first moment along the axis of a base joint that turns about gravity) changes
//!   no torque, and only differences of `H` are observable.
//! - Power of the joint terms other than the armature (viscous, Coulomb, offset): `q̇ᵀ τ_terms =
//!   e_P(q̇)·θ`, entry `q̇_j · column` in each such column. They do no conservative work, so
//!   over `[t0, t1]`: `∫ q̇ᵀ τ dt = [e_T + e_V]_{t0}^{t1}·θ + ∫ e_P dt·θ`.
//!
//! Columns follow [`Model::parameters`](crate::model::Model::parameters): ten per body, then
//! the joint-level ones.

use super::coupling::expand;
use super::joint_terms::column_entry;
use super::kinematics::body_poses;
use super::slotine_li::{forward_pass, gravity_vector};
use super::NumericDynamics;
use crate::model::{JointTermKind, Model};
use crate::scalar::Scalar;
use crate::spatial::{RigidInertia, Transform};
use dyngen_runtime::PARAMETERS_PER_BODY;
use nalgebra::DVector;

/// `e_T(q, q̇)` with `e_T·θ = T`, from the joint transforms at `q`.
pub fn kinetic_energy_regressor<S: Scalar>(model: &Model, x: &[Transform<S>], qd: &[S]) -> Vec<S> {
    let rates = expand(model, qd);
    let zero = vec![S::zero(); rates.len()];
    let motions = forward_pass(model, x, &rates, &rates, &zero, None);
    let half = S::from_f64(0.5);
    let mut e = vec![S::zero(); model.parameter_count()];
    for (i, m) in motions.iter().enumerate() {
        for k in 0..PARAMETERS_PER_BODY {
            let momentum = RigidInertia::unit(k).mul_motion(&m.vel);
            e[PARAMETERS_PER_BODY * i + k] = half * momentum.power(&m.vel);
        }
    }
    for (j, &rate) in qd.iter().enumerate() {
        if let Some(col) = model.joint_term_index(j, JointTermKind::Armature) {
            e[col] = half * rate * rate;
        }
    }
    e
}

/// `e_V(q)` with `e_V·θ = V`, zero at the base frame's origin.
pub fn potential_energy_regressor<S: Scalar>(model: &Model, x: &[Transform<S>]) -> Vec<S> {
    let g = gravity_vector::<S>(model);
    let mut e = vec![S::zero(); model.parameter_count()];
    for (i, pose) in body_poses(model, x).iter().enumerate() {
        let col = PARAMETERS_PER_BODY * i;
        e[col] = -g.dot(&pose.pos);
        // gᵀ R h = (Rᵀ g)ᵀ h.
        let local = pose.rot.tr_mul_vec(&g);
        for c in 0..3 {
            e[col + 1 + c] = -local.0[c];
        }
    }
    e
}

/// `e_P(q̇)` with `e_P·θ = q̇ᵀ τ_terms`, the power of the viscous, Coulomb and offset terms.
pub fn joint_term_power_regressor<S: Scalar>(model: &Model, qd: &[S]) -> Vec<S> {
    let mut e = vec![S::zero(); model.parameter_count()];
    let zero = vec![S::zero(); qd.len()];
    for (j, &rate) in qd.iter().enumerate() {
        for &kind in &model.joint_terms().kinds {
            if kind == JointTermKind::Armature {
                continue;
            }
            if let Some(col) = model.joint_term_index(j, kind) {
                e[col] = rate * column_entry(model, kind, j, qd, qd, &zero);
            }
        }
    }
    e
}

impl NumericDynamics<'_> {
    /// `e_T(q, q̇)`: `e_T·θ` is the kinetic energy `½ q̇ᵀ D(q) q̇` (armature included).
    pub fn kinetic_energy_regressor(&self, q: &[f64], qd: &[f64]) -> DVector<f64> {
        let x = self.configuration(q).transforms;
        DVector::from_vec(kinetic_energy_regressor(self.model, &x, qd))
    }

    /// `e_V(q)`: `e_V·θ` is the potential energy in gravity, whose gradient is `g(q)`.
    pub fn potential_energy_regressor(&self, q: &[f64]) -> DVector<f64> {
        let x = self.configuration(q).transforms;
        DVector::from_vec(potential_energy_regressor(self.model, &x))
    }

    /// `e_T + e_V`: the total energy's regressor.
    pub fn energy_regressor(&self, q: &[f64], qd: &[f64]) -> DVector<f64> {
        let x = self.configuration(q).transforms;
        let t = kinetic_energy_regressor(self.model, &x, qd);
        let v = potential_energy_regressor(self.model, &x);
        DVector::from_iterator(t.len(), t.iter().zip(&v).map(|(a, b)| a + b))
    }

    /// `e_P(q̇)`: `e_P·θ` is the power `q̇ᵀ τ` of the viscous, Coulomb and offset terms.
    pub fn joint_term_power_regressor(&self, qd: &[f64]) -> DVector<f64> {
        assert_eq!(qd.len(), self.model.dof(), "q̇ has the wrong length");
        DVector::from_vec(joint_term_power_regressor(self.model, qd))
    }
}
