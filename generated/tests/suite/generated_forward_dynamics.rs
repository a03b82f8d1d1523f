//! Compiled generated forward dynamics, `D⁻¹` and derivatives of the dynamics: against the
//! generic f64 algorithms (random states), against Pinocchio's reference values, and against
//! oracles that use none of our dynamics algorithms twice: `D⁻¹ D = I` (CRBA vs the tree
//! factorisation), `FD(ID(q̈)) = q̈` (RNEA vs CRBA + factorisation) and central differences of
//! the generated `τ` and `q̈` (the derivative functions vs the functions themselves).

use dyngen_testkit as common;

use common::oracles::jacobian_by_differences;
use common::random_model::random_state;
use common::{assert_close, column, fixture};
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::dynamics::velocity_parents;
use dyngen_codegen::model::Model;
use dyngen_generated::{Arm7, Arm7Friction, Panda, PandaRounded, Ur5, Ur5Composed};
use dyngen_runtime::__private::{composed, tree_factor::Tree};
use dyngen_runtime::nalgebra::{DMatrix, SMatrix, SVector};
use dyngen_runtime::{DynamicsDerivatives, ForwardDynamics, JointTrig, RobotDynamics};
use std::path::Path;

const STATES: u64 = 200;
const TOL_GENERIC: f64 = 1e-10;
const TOL_FIXTURE: f64 = 1e-9;
/// Identities in floating point (`D⁻¹ D`, `FD(ID(q̈))`): conditioning of `D` costs digits.
const TOL_IDENTITY: f64 = 1e-9;
/// Richardson-extrapolated central differences with step [`STEP`]: errors of about 1e-12
/// relative (Panda, first state: 9e-13 for `∂τ/∂q`), so 1e-8 still catches any wrong term.
const TOL_DIFFERENCE: f64 = 1e-8;
/// Smaller than `common::oracles::STEP`: near-singular `D` gives `q̈(q)` large higher
/// derivatives (arm7, one state: error 2e-6 at h = 1e-2, 9e-10 at 1e-3, of entries of 350).
const STEP: f64 = 1e-3;

