//! The sharpest consistency check of `D`, `C`, `g`, `Y` and `q̈_r`: with the closed loop
//! (plant + adaptive law, θ̂ part of the state) integrated by RK4 at the controller rate, the
//! controller evaluated at every stage, in permanent contact and without noise,
//! `V = ½ rᵀ D r + ½ θ̃ᵀ Γ⁻¹ θ̃` never rises by more than 1e-9 (relative) on a step and
//! `V + ∫ rᵀ G r` stays constant to 1e-6 (relative). For the position task (m = 3) and for
//! the tasks with orientation rows, m = 6 (pose) and m = 5 (tool axis), while the desired
//! orientation turns the tool to vertical. And with the Panda's flange `panda_link8` as the
//! controlled frame (pose task, contact at the flange).
//!
//! With true joint friction and armature (arm7_friction, joint terms adapted too) the loop
//! dissipates more: the law's viscous column is `F_v q̇_r`, the plant's `F_v q̇`, so
//! `D ṙ + C r + (G + F_v) r = Y θ̃` and `V + ∫ rᵀ (G + F_v) r` is the constant (the Coulomb and
//! offset columns are functions of the measured state and cancel exactly; the armature is a
//! constant on `D`'s diagonal and keeps `Ḋ − 2C` skew). So there `V + ∫ rᵀ G r` falls, by
//! exactly `∫ rᵀ F_v r`.
//!
//! With the composite adaptation (`θ̂̇ = −Γ (Yᵀ r + Wᵀ R e)`, the prediction filter part of the
//! state) the prediction error dissipates too: `V + ∫ rᵀ (G + F_v) r + ∫ eᵀ R e` is the
//! constant. That holds only if `W θ = τ_f` at every instant, i.e. if the momentum form of the
//! filtered regressor (`Y_p`, `Y_q` and the difference along `q̇`) is the plant's dynamics and
//! the torque filtered is the one the plant feels (`τ − Jᵀ F̄`).

use dyngen_control::controller::{
    parameter_error_energy, Adaptation, Composite, Measurement, PredictionFilter,
};
use dyngen_control::sim::{rk4_step, start_posture_for, Demo, DemoOptions, RkState, RunKind};
use dyngen_generated::{arm7, arm7_friction, panda};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{JointTrig, Parameterization};

#[derive(Clone, Copy)]
struct Loop<const M: usize> {
    q: SVector<f64, 7>,
    qd: SVector<f64, 7>,
    theta: SVector<f64, M>,
    /// The composite adaptation's prediction filter (unused by the other laws).
    filter: PredictionFilter<7, M>,
    /// `∫ rᵀ G r`.
    dissipated: f64,
    /// `∫ rᵀ F_v r`, the true viscous friction's share.
    friction_dissipated: f64,
    /// `∫ eᵀ R e`, the prediction error's share (composite adaptation).
    prediction_dissipated: f64,
}

impl<const M: usize> RkState for Loop<M> {
    fn axpy(&self, h: f64, k: &Self) -> Self {
        Loop {
            q: self.q + k.q * h,
            qd: self.qd + k.qd * h,
            theta: self.theta + k.theta * h,
            filter: PredictionFilter {
                momentum: self.filter.momentum + k.filter.momentum * h,
                rest: self.filter.rest + k.filter.rest * h,
                torque: self.filter.torque + k.filter.torque * h,
            },
            dissipated: self.dissipated + k.dissipated * h,
            friction_dissipated: self.friction_dissipated + k.friction_dissipated * h,
            prediction_dissipated: self.prediction_dissipated + k.prediction_dissipated * h,
        }
    }
}

/// The standard parameters (ten per body): `Y` and the generated `D`, `C`, `g` agree.
#[test]
fn lyapunov_function_decreases_by_exactly_the_dissipation() {
    lyapunov_check::<arm7::Standard, { arm7::PARAMETER_COUNT }, 3>();
}

/// The base parameters (the default), for the controller and the plant.
#[test]
fn lyapunov_function_decreases_by_exactly_the_dissipation_on_base_parameters() {
    lyapunov_check::<arm7::Base, { arm7::BASE_PARAMETER_COUNT }, 3>();
}

/// Task dimension 6: position and orientation (1-D null space on arm7).
#[test]
fn lyapunov_with_orientation_rows() {
    lyapunov_check::<arm7::Base, { arm7::BASE_PARAMETER_COUNT }, 6>();
}

/// Task dimension 5: position and tool axis (free rotation about it).
#[test]
fn lyapunov_with_tool_axis_rows() {
    lyapunov_check::<arm7::Base, { arm7::BASE_PARAMETER_COUNT }, 5>();
}

