//! The compiled floating-base robot (Solo-12, `robots/solo12.yaml`) against Pinocchio 4.1 with
//! `JointModelFreeFlyer` (`codegen/tests/fixtures/floating/solo12.json`) and against the generic
//! floating-base dynamics at random states, every function of `FloatingBaseDynamics`,
//! `FloatingRegressors`, `FloatingBaseParameters`, `FloatingForwardDynamics`,
//! `FloatingDynamicsDerivatives` and `FloatingFrameKinematics`; and the frames' `local` and
//! `world` quantities converted at run time (`robots/solo12_aligned_frames.yaml`).

use dyngen_testkit as common;

use common::fixture::{matrix, vector};
use common::floating_fixture::{self, Order};
use common::{assert_close, column, workspace_root};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::FloatingDynamics;
use dyngen_generated::solo12::{self, Frame, Solo12, Velocity, NV};
use dyngen_generated::solo12_aligned_frames::{self as aligned, Solo12AlignedFrames};
use dyngen_runtime::nalgebra::{DMatrix, SMatrix};
use dyngen_runtime::{
    ConfigurationError, FloatingBaseDynamics, FloatingBaseParameters, FloatingDynamicsDerivatives,
    FloatingForwardDynamics, FloatingFrameKinematics, FloatingRegressors, ReferenceFrame, RobotFrame,
    SplitMix64,
};

const TOL_FIXTURE: f64 = 1e-9;
const TOL_GENERIC: f64 = 1e-10;

fn dm<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

fn velocity(x: &[f64]) -> Velocity {
    Velocity::from_column_slice(x)
}

/// A random Solo-12 configuration (19 entries, the quaternion normalised) and `N` vectors of
/// `NV` entries in ±4.
fn random_state<const N: usize>(rng: &mut SplitMix64) -> (Vec<f64>, [Vec<f64>; N]) {
    let mut q: Vec<f64> = (0..19).map(|_| rng.uniform((-3.0, 3.0))).collect();
    let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
    q[3..7].iter_mut().for_each(|x| *x /= norm);
    let vectors = [0; N].map(|_| (0..NV).map(|_| rng.uniform((-4.0, 4.0))).collect::<Vec<f64>>());
    (q, vectors)
}

