//! URDFs of example-robot-data that no other test has (`codegen/tests/data/example-robot-data/`,
//! why each: its README), loaded as a user would (the bare file, with only `snap_angles: 1e-9`:
//! the fixtures' Pinocchio reads angles within 1e-9 rad of a quarter turn as exact), against
//! Pinocchio 4.1's reference values for the same file (`codegen/tests/fixtures/`, made by
//! `tools/fixtures.py`): the model (joints, parameters, end-effector), the generic dynamics,
//! and the traced graph that the generated code is printed from (through the interpreter),
//! every quantity to 1e-9 relative. `tools/sweep.py` does the same for every fixed-base robot
//! of the package with compiled generated code; CI keeps these four, one of them with inertias
//! that are not physical.

use dyngen_testkit as common;

use common::fixture::{self, Fixture, State};
use common::{assert_close, column, workspace_root};
use dyngen_codegen::description::{self, Choices, Loaded, NonPhysicalInertia};
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::generate::{trace, SymbolicRobot};
use nalgebra::DMatrix;

const TOL: f64 = 1e-9;

/// The choices the fixtures were made with: angles within 1e-9 rad of a quarter turn exact
/// (`exact_quarter_turns` in `tools/pinocchio_reference.py`), each a note.
fn fixture_choices() -> Choices {
    Choices {
        snap_angles: Some(1e-9),
        ..Choices::default()
    }
}

fn load(path: &str) -> Loaded {
    description::load_with(&workspace_root().join(path), &fixture_choices()).unwrap_or_else(|e| panic!("{e}"))
}

/// The fixture in the loaded model's joint order (checked to be the same joints).
fn fixture_for(robot: &str, loaded: &Loaded) -> Fixture {
    let fx = fixture::load(robot);
    let ours: Vec<&str> = loaded.model.joints().iter().map(|j| j.name.as_str()).collect();
    let mut sorted_ours = ours.clone();
    let mut theirs: Vec<&str> = fx.joint_names.iter().map(String::as_str).collect();
    sorted_ours.sort_unstable();
    theirs.sort_unstable();
    assert_eq!(sorted_ours, theirs, "{robot}: the moving joints");
    assert_eq!(
        loaded.model.end_effector().name,
        fx.json["ee_frame"].as_str().unwrap(),
        "{robot}: dyngen's end-effector is the fixture's frame"
    );
    fx.reordered(&ours)
}

fn pose_column(rotation: &DMatrix<f64>, translation: &[f64]) -> DMatrix<f64> {
    let mut values = rotation.as_slice().to_vec(); // column-major, as the traced pose
    values.extend_from_slice(translation);
    column(&values)
}

/// Generic dynamics of the loaded model against every field of one state.
fn check_generic(robot: &str, k: usize, dynamics: &NumericDynamics, s: &State) {
    let at = |what: &str| format!("{robot} state {k}, generic: {what}");
    fixture::assert_rigid_body_fields(dynamics, s, &at, TOL);
    assert_close(&at("Y"), &dynamics.regressor(&s.q, &s.v, &s.v, &s.a), &s.y, TOL);
    fixture::assert_forward_dynamics_fields(dynamics, s, &at, TOL);
}