fn model(robot: &str) -> Model {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .join("robots")
        .join(format!("{robot}.yaml"));
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

fn dm<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> DMatrix<f64> {
    DMatrix::from_column_slice(R, C, m.as_slice())
}

fn sv<const N: usize>(x: &[f64]) -> SVector<f64, N> {
    SVector::from_column_slice(x)
}

fn fd<R: ForwardDynamics<N, P> + DynamicsDerivatives<N, P>, const N: usize, const P: usize>(
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
) -> DMatrix<f64> {
    dm(&R::forward_dynamics(&JointTrig::new(&sv(q)), &sv(qd), &sv(tau)))
}

fn id<R: ForwardDynamics<N, P> + DynamicsDerivatives<N, P>, const N: usize, const P: usize>(
    q: &[f64],
    qd: &[f64],
    qdd: &[f64],
) -> DMatrix<f64> {
    dm(&R::inverse_dynamics(&JointTrig::new(&sv(q)), &sv(qd), &sv(qdd)))
}

/// The Jacobian of `f` at `x` by extrapolated central differences.
fn differenced(f: impl Fn(&[f64]) -> DMatrix<f64>, x: &[f64]) -> DMatrix<f64> {
    jacobian_by_differences(f, x, STEP)
}

fn against_generic<R: ForwardDynamics<N, P> + DynamicsDerivatives<N, P>, const N: usize, const P: usize>(
    robot: &str,
) {
    let model = model(robot);
    let generic = NumericDynamics::new(&model);
    for seed in 0..STATES {
        let s = random_state(&model, seed);
        let at = |what: &str| format!("{robot} seed {seed}: {what}");
        let t = JointTrig::new(&sv::<N>(&s.q));
        let (qd, a) = (sv::<N>(&s.qd), sv::<N>(&s.a));
        assert_close(
            &at("q̈"),
            &dm(&R::forward_dynamics(&t, &qd, &a)),
            &column(generic.forward_dynamics(&s.q, &s.qd, &s.a).as_slice()),
            TOL_GENERIC,
        );
        assert_close(
            &at("D⁻¹"),
            &dm(&R::mass_matrix_inverse(&t)),
            &generic.mass_matrix_inverse(&s.q),
            TOL_GENERIC,
        );
        let (dq, dv) = R::inverse_dynamics_derivatives(&t, &qd, &a);
        let (gq, gv) = generic.inverse_dynamics_derivatives(&s.q, &s.qd, &s.a);
        assert_close(&at("∂τ/∂q"), &dm(&dq), &gq, TOL_GENERIC);
        assert_close(&at("∂τ/∂q̇"), &dm(&dv), &gv, TOL_GENERIC);
        let (dq, dv) = R::forward_dynamics_derivatives(&t, &qd, &a);
        let (gq, gv) = generic.forward_dynamics_derivatives(&s.q, &s.qd, &s.a);
        assert_close(&at("∂q̈/∂q"), &dm(&dq), &gq, TOL_GENERIC);
        assert_close(&at("∂q̈/∂q̇"), &dm(&dv), &gv, TOL_GENERIC);
    }
}

#[test]
fn arm7_generated_forward_dynamics_matches_generic() {
    against_generic::<Arm7, 7, 70>("arm7");
}

#[test]
fn panda_generated_forward_dynamics_matches_generic() {
    against_generic::<Panda, 7, 70>("panda");
}

#[test]
fn panda_rounded_generated_forward_dynamics_matches_generic() {
    against_generic::<PandaRounded, 7, 70>("panda_rounded");
}

#[test]
fn ur5_generated_forward_dynamics_matches_generic() {
    against_generic::<Ur5, 6, 60>("ur5");
}

fn against_fixture<R: ForwardDynamics<N, P> + DynamicsDerivatives<N, P>, const N: usize, const P: usize>(
    robot: &str,
) {
    let fx = fixture::load(robot);
    for (k, s) in fx.states.iter().enumerate() {
        let at = |what: &str| format!("{robot} fixture state {k}: {what}");
        let t = JointTrig::new(&sv::<N>(&s.q));
        let (v, a, tau) = (sv::<N>(&s.v), sv::<N>(&s.a), sv::<N>(&s.tau));
        let qdd = R::forward_dynamics(&t, &v, &tau);
        assert_close(&at("q̈"), &dm(&qdd), &column(&s.aba), TOL_FIXTURE);
        assert_close(&at("D⁻¹"), &dm(&R::mass_matrix_inverse(&t)), &s.minv, TOL_FIXTURE);
        let (dq, dv) = R::inverse_dynamics_derivatives(&t, &v, &a);
        assert_close(&at("∂τ/∂q"), &dm(&dq), &s.dtau_dq, TOL_FIXTURE);
        assert_close(&at("∂τ/∂q̇"), &dm(&dv), &s.dtau_dv, TOL_FIXTURE);
        let (dq, dv) = R::forward_dynamics_derivatives(&t, &v, &tau);
        assert_close(&at("∂q̈/∂q"), &dm(&dq), &s.dqdd_dq, TOL_FIXTURE);
        assert_close(&at("∂q̈/∂q̇"), &dm(&dv), &s.dqdd_dv, TOL_FIXTURE);
    }
}

#[test]
fn panda_generated_forward_dynamics_matches_pinocchio() {
    against_fixture::<Panda, 7, 70>("panda");
}

#[test]
fn panda_rounded_generated_forward_dynamics_matches_pinocchio() {
    against_fixture::<PandaRounded, 7, 70>("panda_rounded");
}

#[test]
fn ur5_generated_forward_dynamics_matches_pinocchio() {
    against_fixture::<Ur5, 6, 60>("ur5");
}

/// `∂q̈/∂x` composed from the UR5's own `∂τ/∂x`, `D` and `τ` (`code_shape: composed`): the
/// same Pinocchio values, and the same oracles.
#[test]
fn ur5_composed_forward_dynamics_matches_pinocchio() {
    against_fixture::<Ur5Composed, 6, 60>("ur5");
    oracles::<Ur5Composed, 6, 60>("ur5_composed", 20);
}

/// The composition run over the functions of a robot with joint-level terms (the armature in
/// `D`, friction and offset in `τ` and `∂τ/∂q̇`) against its straight-line `∂q̈/∂x`.
#[test]
fn composed_derivatives_take_the_joint_terms_as_the_flat_ones() {
    type R = Arm7Friction;
    let model = model("arm7_friction");
    let parents: [Option<usize>; 7] = velocity_parents(&model).try_into().expect("7 coordinates");
    let tree = Tree::new(parents);
    for seed in 0..STATES {
        let s = random_state(&model, seed);
        let t = JointTrig::new(&sv::<7>(&s.q));
        let (qd, tau) = (sv::<7>(&s.qd), sv::<7>(&s.a));
        let bias = R::inverse_dynamics(&t, &qd, &SVector::zeros());
        let (dq, dv) = composed::forward_dynamics_derivatives(&tree, R::mass_matrix(&t), tau - bias, |a| {
            R::inverse_dynamics_derivatives(&t, &qd, a)
        });
        let (flat_q, flat_v) = R::forward_dynamics_derivatives(&t, &qd, &tau);
        let at = |what: &str| format!("arm7_friction seed {seed}: {what}");
        assert_close(&at("∂q̈/∂q"), &dm(&dq), &dm(&flat_q), TOL_GENERIC);
        assert_close(&at("∂q̈/∂q̇"), &dm(&dv), &dm(&flat_v), TOL_GENERIC);
    }
}

fn oracles<R: ForwardDynamics<N, P> + DynamicsDerivatives<N, P>, const N: usize, const P: usize>(
    robot: &str,
    states: u64,
) {
    let model = model(robot);
    for seed in 0..states {
        let s = random_state(&model, 1000 + seed);
        let at = |what: &str| format!("{robot} seed {seed}: {what}");
        let t = JointTrig::new(&sv::<N>(&s.q));
        let product = dm(&(R::mass_matrix_inverse(&t) * R::mass_matrix(&t)));
        assert_close(&at("D⁻¹ D = I"), &product, &DMatrix::identity(N, N), TOL_IDENTITY);
        let tau = id::<R, N, P>(&s.q, &s.qd, &s.qdd);
        let back = fd::<R, N, P>(&s.q, &s.qd, tau.as_slice());
        assert_close(&at("FD(ID(q̈)) = q̈"), &back, &column(&s.qdd), TOL_IDENTITY);

        let (qd, qdd) = (sv::<N>(&s.qd), sv::<N>(&s.qdd));
        let (dq, dv) = R::inverse_dynamics_derivatives(&t, &qd, &qdd);
        let num_q = differenced(|q| id::<R, N, P>(q, &s.qd, &s.qdd), &s.q);
        let num_v = differenced(|v| id::<R, N, P>(&s.q, v, &s.qdd), &s.qd);
        assert_close(&at("∂τ/∂q vs differenced τ"), &dm(&dq), &num_q, TOL_DIFFERENCE);
        assert_close(&at("∂τ/∂q̇ vs differenced τ"), &dm(&dv), &num_v, TOL_DIFFERENCE);

        let (dq, dv) = R::forward_dynamics_derivatives(&t, &qd, &sv::<N>(tau.as_slice()));
        let num_q = differenced(|q| fd::<R, N, P>(q, &s.qd, tau.as_slice()), &s.q);
        let num_v = differenced(|v| fd::<R, N, P>(&s.q, v, tau.as_slice()), &s.qd);
        assert_close(&at("∂q̈/∂q vs differenced q̈"), &dm(&dq), &num_q, TOL_DIFFERENCE);
        assert_close(&at("∂q̈/∂q̇ vs differenced q̈"), &dm(&dv), &num_v, TOL_DIFFERENCE);
    }
}

#[test]
fn arm7_forward_dynamics_oracles() {
    oracles::<Arm7, 7, 70>("arm7", 50);
}

#[test]
fn panda_forward_dynamics_oracles() {
    oracles::<Panda, 7, 70>("panda", 50);
}

#[test]
fn panda_rounded_forward_dynamics_oracles() {
    oracles::<PandaRounded, 7, 70>("panda_rounded", 50);
}

#[test]
fn ur5_forward_dynamics_oracles() {
    oracles::<Ur5, 6, 60>("ur5", 50);
}