#[test]
fn solo12_matches_pinocchio() {
    let model = load(&workspace_root().join("robots/solo12.yaml")).unwrap().model;
    let fx = floating_fixture::load("solo12");
    let order = Order::new(&model, &fx);
    let pi = DMatrix::from_row_slice(1, 130, &vector(&fx["pi"]));
    let theta = Solo12::parameters();
    assert_close(
        "θ",
        &DMatrix::from_row_slice(1, 130, theta.as_slice()),
        &order.parameter_columns(&pi),
        TOL_FIXTURE,
    );
    for (k, st) in fx["states"].as_array().unwrap().iter().enumerate() {
        let what = |q: &str| format!("state {k}: {q}");
        let q = order.configuration(&vector(&st["q"]));
        let t = solo12::trig(&solo12::Configuration::from_column_slice(&q)).unwrap();
        let [v, a, vr, ar, tau] =
            ["v", "a", "vr", "ar", "tau"].map(|f| velocity(&order.vector(&vector(&st[f]))));
        let rows = |f: &str| column(&order.vector(&vector(&st[f])));
        assert_close(
            &what("D"),
            &dm(&Solo12::mass_matrix(&t)),
            &order.square(st, "D"),
            TOL_FIXTURE,
        );
        assert_close(
            &what("C"),
            &dm(&Solo12::coriolis_matrix(&t, &v)),
            &order.square(st, "C"),
            TOL_FIXTURE,
        );
        assert_close(&what("g"), &dm(&Solo12::gravity(&t)), &rows("g"), TOL_FIXTURE);
        assert_close(
            &what("tau"),
            &dm(&Solo12::inverse_dynamics(&t, &v, &a)),
            &rows("tau"),
            TOL_FIXTURE,
        );
        assert_close(
            &what("tau_ref"),
            &dm(&Solo12::slotine_li(&t, &v, &vr, &ar)),
            &rows("tau_ref"),
            TOL_FIXTURE,
        );
        let y = order.parameter_columns(&order.matrix(&matrix(&st["Y"]), true, false));
        assert_close(
            &what("Y"),
            &dm(&Solo12::regressor(&t, &v, &v, &a)),
            &y,
            TOL_FIXTURE,
        );
        // The base parameters of Pinocchio's θ, and the base regressors with them: the base
        // wrench and torques Pinocchio computes.
        let theta_b = Solo12::base_parameters(&theta);
        assert_close(
            &what("Y_b θ_b"),
            &dm(&(Solo12::base_torque_regressor(&t, &v, &a) * theta_b)),
            &rows("tau"),
            TOL_FIXTURE,
        );
        assert_close(
            &what("Slotine–Li Y_b θ_b"),
            &dm(&(Solo12::base_regressor(&t, &v, &vr, &ar) * theta_b)),
            &rows("tau_ref"),
            TOL_FIXTURE,
        );
        assert_close(
            &what("aba"),
            &dm(&Solo12::forward_dynamics(&t, &v, &tau)),
            &rows("aba"),
            TOL_FIXTURE,
        );
        assert_close(
            &what("Minv"),
            &dm(&Solo12::mass_matrix_inverse(&t)),
            &order.square(st, "Minv"),
            TOL_FIXTURE,
        );
        let (dtau_dq, dtau_dv) = Solo12::inverse_dynamics_derivatives(&t, &v, &a);
        assert_close(
            &what("dtau_dq"),
            &dm(&dtau_dq),
            &order.square(st, "dtau_dq"),
            TOL_FIXTURE,
        );
        assert_close(
            &what("dtau_dv"),
            &dm(&dtau_dv),
            &order.square(st, "dtau_dv"),
            TOL_FIXTURE,
        );
        let (dqdd_dq, dqdd_dv) = Solo12::forward_dynamics_derivatives(&t, &v, &tau);
        assert_close(
            &what("dqdd_dq"),
            &dm(&dqdd_dq),
            &order.square(st, "dqdd_dq"),
            TOL_FIXTURE,
        );
        assert_close(
            &what("dqdd_dv"),
            &dm(&dqdd_dv),
            &order.square(st, "dqdd_dv"),
            TOL_FIXTURE,
        );
        assert_close(
            &what("com"),
            &dm(&Solo12::center_of_mass(&t)),
            &column(&vector(&st["com"])),
            TOL_FIXTURE,
        );
        let ag = order.matrix(&matrix(&st["Ag"]), false, true);
        assert_close(
            &what("Ag"),
            &dm(&Solo12::centroidal_momentum_matrix(&t)),
            &ag,
            TOL_FIXTURE,
        );
        assert_close(
            &what("dAg_v"),
            &dm(&Solo12::centroidal_bias(&t, &v)),
            &column(&vector(&st["dAg_v"])),
            TOL_FIXTURE,
        );
        // The feet and the trunk's frame on the base body.
        assert_eq!(Frame::ALL.len(), st["frames"].as_object().unwrap().len());
        for frame in Frame::ALL.iter().copied() {
            let expected = &st["frames"][frame.name()];
            let pose = Solo12::frame_pose(frame, &t);
            assert_close(
                &what("translation"),
                &dm(&pose.translation),
                &column(&vector(&expected["translation"])),
                TOL_FIXTURE,
            );
            assert_close(
                &what("rotation"),
                &dm(&pose.rotation),
                &matrix(&expected["rotation"]),
                TOL_FIXTURE,
            );
            let columns = |field: &str| order.matrix(&matrix(&expected[field]), false, true);
            let lwa = ReferenceFrame::LocalWorldAligned;
            assert_close(
                &what("J"),
                &dm(&Solo12::frame_jacobian(frame, lwa, &t)),
                &columns("J_lwa"),
                TOL_FIXTURE,
            );
            let local = Solo12::frame_jacobian(frame, ReferenceFrame::Local, &t);
            assert_close(&what("J local"), &dm(&local), &columns("J_local"), TOL_FIXTURE);
            let jdot = Solo12::frame_jacobian_time_variation(frame, lwa, &t, &v);
            assert_close(&what("Jdot"), &dm(&jdot), &columns("Jdot_lwa"), TOL_FIXTURE);
        }
    }
}

