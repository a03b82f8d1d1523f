//! Compiled generated code against the generic f64 dynamics of the same description (1000
//! random states per robot) and against Pinocchio's reference values.

use dyngen_testkit as common;

use common::random_model::random_state;
use common::{assert_close, column, fixture};
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::Model;
use dyngen_generated::{Arm7, Arm7Friction, Panda, PandaRounded, Ur5, Xarm7, Xarm7Snapped};
use dyngen_runtime::nalgebra::{DMatrix, SMatrix, SVector};
use dyngen_runtime::{JointTrig, Kinematics, Regressors, RobotDynamics};
use std::path::Path;

const STATES: u64 = 1000;
const TOL_GENERIC: f64 = 1e-10;
const TOL_FIXTURE: f64 = 1e-9;

fn model(robot: &str) -> Model {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("robots")
        .join(format!("{robot}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

fn dm<const R: usize, const C: usize>(m: &dyngen_runtime::nalgebra::SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

fn sv<const N: usize>(x: &[f64]) -> SVector<f64, N> {
    SVector::from_column_slice(x)
}

/// Every quantity of the generated `R` against the generic algorithms at one state.
fn compare<R: Regressors<N, P>, const N: usize, const P: usize>(
    generic: &NumericDynamics,
    q: &[f64],
    qd: &[f64],
    v: &[f64],
    a: &[f64],
    tol: f64,
    at: &str,
) {
    let t = JointTrig::new(&sv::<N>(q));
    let (qd_, v_, a_) = (sv::<N>(qd), sv::<N>(v), sv::<N>(a));
    let pose = R::forward_kinematics(&t);
    // The fused kinematics compute the same nodes as the three functions (equal up to which
    // products fuse into multiply-adds, on targets with FMA).
    let (fused_pose, fused_j, fused_jd) = R::kinematics(&t, &qd_);
    assert_close(
        &format!("{at}: fused pose"),
        &dm(&fused_pose.rotation),
        &dm(&pose.rotation),
        1e-14,
    );
    assert_close(
        &format!("{at}: fused J"),
        &dm(&fused_j),
        &dm(&R::jacobian(&t)),
        1e-14,
    );
    assert_close(
        &format!("{at}: fused J̇"),
        &dm(&fused_jd),
        &dm(&R::jacobian_dot(&t, &qd_)),
        1e-14,
    );
    let (rot, pos) = generic.end_effector_pose(q);
    assert_close(&format!("{at}: ee rotation"), &dm(&pose.rotation), &dm(&rot), tol);
    assert_close(
        &format!("{at}: ee translation"),
        &dm(&pose.translation),
        &dm(&pos),
        tol,
    );
    assert_close(
        &format!("{at}: J"),
        &dm(&R::jacobian(&t)),
        &generic.jacobian(q),
        tol,
    );
    assert_close(
        &format!("{at}: J̇"),
        &dm(&R::jacobian_dot(&t, &qd_)),
        &generic.jacobian_dot(q, qd),
        tol,
    );
    assert_close(
        &format!("{at}: D"),
        &dm(&R::mass_matrix(&t)),
        &generic.mass_matrix(q),
        tol,
    );
    assert_close(
        &format!("{at}: C"),
        &dm(&R::coriolis_matrix(&t, &qd_)),
        &generic.coriolis_matrix(q, qd),
        tol,
    );
    assert_close(
        &format!("{at}: g"),
        &dm(&R::gravity(&t)),
        &column(generic.gravity_torque(q).as_slice()),
        tol,
    );
    let tau = generic.inverse_dynamics(q, qd, a);
    assert_close(
        &format!("{at}: τ"),
        &dm(&R::inverse_dynamics(&t, &qd_, &a_)),
        &column(tau.as_slice()),
        tol,
    );
    let sl = generic.slotine_li(q, qd, v, a, true);
    assert_close(
        &format!("{at}: Slotine–Li"),
        &dm(&R::slotine_li(&t, &qd_, &v_, &a_)),
        &column(sl.as_slice()),
        tol,
    );
    assert_close(
        &format!("{at}: Y"),
        &dm(&R::regressor(&t, &qd_, &v_, &a_)),
        &generic.regressor(q, qd, v, a),
        tol,
    );
    assert_close(
        &format!("{at}: Y in torque form"),
        &dm(&R::torque_regressor(&t, &qd_, &a_)),
        &generic.regressor(q, qd, qd, a),
        tol,
    );
}

fn against_generic<R: Regressors<N, P>, const N: usize, const P: usize>(robot: &str) {
    against_generic_at::<R, N, P>(robot, STATES);
}

fn against_generic_at<R: Regressors<N, P>, const N: usize, const P: usize>(robot: &str, states: u64) {
    let model = model(robot);
    assert_eq!(
        R::JOINT_NAMES.to_vec(),
        model.joints().iter().map(|j| j.name.as_str()).collect::<Vec<_>>()
    );
    assert_eq!(
        R::parameters().as_slice(),
        model.parameters().as_slice(),
        "{robot}: θ"
    );
    let generic = NumericDynamics::new(&model);
    for seed in 0..states {
        let s = random_state(&model, seed);
        compare::<R, N, P>(
            &generic,
            &s.q,
            &s.qd,
            &s.v,
            &s.a,
            TOL_GENERIC,
            &format!("{robot} seed {seed}"),
        );
    }
}

/// arm7 with joint-level columns: its joint terms (in `D`, `τ`, Slotine–Li and `Y`) against
/// the generic code; 200 states, the rigid-body part being arm7's, tested above at 1000.
#[test]
fn arm7_friction_generated_matches_generic() {
    against_generic_at::<Arm7Friction, 7, 98>("arm7_friction", 200);
}

/// `robots/arm7_friction.yaml` copies arm7's links and joints: same joints and limits, same
/// inertial parameters (the first 70 of its 98), same kinematics, and without its joint terms
/// the same mass matrix.
#[test]
fn arm7_friction_is_arm7_plus_joint_terms() {
    assert_eq!(Arm7Friction::JOINT_NAMES, Arm7::JOINT_NAMES);
    assert_eq!(Arm7Friction::JOINT_LIMITS, Arm7::JOINT_LIMITS);
    assert_eq!(
        &Arm7Friction::parameters().as_slice()[..70],
        Arm7::parameters().as_slice()
    );
    for seed in 0..20u64 {
        let q = SVector::<f64, 7>::from_fn(|i, _| ((seed * 7 + i as u64) as f64 * 0.37).sin() * 1.5);
        let t = JointTrig::new(&q);
        assert!((Arm7Friction::jacobian(&t) - Arm7::jacobian(&t)).amax() < 1e-12);
        let (a, b) = (Arm7Friction::forward_kinematics(&t), Arm7::forward_kinematics(&t));
        assert!((a.translation - b.translation).amax() < 1e-12 && (a.rotation - b.rotation).amax() < 1e-12);
        let dd = Arm7Friction::mass_matrix(&t) - Arm7::mass_matrix(&t);
        assert!(
            (dd - SMatrix::from_diagonal(&dd.diagonal())).amax() < 1e-12,
            "off-diagonal"
        );
        assert!(
            dd.diagonal().iter().all(|x| *x > 0.0),
            "armature on the diagonal: {dd}"
        );
    }
}

#[test]
fn arm7_generated_matches_generic() {
    against_generic::<Arm7, 7, 70>("arm7");
}

#[test]
fn panda_generated_matches_generic() {
    against_generic::<Panda, 7, 70>("panda");
}

#[test]
fn panda_rounded_generated_matches_generic() {
    against_generic::<PandaRounded, 7, 70>("panda_rounded");
}

/// A vendor URDF as written (`1.5708` quarter turns kept) and the same file snapped.
#[test]
fn xarm7_generated_matches_generic() {
    against_generic::<Xarm7, 7, 70>("xarm7");
    against_generic::<Xarm7Snapped, 7, 70>("xarm7_snapped");
}

#[test]
fn ur5_generated_matches_generic() {
    against_generic::<Ur5, 6, 60>("ur5");
}

/// Generated code for the described robot against Pinocchio's values for the same URDF.
fn against_fixture<R: Regressors<N, P>, const N: usize, const P: usize>(robot: &str) {
    let fx = fixture::load(robot);
    assert_close(
        &format!("{robot} θ"),
        &dm(&R::parameters()),
        &column(&fx.pi),
        TOL_FIXTURE,
    );
    for (k, s) in fx.states.iter().enumerate() {
        let at = |what: &str| format!("{robot} fixture state {k}: {what}");
        let t = JointTrig::new(&sv::<N>(&s.q));
        let (v, a, vr, ar) = (sv::<N>(&s.v), sv::<N>(&s.a), sv::<N>(&s.vr), sv::<N>(&s.ar));
        let pose = R::forward_kinematics(&t);
        assert_close(
            &at("ee rotation"),
            &dm(&pose.rotation),
            &s.ee_rotation,
            TOL_FIXTURE,
        );
        assert_close(
            &at("ee translation"),
            &dm(&pose.translation),
            &column(&s.ee_translation),
            TOL_FIXTURE,
        );
        assert_close(&at("J"), &dm(&R::jacobian(&t)), &s.j, TOL_FIXTURE);
        assert_close(&at("J̇"), &dm(&R::jacobian_dot(&t, &v)), &s.jdot, TOL_FIXTURE);
        assert_close(&at("D"), &dm(&R::mass_matrix(&t)), &s.d, TOL_FIXTURE);
        assert_close(&at("C"), &dm(&R::coriolis_matrix(&t, &v)), &s.c, TOL_FIXTURE);
        assert_close(&at("g"), &dm(&R::gravity(&t)), &column(&s.g), TOL_FIXTURE);
        assert_close(
            &at("τ"),
            &dm(&R::inverse_dynamics(&t, &v, &a)),
            &column(&s.tau),
            TOL_FIXTURE,
        );
        assert_close(
            &at("Slotine–Li τ"),
            &dm(&R::slotine_li(&t, &v, &vr, &ar)),
            &column(&s.tau_ref),
            TOL_FIXTURE,
        );
        assert_close(&at("Y"), &dm(&R::regressor(&t, &v, &v, &a)), &s.y, TOL_FIXTURE);
        assert_close(
            &at("Y in torque form"),
            &dm(&R::torque_regressor(&t, &v, &a)),
            &s.y,
            TOL_FIXTURE,
        );
    }
}

#[test]
fn panda_generated_matches_pinocchio() {
    against_fixture::<Panda, 7, 70>("panda");
}

/// The rounded Panda as generated with `snap_angles: 1e-4`, against Pinocchio's values for the
/// same URDF with the same angles snapped.
#[test]
fn panda_rounded_generated_matches_pinocchio() {
    against_fixture::<PandaRounded, 7, 70>("panda_rounded");
}

#[test]
fn ur5_generated_matches_pinocchio() {
    against_fixture::<Ur5, 6, 60>("ur5");
}

/// xarm7 as its vendor writes it, against Pinocchio's values for the same file.
#[test]
fn xarm7_generated_matches_pinocchio() {
    against_fixture::<Xarm7, 7, 70>("xarm7");
}
