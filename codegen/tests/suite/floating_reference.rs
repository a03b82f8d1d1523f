//! Floating-base robots of example-robot-data (a quadruped and a humanoid,
//! `codegen/tests/data/example-robot-data/`) and a torso with a gripper whose mimic joints are a
//! prismatic finger (multiplier −1, offset 0.01) and a revolute tail on a branch of its own
//! (`codegen/tests/data/mimic/floating_gripper.urdf`), loaded with `floating_base`, against
//! Pinocchio 4.1's values for the same URDF with `JointModelFreeFlyer` (and `mimic=True`)
//! (`codegen/tests/fixtures/floating/`, made by `tools/floating_fixtures.py`): the base body,
//! every dynamics quantity and the
//! derivatives of inverse and forward dynamics in the tangent space, frames,
//! the centroidal momentum and the configuration space's `integrate` and `difference`, joint by
//! joint name, to 1e-9 relative; and the traced graph that generated code is printed from
//! (through the interpreter), function by function.

use dyngen_testkit as common;

use common::fixture::{matrix, vector};
use common::floating_fixture::{self, Order};
use common::{assert_close, column, workspace_root};
use dyngen_codegen::description::{self, Choices, FrameSelection, FrameSpec, Loaded};
use dyngen_codegen::dynamics::FloatingDynamics;
use dyngen_codegen::internals::generate::{trace, Arguments, SymbolicRobot};
use dyngen_runtime::ReferenceFrame;
use nalgebra::DMatrix;
use serde_json::Value;

const TOL: f64 = 1e-9;

/// The robot as a user loads it, with the fixture's frames (the G1's IMU rides on the base
/// body).
fn load(urdf: &str, fixture: &Value) -> Loaded {
    let frames: Vec<FrameSpec> = fixture["frames"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| FrameSpec::link(f["name"].as_str().unwrap()))
        .collect();
    let options = Choices {
        floating_base: true,
        end_effector: Some(frames[0].clone()),
        frames: FrameSelection::Listed(frames),
        ..Choices::default()
    };
    let path = workspace_root().join("codegen/tests/data").join(urdf);
    description::load_with(&path, &options).unwrap_or_else(|e| panic!("{e}"))
}