/// True friction and armature off their nominal values, joint terms adapted (base
/// parameters): `V + ∫ rᵀ (G + F_v) r` is the constant.
#[test]
fn lyapunov_with_joint_friction_and_armature_adapted() {
    let friction = lyapunov_check::<arm7_friction::Base, { arm7_friction::BASE_PARAMETER_COUNT }, 3>();
    // Not a vacuous extension: the friction's share of the dissipation is visible at the
    // tolerance of the check by far.
    assert!(friction > 1e-4, "∫rᵀF_v r / V(0) = {friction:.2e}");
}

/// The composite adaptation on arm7: `V + ∫ rᵀ G r + ∫ eᵀ R e` is the constant, and the
/// prediction error's share is not negligible.
#[test]
fn lyapunov_with_the_composite_adaptation() {
    let demo = Demo::<arm7::Base, 7, { arm7::BASE_PARAMETER_COUNT }, 3>::new(
        composite(),
        start::<arm7::Base, { arm7::BASE_PARAMETER_COUNT }>(),
    )
    .expect("valid demo");
    let (_, predicted) = lyapunov_of(demo, RunKind::Composite);
    assert!(predicted > 1e-2, "∫eᵀRe / V(0) = {predicted:.2e}");
}

/// The composite adaptation with true joint friction and armature, joint terms adapted, pose
/// task: the filtered regressor's friction and armature columns and the contact torque through
/// the frame's Jacobian are consistent with the plant.
#[test]
fn lyapunov_with_the_composite_adaptation_and_joint_friction() {
    type Z = arm7_friction::Base;
    const M: usize = arm7_friction::BASE_PARAMETER_COUNT;
    let demo = Demo::<Z, 7, M, 6>::new(composite(), start::<Z, M>()).expect("valid demo");
    let (friction, predicted) = lyapunov_of(demo, RunKind::Composite);
    assert!(friction > 1e-4, "∫rᵀF_v r / V(0) = {friction:.2e}");
    assert!(predicted > 1e-2, "∫eᵀRe / V(0) = {predicted:.2e}");
}

/// [`pressing`] with the composite adaptation at its default filter. The weight is the
/// largest the explicit RK4 step of this test integrates stably: the prediction term is stiff
/// (`Γ Wᵀ R W` has the mass gains times `(g·lever)²`), which is why the controller's own tick
/// steps it implicitly.
fn composite() -> DemoOptions {
    DemoOptions {
        composite: Some(Composite {
            weight: WEIGHT,
            ..Composite::default()
        }),
        ..pressing()
    }
}

const WEIGHT: f64 = 1e-3;

/// At a named frame other than the end-effector (the Panda's flange `panda_link8`, pose task):
/// the frame's generated `J` and `J̇` are consistent in the closed loop as the end-effector's
/// are, with the contact at that frame too.
#[test]
fn lyapunov_at_a_named_frame() {
    type Z = panda::Base;
    const M: usize = panda::BASE_PARAMETER_COUNT;
    let demo = Demo::<Z, 7, M, 6>::new_at_frame(pressing(), start::<Z, M>(), panda::Frame::PandaLink8)
        .expect("valid demo");
    assert_eq!(demo.controlled_frame(), Some("panda_link8"));
    lyapunov_of(demo, RunKind::Adaptive);
}

fn start<Z: Parameterization<7, M>, const M: usize>() -> SVector<f64, 7> {
    start_posture_for::<Z::Robot, 7>(None).expect("start posture")
}

/// Start pressing (0.5 mm into the table, 5 N), so that the contact never opens.
fn pressing() -> DemoOptions {
    DemoOptions {
        start_height: -0.0005,
        ..DemoOptions::default()
    }
}

/// [`lyapunov_of`] the demo at the end-effector.
fn lyapunov_check<Z: Parameterization<7, M>, const M: usize, const T: usize>() -> f64 {
    lyapunov_of(
        Demo::<Z, 7, M, T>::new(pressing(), start::<Z, M>()).expect("valid demo"),
        RunKind::Adaptive,
    )
    .0
}