/// Every function against the generic floating-base dynamics at random states (random base
/// orientations, velocities and joints).
#[test]
fn solo12_matches_the_generic_dynamics() {
    let model = load(&workspace_root().join("robots/solo12.yaml")).unwrap().model;
    let generic = FloatingDynamics::new(&model).unwrap();
    let base = BaseParameterSet::compute(&model);
    let theta = Solo12::parameters();
    assert_close(
        "θ_b",
        &dm(&Solo12::base_parameters(&theta)),
        &column(&base.base_parameters(theta.as_slice())),
        TOL_GENERIC,
    );
    let mut rng = SplitMix64::new(12);
    for k in 0..200 {
        let what = |q: &str| format!("state {k}: {q}");
        let (q, [v, a, vr, tau]) = random_state(&mut rng);
        let t = solo12::trig(&solo12::Configuration::from_column_slice(&q)).unwrap();
        let s = generic.state(&q).unwrap();
        let (vv, av, vrv, tauv) = (velocity(&v), velocity(&a), velocity(&vr), velocity(&tau));
        assert_close(
            &what("D"),
            &dm(&Solo12::mass_matrix(&t)),
            &generic.mass_matrix(&s),
            TOL_GENERIC,
        );
        assert_close(
            &what("C"),
            &dm(&Solo12::coriolis_matrix(&t, &vv)),
            &generic.coriolis_matrix(&s, &v),
            TOL_GENERIC,
        );
        let tau_generic = generic.slotine_li(&s, &v, &vr, &a);
        assert_close(
            &what("τ_ref"),
            &dm(&Solo12::slotine_li(&t, &vv, &vrv, &av)),
            &column(tau_generic.as_slice()),
            TOL_GENERIC,
        );
        let y = generic.regressor(&s, &v, &vr, &a);
        assert_close(
            &what("Y"),
            &dm(&Solo12::regressor(&t, &vv, &vrv, &av)),
            &y,
            TOL_GENERIC,
        );
        assert_close(
            &what("Y_b"),
            &dm(&Solo12::base_regressor(&t, &vv, &vrv, &av)),
            &base.base_regressor(&y),
            TOL_GENERIC,
        );
        let torque_y = generic.regressor(&s, &v, &v, &a);
        assert_close(
            &what("torque-form Y_b"),
            &dm(&Solo12::base_torque_regressor(&t, &vv, &av)),
            &base.base_regressor(&torque_y),
            TOL_GENERIC,
        );
        let (dq, dv) = generic.inverse_dynamics_derivatives(&s, &v, &a);
        let (gq, gv) = Solo12::inverse_dynamics_derivatives(&t, &vv, &av);
        assert_close(&what("∂τ/∂q"), &dm(&gq), &dq, TOL_GENERIC);
        assert_close(&what("∂τ/∂ν"), &dm(&gv), &dv, TOL_GENERIC);
        let (dq, dv) = generic.forward_dynamics_derivatives(&s, &v, &tau);
        let (gq, gv) = Solo12::forward_dynamics_derivatives(&t, &vv, &tauv);
        assert_close(&what("∂ν̇/∂q"), &dm(&gq), &dq, TOL_GENERIC);
        assert_close(&what("∂ν̇/∂ν"), &dm(&gv), &dv, TOL_GENERIC);
        let forward = generic.forward_dynamics(&s, &v, &tau);
        assert_close(
            &what("ν̇"),
            &dm(&Solo12::forward_dynamics(&t, &vv, &tauv)),
            &column(forward.as_slice()),
            TOL_GENERIC,
        );
        for (index, frame) in Frame::ALL.iter().copied().enumerate() {
            for reference in ReferenceFrame::ALL {
                let jdot = generic.frame_jacobian_time_variation(&s, &v, index, reference);
                let generated = Solo12::frame_jacobian_time_variation(frame, reference, &t, &vv);
                assert_close(&what("J̇"), &dm(&generated), &jdot, TOL_GENERIC);
                let velocity = generic.frame_velocity(&s, &v, index, reference);
                let generated = Solo12::frame_velocity(frame, reference, &t, &vv);
                assert_close(
                    &what("frame velocity"),
                    &dm(&generated),
                    &dm(&velocity),
                    TOL_GENERIC,
                );
                let acceleration = generic.frame_classical_acceleration(&s, &v, &a, index, reference);
                let generated = Solo12::frame_classical_acceleration(frame, reference, &t, &vv, &av);
                assert_close(
                    &what("frame acceleration"),
                    &dm(&generated),
                    &dm(&acceleration),
                    TOL_GENERIC,
                );
            }
        }
    }
}