/// The traced graph (what the generated functions compute) against every field of one state.
fn check_traced(robot: &str, k: usize, traced: &SymbolicRobot, theta: &[f64], s: &State) {
    let n = s.q.len();
    let at = |what: &str| format!("{robot} state {k}, traced: {what}");
    let none: &[f64] = &[];
    let matrix = |values: Vec<f64>, rows: usize| {
        let cols = values.len() / rows;
        DMatrix::from_column_slice(rows, cols, &values)
    };
    let eval = |name: &str, qd: &[f64], v: &[f64], a: &[f64], rows: usize| {
        matrix(traced.evaluate(name, &s.q, qd, v, a).expect(name), rows)
    };
    let eval_tau = |name: &str| matrix(traced.evaluate_tau(name, &s.q, &s.v, &s.tau).expect(name), n);
    let side_by_side = |left: &DMatrix<f64>, right: &DMatrix<f64>| {
        let mut both = DMatrix::zeros(n, 2 * n);
        both.columns_mut(0, n).copy_from(left);
        both.columns_mut(n, n).copy_from(right);
        both
    };
    assert_close(
        &at("ee pose"),
        &eval("forward_kinematics", none, none, none, 12),
        &pose_column(&s.ee_rotation, &s.ee_translation),
        TOL,
    );
    assert_close(&at("J"), &eval("jacobian", none, none, none, 6), &s.j, TOL);
    assert_close(&at("J̇"), &eval("jacobian_dot", &s.v, none, none, 6), &s.jdot, TOL);
    // The fused kinematics: pose, J and J̇ one after the other, as one column.
    let mut fused = pose_column(&s.ee_rotation, &s.ee_translation).as_slice().to_vec();
    fused.extend(s.j.iter().chain(s.jdot.iter()));
    let all = fused.len();
    assert_close(
        &at("(pose, J, J̇)"),
        &eval("kinematics", &s.v, none, none, all),
        &column(&fused),
        TOL,
    );
    assert_close(&at("D"), &eval("mass_matrix", none, none, none, n), &s.d, TOL);
    assert_close(&at("C"), &eval("coriolis_matrix", &s.v, none, none, n), &s.c, TOL);
    assert_close(
        &at("g"),
        &eval("gravity", none, none, none, n),
        &column(&s.g),
        TOL,
    );
    let tau = eval("inverse_dynamics", &s.v, none, &s.a, n);
    assert_close(&at("τ"), &tau, &column(&s.tau), TOL);
    let slotine_li = eval("slotine_li", &s.v, &s.vr, &s.ar, n);
    assert_close(&at("Slotine–Li τ"), &slotine_li, &column(&s.tau_ref), TOL);
    assert_close(&at("Y"), &eval("regressor", &s.v, &s.v, &s.a, n), &s.y, TOL);
    let y_b = eval("base_regressor", &s.v, &s.v, &s.a, n);
    let theta_b = column(&traced.base.base_parameters(theta));
    assert_close(&at("Y_b θ_b"), &(y_b * &theta_b), &column(&s.tau), TOL);
    // The torque-form regressors (identification's), traced as quantities of their own.
    assert_close(
        &at("torque-form Y"),
        &eval("torque_regressor", &s.v, none, &s.a, n),
        &s.y,
        TOL,
    );
    let y_b = eval("base_torque_regressor", &s.v, none, &s.a, n);
    assert_close(&at("torque-form Y_b θ_b"), &(y_b * theta_b), &column(&s.tau), TOL);
    assert_close(&at("q̈"), &eval_tau("forward_dynamics"), &column(&s.aba), TOL);
    assert_close(
        &at("D⁻¹"),
        &eval("mass_matrix_inverse", none, none, none, n),
        &s.minv,
        TOL,
    );
    assert_close(
        &at("∂τ/∂(q, q̇)"),
        &eval("inverse_dynamics_derivatives", &s.v, none, &s.a, n),
        &side_by_side(&s.dtau_dq, &s.dtau_dv),
        TOL,
    );
    assert_close(
        &at("∂q̈/∂(q, q̇)"),
        &eval_tau("forward_dynamics_derivatives"),
        &side_by_side(&s.dqdd_dq, &s.dqdd_dv),
        TOL,
    );
}

fn check(robot: &str, path: &str) -> Loaded {
    let loaded = load(path);
    let fx = fixture_for(robot, &loaded);
    let model = &loaded.model;
    let theta = model.parameters();
    assert_close(&format!("{robot} θ"), &column(&theta), &column(&fx.pi), TOL);
    let dynamics = NumericDynamics::new(model);
    let traced = trace(model);
    for (k, s) in fx.states.iter().enumerate() {
        check_generic(robot, k, &dynamics, s);
        check_traced(robot, k, &traced, &theta, s);
    }
    loaded
}

/// Another vendor's 2-DOF arm whose base is turned by `yaw -1.57`, 8e-4 rad short of a
/// quarter turn: dyngen says so, and keeps the angle as written (as Pinocchio does), so the
/// values still agree to 1e-9.
#[test]
fn asr_twodof_matches_pinocchio_and_warns_about_its_near_quarter_turn() {
    let loaded = check(
        "asr_twodof",
        "codegen/tests/data/example-robot-data/asr_twodof_description/TwoDofs.urdf",
    );
    assert_eq!(loaded.model.dof(), 2);
    assert!(
        loaded.warnings.len() == 1
            && loaded.warnings[0].contains("joint 'ground_fixed'")
            && loaded.warnings[0].contains("-1.57"),
        "{:?}",
        loaded.warnings
    );
}