/// Runs the closed loop of the law of `kind` and checks `V`; returns `∫ rᵀ F_v r / V(0)` (0
/// without friction) and `∫ eᵀ R e / V(0)` (0 but for the composite adaptation).
fn lyapunov_of<Z: Parameterization<7, M>, const M: usize, const T: usize>(
    demo: Demo<Z, 7, M, T>,
    kind: RunKind,
) -> (f64, f64) {
    let q0 = demo.q0;
    let ctrl = demo.controller(kind).expect("valid controller");
    let weight = match ctrl.config().adaptation {
        Adaptation::Composite(c) => c.weight,
        _ => 0.0,
    };
    let g = demo.g;
    let gamma = demo.gamma;
    let theta_true = demo.theta_true;
    let plant = &demo.plant;
    // Constant coefficients: found once (0 for a robot without a viscous column).
    let viscous = plant.viscous_friction(&JointTrig::new(&q0));

    let mut min_penetration = f64::INFINITY;
    let mut f = |t: f64, x: &Loop<M>| -> Result<(Loop<M>, f64), String> {
        let trig = JointTrig::new(&x.q);
        // A compliant table: the force is the deflection's, whatever the torque.
        let st = dyngen_control::sim::PlantState { q: x.q, qd: x.qd };
        let force = plant
            .contact_force(&st, &SVector::zeros())
            .map_err(|e| e.to_string())?;
        min_penetration = min_penetration.min(force.z.abs());
        let m = Measurement {
            q: x.q,
            qd: x.qd,
            force,
        };
        let (out, filter_rate) = ctrl
            .evaluate_composite(&m, &demo.scenario.desired(t), &x.theta, &x.filter)
            .map_err(|e| e.to_string())?;
        assert!(!out.saturated && out.damping == 0.0);
        let r = out.reference.r;
        let (qdd, _) = plant.acceleration(&st, &out.tau).map_err(|e| e.to_string())?;
        let theta_err = x.theta - theta_true;
        let v = 0.5 * r.dot(&(plant.mass_matrix(&trig) * r)) + parameter_error_energy(&theta_err, &gamma);
        Ok((
            Loop {
                q: x.qd,
                qd: qdd,
                theta: out.theta_hat_dot,
                filter: filter_rate,
                dissipated: r.dot(&(g * r)),
                friction_dissipated: r.dot(&viscous.component_mul(&r)),
                prediction_dissipated: weight * out.prediction_error.norm_squared(),
            },
            v,
        ))
    };

    let dt = demo.options.sim.control_period;
    let steps = 3000;
    let start = Measurement {
        q: q0,
        qd: SVector::zeros(),
        force: plant
            .contact_force(&dyngen_control::sim::PlantState::at_rest(q0), &SVector::zeros())
            .expect("compliant"),
    };
    let mut x = Loop {
        q: q0,
        qd: SVector::zeros(),
        theta: demo.theta_hat0,
        filter: ctrl.prediction_filter_start(&start),
        dissipated: 0.0,
        friction_dissipated: 0.0,
        prediction_dissipated: 0.0,
    };
    let (_, v0) = f(0.0, &x).expect("first evaluation");
    let (mut v_prev, mut rises, mut worst_rise, mut worst_drift) = (v0, 0, 0.0f64, 0.0f64);
    // The largest `V + ∫ rᵀ G r − V(0)` (relative): ≤ 0 up to integration error, since the
    // friction only adds dissipation.
    let mut worst_excess = f64::NEG_INFINITY;
    for k in 0..steps {
        let t = k as f64 * dt;
        x = rk4_step(t, &x, dt, |t, s| f(t, s).map(|(d, _)| d)).expect("closed loop step");
        let (_, v) = f(t + dt, &x).expect("evaluation");
        let rise = (v - v_prev) / v_prev;
        if rise > 0.0 {
            rises += 1;
            worst_rise = worst_rise.max(rise);
        }
        worst_drift = worst_drift
            .max(((v + x.dissipated + x.friction_dissipated + x.prediction_dissipated) - v0).abs() / v0);
        worst_excess = worst_excess.max((v + x.dissipated + x.prediction_dissipated - v0) / v0);
        v_prev = v;
    }
    println!(
        "{M} parameters, task dimension {T}: V(0) = {v0:.6e}, V(end) = {v_prev:.6e}, ∫rᵀGr = {:.6e}; V rose on {rises} of {steps} steps \
         (worst {worst_rise:.2e} relative); ∫rᵀF_v r = {:.6e}; ∫eᵀRe = {:.6e}; \
         max |V + ∫rᵀ(G + F_v)r + ∫eᵀRe − V(0)|/V(0) = {worst_drift:.2e}; \
         max (V + ∫rᵀGr + ∫eᵀRe − V(0))/V(0) = {worst_excess:.2e}; min contact force {min_penetration:.3} N",
        x.dissipated, x.friction_dissipated, x.prediction_dissipated
    );
    assert!(min_penetration > 0.0, "the contact opened");
    // Not a trivial run: a substantial share of V(0) is dissipated.
    assert!(
        x.dissipated > 0.1 * v0,
        "∫rᵀGr = {} for V(0) = {v0}",
        x.dissipated
    );
    assert!(
        worst_rise <= 1e-9,
        "V rose by {worst_rise:.3e} relative on a step"
    );
    assert!(
        worst_drift <= 1e-6,
        "V + ∫rᵀ(G + F_v)r + ∫eᵀRe drifted by {worst_drift:.3e} relative"
    );
    assert!(
        worst_excess <= 1e-6,
        "V + ∫rᵀGr + ∫eᵀRe rose above V(0) by {worst_excess:.3e} relative"
    );
    (x.friction_dissipated / v0, x.prediction_dissipated / v0)
}