fn check_robot(robot: &str, urdf: &str) {
    let fx = floating_fixture::load(robot);
    let loaded = load(urdf, &fx);
    let model = &loaded.model;
    assert_eq!(
        model.floating_base().unwrap().name,
        fx["base_body"].as_str().unwrap()
    );
    assert_eq!(
        (model.nq(), model.nv()),
        (
            fx["nq"].as_u64().unwrap() as usize,
            fx["nv"].as_u64().unwrap() as usize
        )
    );
    let order = Order::new(&loaded.model, &fx);
    let dynamics = FloatingDynamics::new(model).unwrap();
    let pi = DMatrix::from_row_slice(1, vector(&fx["pi"]).len(), &vector(&fx["pi"]));
    assert_close(
        &format!("{robot}: parameters (base first)"),
        &DMatrix::from_row_slice(1, pi.ncols(), &dynamics.parameters()),
        &order.parameter_columns(&pi),
        TOL,
    );
    let traced = trace(model);
    let states = fx["states"].as_array().unwrap();
    for (k, st) in states.iter().enumerate() {
        let what = |q: &str| format!("{robot} state {k}: {q}");
        let q = order.configuration(&vector(&st["q"]));
        let [v, a, vr, ar] = ["v", "a", "vr", "ar"].map(|f| order.vector(&vector(&st[f])));
        let reorder = |f: &str| order.square(st, f);
        let rows = |f: &str| column(&order.vector(&vector(&st[f])));
        let s = dynamics.state(&q).unwrap();
        assert_close(&what("D"), &dynamics.mass_matrix(&s), &reorder("D"), TOL);
        assert_close(&what("C"), &dynamics.coriolis_matrix(&s, &v), &reorder("C"), TOL);
        assert_close(
            &what("g"),
            &column(dynamics.gravity(&s).as_slice()),
            &rows("g"),
            TOL,
        );
        let tau = dynamics.inverse_dynamics(&s, &v, &a);
        assert_close(&what("tau"), &column(tau.as_slice()), &rows("tau"), TOL);
        assert_close(
            &what("tau_ref"),
            &column(dynamics.slotine_li(&s, &v, &vr, &ar).as_slice()),
            &rows("tau_ref"),
            TOL,
        );
        let y = order.parameter_columns(&order.matrix(&matrix(&st["Y"]), true, false));
        assert_close(&what("Y"), &dynamics.regressor(&s, &v, &v, &a), &y, TOL);
        assert_close(
            &what("aba"),
            &column(dynamics.forward_dynamics(&s, &v, tau.as_slice()).as_slice()),
            &rows("aba"),
            TOL,
        );
        assert_close(
            &what("Minv"),
            &dynamics.mass_matrix_inverse(&s),
            &reorder("Minv"),
            TOL,
        );
        let (dtau_dq, dtau_dv) = dynamics.inverse_dynamics_derivatives(&s, &v, &a);
        assert_close(&what("dtau_dq"), &dtau_dq, &reorder("dtau_dq"), TOL);
        assert_close(&what("dtau_dv"), &dtau_dv, &reorder("dtau_dv"), TOL);
        let (dqdd_dq, dqdd_dv) = dynamics.forward_dynamics_derivatives(&s, &v, tau.as_slice());
        assert_close(&what("dqdd_dq"), &dqdd_dq, &reorder("dqdd_dq"), TOL);
        assert_close(&what("dqdd_dv"), &dqdd_dv, &reorder("dqdd_dv"), TOL);
        let (mass, com, ag) = dynamics.centroidal_momentum_matrix(&s);
        assert!(mass > 0.0);
        assert_close(
            &what("com"),
            &column(com.as_slice()),
            &column(&vector(&st["com"])),
            TOL,
        );
        assert_close(
            &what("Ag"),
            &ag,
            &order.matrix(&matrix(&st["Ag"]), false, true),
            TOL,
        );
        assert_close(
            &what("Jcom"),
            &dynamics.center_of_mass_jacobian(&s),
            &order.matrix(&matrix(&st["Jcom"]), false, true),
            TOL,
        );
        assert_close(
            &what("dAg_v"),
            &column(dynamics.centroidal_bias(&s, &v).as_slice()),
            &column(&vector(&st["dAg_v"])),
            TOL,
        );
        let mut frames_compared = 0;
        for (f, frame) in st["frames"].as_object().unwrap() {
            let index = (model.frames().iter().position(|m| m.name == *f))
                .unwrap_or_else(|| panic!("{}", what(&format!("frame {f} is not loaded"))));
            frames_compared += 1;
            let (rotation, translation) = dynamics.frame_pose(&s, index);
            assert_close(
                &what(&format!("{f} translation")),
                &column(translation.as_slice()),
                &column(&vector(&frame["translation"])),
                TOL,
            );
            assert_close(
                &what(&format!("{f} rotation")),
                &DMatrix::from_column_slice(3, 3, rotation.as_slice()),
                &matrix(&frame["rotation"]),
                TOL,
            );
            let columns = |field: &str| order.matrix(&matrix(&frame[field]), false, true);
            let lwa = ReferenceFrame::LocalWorldAligned;
            assert_close(
                &what(&format!("{f} J")),
                &dynamics.frame_jacobian(&s, index, lwa),
                &columns("J_lwa"),
                TOL,
            );
            assert_close(
                &what(&format!("{f} J local")),
                &dynamics.frame_jacobian(&s, index, ReferenceFrame::Local),
                &columns("J_local"),
                TOL,
            );
            assert_close(
                &what(&format!("{f} Jdot")),
                &dynamics.frame_jacobian_time_variation(&s, &v, index, lwa),
                &columns("Jdot_lwa"),
                TOL,
            );
        }
        assert_eq!(
            frames_compared,
            model.frames().len(),
            "{}",
            what("every frame compared")
        );
        check_traced(
            &traced,
            &order,
            order.parameter_columns(&pi).as_slice(),
            st,
            &what,
        );
        let moved = dynamics.integrate(&q, &v, 0.1).unwrap();
        assert_close(
            &what("integrate"),
            &column(&moved),
            &column(&order.configuration(&vector(&st["integrate"]))),
            TOL,
        );
        let next = order.configuration(&vector(&states[(k + 1) % states.len()]["q"]));
        let difference = dynamics.difference(&q, &next).unwrap();
        assert_close(
            &what("difference"),
            &column(&difference),
            &column(&order.vector(&vector(&st["difference"]))),
            TOL,
        );
    }
}

