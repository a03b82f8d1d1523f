//! What the controller is given each tick (measurement, desired motion) and the reference
//! velocity `q̇_r`, acceleration `q̈_r` and sliding variable `r` it computes from them.

use super::orientation::OrientationRows;
use super::projections::Projections;
use super::task::{ContactTask, Split};
use nalgebra::{Matrix3, SVector, Vector3};

/// What is measured: joint positions and velocities and the force the controlled frame (the
/// end-effector by default) exerts on the environment at its origin, `F̄` (base frame). No
/// joint acceleration, no force derivative.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measurement<const N: usize> {
    pub q: SVector<f64, N>,
    pub qd: SVector<f64, N>,
    pub force: Vector3<f64>,
}

/// The desired motion at one instant, with first and second derivatives: force `F_d` (S
/// controlled components), task position `x_d` (task frame), orientation `R_d` (base frame,
/// with angular velocity `ω_d` and acceleration `ω̇_d`, base axes: `Ṙ_d = [ω_d]× R_d`) and
/// null-space posture `q_ν`. It must satisfy `F_d = K (x_d − x_e)` where the force is
/// controlled (eq. 39); only the `K⁻` part of `x_d` enters the law. The orientation is used by
/// tasks of dimension 5 (only the direction of the tool axis, `R_d a_b`) and 6, and ignored by
/// the position task.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Desired<const N: usize, const S: usize> {
    pub force: SVector<f64, S>,
    pub force_dot: SVector<f64, S>,
    pub force_ddot: SVector<f64, S>,
    pub position: Vector3<f64>,
    pub velocity: Vector3<f64>,
    pub acceleration: Vector3<f64>,
    pub orientation: Matrix3<f64>,
    pub angular_velocity: Vector3<f64>,
    pub angular_acceleration: Vector3<f64>,
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
    /// `x̃ = x_t − x_d` (position rows).
    pub position_error: Vector3<f64>,
    /// The orientation error `e` (base axes, `sin φ · u`; zero for the position task).
    pub orientation_error: Vector3<f64>,
    /// `x_t − x_e`.
    pub deflection: Vector3<f64>,
    /// `J⁻ (q − q_ν)`.
    pub null_error: SVector<f64, N>,
}

/// Gains the reference needs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ReferenceGains {
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
///
/// `position` and `velocity` are those of the controlled frame's origin (base frame);
/// `orientation` holds the orientation rows at this state (see [`super::orientation`]); `proj`
/// the task Jacobian.
#[allow(clippy::too_many_arguments)]
#[inline]
pub(crate) fn reference<const N: usize, const S: usize, const T: usize>(
    m: &Measurement<N>,
    d: &Desired<N, S>,
    task: &ContactTask<T, S>,
    split: &Split<T, S>,
    position: &Vector3<f64>,
    velocity: &Vector3<f64>,
    orientation: &OrientationRows<T>,
    proj: &Projections<N, T>,
    gains: &ReferenceGains,
) -> Reference<N, S> {
    let rot = &task.rotation;
    let x_t = rot * position;
    let xd_t = rot * velocity;
    let deflection = x_t - task.contact_point;
    // K acts on the position rows only (its orientation columns are zero, checked at set-up).
    let k_pos = split.k.fixed_columns::<3>(0);
    let f_model = k_pos * deflection;
    let f_meas = task.force_selection * (rot * m.force);
    let force = SVector::<f64, S>::from_fn(|i, _| if f_model[i] > 0.0 { f_meas[i] } else { f_model[i] });
    let force_rate = k_pos * xd_t;

    let lambda = gains.lambda;
    let force_error = force - d.force;
    let position_error = x_t - d.position;
    let v_f = d.force_dot - force_error * lambda;
    let vd_f = d.force_ddot - (force_rate - d.force_dot) * lambda;
    // Task-frame v_x and its derivative: position rows, then the orientation rows P(ω_d − λe).
    let embed = |v: Vector3<f64>| SVector::<f64, T>::from_fn(|i, _| if i < 3 { v[i] } else { 0.0 });
    let mut v_x = embed(d.velocity - position_error * lambda);
    let mut vd_x = embed(d.acceleration - (xd_t - d.velocity) * lambda);
    if T > 3 {
        let o = orientation;
        let w_o = d.angular_velocity - o.error * lambda;
        v_x += o.p * w_o;
        vd_x += o.p_dot * w_o + o.p * (d.angular_acceleration - o.error_rate * lambda);
    }
    // R_T⁻¹ = diag(Rᵀ, I): only the position rows turn back to the base frame.
    let unrotate = |v: SVector<f64, T>| {
        let p = rot.tr_mul(&v.fixed_rows::<3>(0));
        SVector::<f64, T>::from_fn(|i, _| if i < 3 { p[i] } else { v[i] })
    };
    let w = unrotate(split.k_plus * v_f + split.k_minus * v_x);
    let wd = unrotate(split.k_plus * vd_f + split.k_minus * vd_x);

    let e_null = m.q - d.posture;
    let qd_d = d.posture_velocity - e_null * gains.lambda_null;
    let qdd_d = d.posture_acceleration - (m.qd - d.posture_velocity) * gains.lambda_null;

    // q̇_r = J⁺ w + J⁻ q̇_d and its derivative q̈_r: vectors only.
    let (qd_r, qdd_r) = proj.range_and_null_with_rate(&w, &wd, &qd_d, &qdd_d);
    Reference {
        qd_r,
        qdd_r,
        r: m.qd - qd_r,
        force_error,
        force,
        position_error,
        orientation_error: orientation.error,
        deflection,
        null_error: proj.null_mul(&e_null),
    }
}
