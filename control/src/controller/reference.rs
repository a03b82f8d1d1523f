//! What the controller is given each tick (measurement, desired motion) and the reference
//! velocity `q̇_r`, acceleration `q̈_r` and sliding variable `r` it computes from them.

use super::projections::Projections;
use super::task::{ContactTask, Split};
use nalgebra::{SMatrix, SVector, Vector3};

/// What is measured: joint positions and velocities and the force the end-effector exerts on
/// the environment `F̄` (base frame). No joint acceleration, no force derivative.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement<const N: usize> {
    pub q: SVector<f64, N>,
    pub qd: SVector<f64, N>,
    pub force: Vector3<f64>,
}

/// The desired motion at one instant, with first and second derivatives: force `F_d` (S
/// controlled components), task position `x_d` (task frame) and null-space posture `q_ν`.
/// It must satisfy `F_d = K (x_d − x_e)` where the force is controlled (eq. 39); only the
/// `K⁻` part of `x_d` enters the law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Desired<const N: usize, const S: usize> {
    pub force: SVector<f64, S>,
    pub force_dot: SVector<f64, S>,
    pub force_ddot: SVector<f64, S>,
    pub position: Vector3<f64>,
    pub velocity: Vector3<f64>,
    pub acceleration: Vector3<f64>,
    pub posture: SVector<f64, N>,
    pub posture_velocity: SVector<f64, N>,
    pub posture_acceleration: SVector<f64, N>,
}

/// `q̇_r`, `q̈_r`, `r` and the errors they are made of.
#[derive(Clone, Copy, Debug)]
pub struct Reference<const N: usize, const S: usize> {
    pub qd_r: SVector<f64, N>,
    pub qdd_r: SVector<f64, N>,
    pub r: SVector<f64, N>,
    /// `F̃ = F_t − F_d`.
    pub force_error: SVector<f64, S>,
    /// `F_t` as used (measured in contact, contact model in free space).
    pub force: SVector<f64, S>,
    /// `x̃ = x_t − x_d`.
    pub position_error: Vector3<f64>,
    /// `x_t − x_e`.
    pub deflection: Vector3<f64>,
    /// `J⁻ (q − q_ν)`.
    pub null_error: SVector<f64, N>,
}

/// Gains the reference needs.
#[derive(Clone, Copy, Debug)]
pub struct ReferenceGains {
    pub lambda: f64,
    pub lambda_null: f64,
}

/// Computes the reference (the note's A.3 and its analytic derivative).
///
/// The force derivative comes from the contact model, `Ḟ_t = K R J q̇` (Remark 4). `F_t` is the
/// measured `Σ R F̄` for rows in contact and the contact model `K (x_t − x_e)` (≤ 0: a signed
/// distance to the known surface) for rows out of contact, decided from the kinematics. Both
/// are 0 at touch-down, so `F_t` is continuous, and with an exact `K` and `x_e` its derivative
/// *is* `K R J q̇` on both sides: `q̈_r` stays the derivative of `q̇_r` through contact changes
/// and the approach can be commanded with the same law (a desired `F_d < 0` is a desired
/// distance). This replaces the note's guard (`Ḟ_t = 0` when `F̄ = 0`), which makes `q̈_r`
/// inconsistent in free space.
#[allow(clippy::too_many_arguments)]
#[inline]
pub fn reference<const N: usize, const S: usize>(
    m: &Measurement<N>,
    d: &Desired<N, S>,
    task: &ContactTask<S>,
    split: &Split<S>,
    position: &Vector3<f64>,
    j: &SMatrix<f64, 3, N>,
    proj: &Projections<N>,
    gains: &ReferenceGains,
) -> Reference<N, S> {
    let rot = &task.rotation;
    let x_t = rot * position;
    let xd_t = rot * (j * m.qd);
    let deflection = x_t - task.contact_point;
    let f_model = split.k * deflection;
    let f_meas = task.force_selection * (rot * m.force);
    let force = SVector::<f64, S>::from_fn(|i, _| if f_model[i] > 0.0 { f_meas[i] } else { f_model[i] });
    let force_rate = split.k * xd_t;

    let lambda = gains.lambda;
    let force_error = force - d.force;
    let position_error = x_t - d.position;
    let v_f = d.force_dot - force_error * lambda;
    let v_x = d.velocity - position_error * lambda;
    let vd_f = d.force_ddot - (force_rate - d.force_dot) * lambda;
    let vd_x = d.acceleration - (xd_t - d.velocity) * lambda;
    let w = rot.tr_mul(&(split.k_plus * v_f + split.k_minus * v_x));
    let wd = rot.tr_mul(&(split.k_plus * vd_f + split.k_minus * vd_x));

    let e_null = m.q - d.posture;
    let qd_d = d.posture_velocity - e_null * gains.lambda_null;
    let qdd_d = d.posture_acceleration - (m.qd - d.posture_velocity) * gains.lambda_null;

    // q̇_r = J⁺ w + J⁻ q̇_d = J⁺ (w − J q̇_d) + q̇_d, and its derivative
    // q̈_r = d(J⁺)/dt (w − J q̇_d) + J⁺ (ẇ − J̇ q̇_d − J q̈_d) + q̈_d: vectors only.
    let jd = proj.jd();
    let qd_r = proj.pinv_mul(&(w - j * qd_d)) + qd_d;
    let qdd_r = proj.pinv_dot_mul(&(w - j * qd_d)) + proj.pinv_mul(&(wd - jd * qd_d - j * qdd_d)) + qdd_d;
    Reference {
        qd_r,
        qdd_r,
        r: m.qd - qd_r,
        force_error,
        force,
        position_error,
        deflection,
        null_error: proj.null_mul(&e_null),
    }
}