/// Every traced function of the floating base at one state, through the interpreter.
/// `theta`: Pinocchio's standard parameters in the model's order.
fn check_traced(
    traced: &SymbolicRobot,
    order: &Order,
    theta: &[f64],
    st: &Value,
    what: &dyn Fn(&str) -> String,
) {
    let q = order.configuration(&vector(&st["q"]));
    let [v, a, vr, ar, tau] = ["v", "a", "vr", "ar", "tau"].map(|f| order.vector(&vector(&st[f])));
    let nv = v.len();
    let eval = |name: &str, args: Arguments| -> Vec<f64> {
        traced
            .evaluate_with(name, &args)
            .unwrap_or_else(|| panic!("{}", what(&format!("{name} is not traced"))))
    };
    let square = |values: Vec<f64>| DMatrix::from_column_slice(nv, nv, &values);
    fn at<'a>(q: &'a [f64], qd: &'a [f64], v: &'a [f64], a: &'a [f64]) -> Arguments<'a> {
        Arguments {
            q,
            qd,
            v,
            a,
            ..Arguments::default()
        }
    }
    let none = at(&q, &[], &[], &[]);
    let rows = |f: &str| column(&order.vector(&vector(&st[f])));
    assert_close(
        &what("traced D"),
        &square(eval("mass_matrix", none)),
        &order.square(st, "D"),
        TOL,
    );
    assert_close(
        &what("traced C"),
        &square(eval("coriolis_matrix", at(&q, &v, &[], &[]))),
        &order.square(st, "C"),
        TOL,
    );
    assert_close(
        &what("traced g"),
        &column(&eval("gravity", none)),
        &rows("g"),
        TOL,
    );
    assert_close(
        &what("traced tau"),
        &column(&eval("inverse_dynamics", at(&q, &v, &[], &a))),
        &rows("tau"),
        TOL,
    );
    assert_close(
        &what("traced tau_ref"),
        &column(&eval("slotine_li", at(&q, &v, &vr, &ar))),
        &rows("tau_ref"),
        TOL,
    );
    let y = eval("regressor", at(&q, &v, &v, &a));
    let expected_y = order.parameter_columns(&order.matrix(&matrix(&st["Y"]), true, false));
    assert_close(
        &what("traced Y"),
        &DMatrix::from_column_slice(nv, y.len() / nv, &y),
        &expected_y,
        TOL,
    );
    // The base regressors: Pinocchio's columns of the base parameters, and with θ_b (of
    // Pinocchio's θ) the base wrench and torques Pinocchio computes.
    let base = &traced.base;
    let theta_b = column(&base.base_parameters(theta));
    let y_b = eval("base_torque_regressor", at(&q, &v, &[], &a));
    let y_b = DMatrix::from_column_slice(nv, base.count(), &y_b);
    assert_close(&what("traced Y_b"), &y_b, &base.base_regressor(&expected_y), TOL);
    assert_close(&what("traced Y_b θ_b"), &(&y_b * &theta_b), &rows("tau"), TOL);
    let y_b = eval("base_regressor", at(&q, &v, &vr, &ar));
    let y_b = DMatrix::from_column_slice(nv, base.count(), &y_b);
    assert_close(
        &what("traced Slotine–Li Y_b θ_b"),
        &(&y_b * &theta_b),
        &rows("tau_ref"),
        TOL,
    );
    let forward = eval(
        "forward_dynamics",
        Arguments {
            q: &q,
            qd: &v,
            tau: &tau,
            ..Arguments::default()
        },
    );
    assert_close(&what("traced aba"), &column(&forward), &rows("aba"), TOL);
    assert_close(
        &what("traced Minv"),
        &square(eval("mass_matrix_inverse", none)),
        &order.square(st, "Minv"),
        TOL,
    );
    let pair = |values: Vec<f64>| {
        let (first, second) = values.split_at(nv * nv);
        (square(first.to_vec()), square(second.to_vec()))
    };
    let (dtau_dq, dtau_dv) = pair(eval("inverse_dynamics_derivatives", at(&q, &v, &[], &a)));
    assert_close(
        &what("traced dtau_dq"),
        &dtau_dq,
        &order.square(st, "dtau_dq"),
        TOL,
    );
    assert_close(
        &what("traced dtau_dv"),
        &dtau_dv,
        &order.square(st, "dtau_dv"),
        TOL,
    );
    let (dqdd_dq, dqdd_dv) = pair(eval(
        "forward_dynamics_derivatives",
        Arguments {
            q: &q,
            qd: &v,
            tau: &tau,
            ..Arguments::default()
        },
    ));
    assert_close(
        &what("traced dqdd_dq"),
        &dqdd_dq,
        &order.square(st, "dqdd_dq"),
        TOL,
    );
    assert_close(
        &what("traced dqdd_dv"),
        &dqdd_dv,
        &order.square(st, "dqdd_dv"),
        TOL,
    );
    assert_close(
        &what("traced com"),
        &column(&eval("center_of_mass", none)),
        &column(&vector(&st["com"])),
        TOL,
    );
    let ag = eval("centroidal_momentum_matrix", none);
    let expected_ag = order.matrix(&matrix(&st["Ag"]), false, true);
    assert_close(
        &what("traced Ag"),
        &DMatrix::from_column_slice(6, nv, &ag),
        &expected_ag,
        TOL,
    );
    let bias = eval("centroidal_bias", at(&q, &v, &[], &[]));
    assert_close(
        &what("traced dAg_v"),
        &column(&bias),
        &column(&vector(&st["dAg_v"])),
        TOL,
    );
    let mut frames_compared = 0;
    for (f, frame) in st["frames"].as_object().unwrap() {
        let snake = f.to_lowercase();
        let jacobian = eval(&format!("frame_jacobian_{snake}_local_world_aligned"), none);
        frames_compared += 1;
        let expected = order.matrix(&matrix(&frame["J_lwa"]), false, true);
        assert_close(
            &what(&format!("traced {f} J")),
            &DMatrix::from_column_slice(6, nv, &jacobian),
            &expected,
            TOL,
        );
        let jdot = eval(
            &format!("frame_jacobian_time_variation_{snake}_local_world_aligned"),
            at(&q, &v, &[], &[]),
        );
        let expected = order.matrix(&matrix(&frame["Jdot_lwa"]), false, true);
        assert_close(
            &what(&format!("traced {f} Jdot")),
            &DMatrix::from_column_slice(6, nv, &jdot),
            &expected,
            TOL,
        );
        let pose = eval(&format!("frame_pose_{snake}"), none);
        assert_close(
            &what(&format!("traced {f} translation")),
            &column(&pose[9..]),
            &column(&vector(&frame["translation"])),
            TOL,
        );
    }
    assert_eq!(
        frames_compared,
        st["frames"].as_object().unwrap().len(),
        "{}",
        what("traced frames")
    );
}

#[test]
fn quadruped_matches_pinocchio() {
    check_robot("solo12", "example-robot-data/solo_description/solo12.urdf");
}

#[test]
fn humanoid_matches_pinocchio() {
    check_robot("g1", "example-robot-data/g1_description/g1_29dof_rev_1_0.urdf");
}

#[test]
fn mimic_joints_on_a_floating_base_match_pinocchio() {
    check_robot("floating_gripper", "mimic/floating_gripper.urdf");
}