/// Another vendor's 7-DOF arm whose quarter turns are written `1.5708` (3.7e-6 rad off):
/// one warning each, the angles kept as written, and the values agree with Pinocchio's.
#[test]
fn xarm7_matches_pinocchio_and_warns_about_its_rounded_quarter_turns() {
    let loaded = check(
        "xarm7",
        "codegen/tests/data/example-robot-data/xarm_description/xarm7.urdf",
    );
    assert_eq!(loaded.model.dof(), 7);
    assert_eq!(loaded.warnings.len(), 6, "{:?}", loaded.warnings);
    assert!(
        loaded
            .warnings
            .iter()
            .all(|w| w.contains("origin roll") && w.contains("1.5708 is 3.7e-6 from")),
        "{:?}",
        loaded.warnings
    );
}

/// A vendor URDF with inertias no real body has (four links break the triangle inequality by
/// 19-20%; Pinocchio loads them as written): loaded as written, one warning per link with its
/// place, and the dynamics agree with Pinocchio's; `inertia: strict` refuses it with one line,
/// `inertia: repair` makes every body physical.
#[test]
fn allegro_hand_with_non_physical_inertias_matches_pinocchio_as_written() {
    let path = "codegen/tests/data/example-robot-data/allegro_hand_description/allegro_right_hand.urdf";
    let loaded = check("allegro_right_hand", path);
    assert_eq!(loaded.model.dof(), 16);
    let places = [
        "143:7: link 'link_3.0'",
        "281:7: link 'link_7.0'",
        "419:7: link 'link_11.0'",
        "565:7: link 'link_15.0'",
    ];
    assert_eq!(loaded.warnings.len(), places.len(), "{:#?}", loaded.warnings);
    for (warning, place) in loaded.warnings.iter().zip(places) {
        assert!(
            warning.contains(&format!(
                "allegro_right_hand.urdf:{place}: inertia is not physical: triangle inequality broken by"
            )),
            "{warning}"
        );
    }
    assert!(loaded.warnings[0].contains("broken by 20%: I1 + I2 = 5.78591e-6 < I3 = 7.2659e-6 kg·m²"));

    let options = |inertia| Choices {
        inertia,
        ..fixture_choices()
    };
    let file = workspace_root().join(path);
    let error = description::load_with(&file, &options(NonPhysicalInertia::Strict))
        .expect_err("strict refuses link_3.0")
        .to_string();
    assert!(
        error.ends_with(
            "allegro_right_hand.urdf:143:7: link 'link_3.0': inertia is not physical: triangle inequality \
             broken by 20%: I1 + I2 = 5.78591e-6 < I3 = 7.2659e-6 kg·m²; `inertia: strict` refuses it"
        ),
        "{error}"
    );
    assert_eq!(error.lines().count(), 1, "{error}");
    let repaired =
        description::load_with(&file, &options(NonPhysicalInertia::Repair)).unwrap_or_else(|e| panic!("{e}"));
    assert!(repaired.warnings.is_empty(), "{:#?}", repaired.warnings);
    assert_eq!(
        repaired
            .notes
            .iter()
            .filter(|n| n.contains("repaired to the nearest physical inertia"))
            .count(),
        4
    );
    assert!(repaired
        .model
        .bodies()
        .iter()
        .all(|b| b.inertia.defect().is_none()));
    // Each defective link carries a fingertip (a fixed joint) that makes its body physical, so
    // only the values say the links were kept as written: they differ from the repaired ones.
    let theta = (loaded.model.parameters(), repaired.model.parameters());
    let differ = (0..theta.0.len()).filter(|&i| theta.0[i] != theta.1[i]).count();
    assert!(differ > 0 && differ <= 4 * 6, "{differ} parameters differ");
}

/// Continuous joints (Pinocchio stores each as (cos, sin)); meshes named by `package://` URLs
/// that dyngen does not read.
#[test]
fn kinova_with_continuous_joints_matches_pinocchio() {
    let loaded = check(
        "kinova",
        "codegen/tests/data/example-robot-data/kinova_description/kinova.urdf",
    );
    let model = &loaded.model;
    assert_eq!(model.dof(), 6);
    let continuous = model.joints().iter().filter(|j| j.limits.is_none()).count();
    assert_eq!(continuous, 3);
    let fx = fixture::load("kinova");
    assert_eq!(
        fx.json["nq"], 9,
        "Pinocchio: two coordinates per continuous joint"
    );
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
}