#[test]
fn a_configuration_that_is_not_one_is_refused() {
    let mut q = solo12::Configuration::zeros();
    q[6] = 1.2;
    assert!(matches!(
        solo12::trig(&q),
        Err(ConfigurationError::NonUnitQuaternion(_))
    ));
    q[6] = 1.0;
    assert!(solo12::trig(&q).is_ok());
    let short = [0.0; 12];
    assert!(matches!(
        dyngen_runtime::FloatingTrig::<12>::from_configuration(&short),
        Err(ConfigurationError::Length {
            expected: 19,
            found: 12
        })
    ));
}

/// With `frame_references: aligned` the frame functions in `local` and `world` are conversions
/// of those in base axes: each equals the generic dynamics' own, in every reference frame.
#[test]
fn frames_converted_from_base_axes_match_the_generic_dynamics() {
    let model = load(&workspace_root().join("robots/solo12_aligned_frames.yaml"))
        .unwrap()
        .model;
    let generic = FloatingDynamics::new(&model).unwrap();
    let mut rng = SplitMix64::new(21);
    for k in 0..50 {
        let what = |q: &str| format!("state {k}: {q}");
        let (q, [v, a]) = random_state(&mut rng);
        let t = aligned::trig(&aligned::Configuration::from_column_slice(&q)).unwrap();
        let s = generic.state(&q).unwrap();
        let (vv, av) = (velocity(&v), velocity(&a));
        for (index, frame) in aligned::Frame::ALL.iter().copied().enumerate() {
            for reference in ReferenceFrame::ALL {
                let what = |q: &str| what(&format!("frame {} {q} {}", frame.name(), reference.keyword()));
                assert_close(
                    &what("J"),
                    &dm(&Solo12AlignedFrames::frame_jacobian(frame, reference, &t)),
                    &generic.frame_jacobian(&s, index, reference),
                    TOL_GENERIC,
                );
                assert_close(
                    &what("J̇"),
                    &dm(&Solo12AlignedFrames::frame_jacobian_time_variation(
                        frame, reference, &t, &vv,
                    )),
                    &generic.frame_jacobian_time_variation(&s, &v, index, reference),
                    TOL_GENERIC,
                );
                assert_close(
                    &what("velocity"),
                    &dm(&Solo12AlignedFrames::frame_velocity(frame, reference, &t, &vv)),
                    &dm(&generic.frame_velocity(&s, &v, index, reference)),
                    TOL_GENERIC,
                );
                assert_close(
                    &what("acceleration"),
                    &dm(&Solo12AlignedFrames::frame_classical_acceleration(
                        frame, reference, &t, &vv, &av,
                    )),
                    &dm(&generic.frame_classical_acceleration(&s, &v, &a, index, reference)),
                    TOL_GENERIC,
                );
            }
        }
    }
}

/// The derivatives of forward dynamics composed from Solo-12's own `∂τ/∂x`, `D` and `τ`
/// through the tree factor (`code_shape: composed`, the base's six coordinates a chain above
/// the legs) against its straight-line ones, at random states.
#[test]
fn composed_derivatives_are_the_flat_ones_on_a_floating_base() {
    use dyngen_codegen::internals::dynamics::velocity_parents;
    use dyngen_runtime::__private::{composed, tree_factor::Tree};
    let model = load(&workspace_root().join("robots/solo12.yaml")).unwrap().model;
    let parents: [Option<usize>; NV] = velocity_parents(&model).try_into().expect("NV coordinates");
    let tree = Tree::new(parents);
    let mut rng = SplitMix64::new(31);
    for k in 0..50 {
        let (q, [v, tau]) = random_state::<2>(&mut rng);
        let t = solo12::trig(&solo12::Configuration::from_column_slice(&q)).expect("a unit quaternion");
        let (v, tau) = (velocity(&v), velocity(&tau));
        let bias = Solo12::inverse_dynamics(&t, &v, &Velocity::zeros());
        let (dq, dv) =
            composed::forward_dynamics_derivatives(&tree, Solo12::mass_matrix(&t), tau - bias, |a| {
                Solo12::inverse_dynamics_derivatives(&t, &v, a)
            });
        let (flat_q, flat_v) = Solo12::forward_dynamics_derivatives(&t, &v, &tau);
        assert_close(&format!("state {k}: ∂ν̇/∂q"), &dm(&dq), &dm(&flat_q), TOL_GENERIC);
        assert_close(&format!("state {k}: ∂ν̇/∂ν"), &dm(&dv), &dm(&flat_v), TOL_GENERIC);
    }
}
