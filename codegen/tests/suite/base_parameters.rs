//! Base inertial parameters: their number against independent figures (Pinocchio's rank of the
//! stacked regressor), `Y_b θ_b = Y θ` for any θ (on Pinocchio's own regressors, on random
//! trees; on compiled generated code in `generated/tests/suite/base_regressor.rs`), two descriptions of one robot, and determinism.
//!
//! `cargo test -p dyngen-codegen --test suite base_parameters:: -- --nocapture` prints p_b, the gaps and the names.

use dyngen_testkit as common;

use common::random_model::{arb_model, random_state, SplitMix64};
use common::{assert_close, column, fixture, scaled_rank};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::generate::{trace_with_base, QuantityKind};
use dyngen_codegen::model::Model;
use nalgebra::DMatrix;
use proptest::test_runner::{Config, RngAlgorithm, RngSeed, TestRunner};
use std::cell::RefCell;
use std::path::Path;

/// `Y_b θ_b` against `Y θ`, relative (to the largest torque, at least 1).
const TOL: f64 = 1e-10;

fn load_model(relative: &str) -> Model {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(relative);
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

fn described(robot: &str) -> Model {
    load_model(&format!("robots/{robot}.yaml"))
}

/// θ with every entry uniform in ±1: the identity `Y_b θ_b = Y θ` is for every θ, not only for
/// physically consistent ones, and a random θ exercises every folding coefficient.
fn random_theta(p: usize, seed: u64) -> Vec<f64> {
    let mut rng = SplitMix64::new(seed);
    (0..p).map(|_| rng.uniform((-1.0, 1.0))).collect()
}

/// The generic regressor stacked at `count` states of the tests' own generator (other states
/// than those the base parameters were selected on).
fn fresh_stack(model: &Model, first_seed: u64, count: u64) -> DMatrix<f64> {
    let dynamics = NumericDynamics::new(model);
    let blocks: Vec<DMatrix<f64>> = (first_seed..first_seed + count)
        .map(|seed| {
            let s = random_state(model, seed);
            dynamics.regressor(&s.q, &s.qd, &s.v, &s.a)
        })
        .collect();
    let n = model.dof();
    DMatrix::from_fn(n * blocks.len(), blocks[0].ncols(), |i, j| {
        blocks[i / n][(i % n, j)]
    })
}

/// Pinocchio's inverse-dynamics regressors of the fixture, stacked (20 states).
fn pinocchio_stack(fx: &fixture::Fixture) -> DMatrix<f64> {
    let n = fx.joint_names.len();
    let p = fx.pi.len();
    DMatrix::from_fn(n * fx.states.len(), p, |i, j| fx.states[i / n].y[(i % n, j)])
}

/// p_b of Panda and UR5 is the rank of their regressor stacked over 200 random states, as
/// computed with Pinocchio 4.1 (Panda 43 of 70, UR5 36 of 60: `codegen/tests/fixtures/README.md`).
/// Checked on the model the fixture states (independent of dyngen's loaders), on the model
/// dyngen loads from the URDF, and against the rank of Pinocchio's own regressors.
#[test]
fn base_parameter_count_is_pinocchios_rank() {
    for (robot, expected, standard) in [("panda", 43, 70), ("ur5", 36, 60)] {
        let fx = fixture::load(robot);
        let from_fixture = BaseParameterSet::compute(&fx.model());
        let from_description = BaseParameterSet::compute(&described(robot));
        assert_eq!(
            from_fixture.count(),
            expected,
            "{robot}: p_b of the fixture's model"
        );
        assert_eq!(
            from_description.count(),
            expected,
            "{robot}: p_b of robots/{robot}.yaml"
        );
        assert_eq!(from_fixture.standard_count, standard);
        assert_eq!(
            from_fixture.columns, from_description.columns,
            "{robot}: fixture model and description select different columns"
        );
        let (rank, _) = scaled_rank(&pinocchio_stack(&fx));
        assert_eq!(rank, expected, "{robot}: rank of Pinocchio's stacked Y");
    }
}

/// `Y θ = Y_b θ_b` on Pinocchio's regressors: external data, columns chosen by dyngen.
#[test]
fn base_parameters_reproduce_pinocchios_torques() {
    for robot in ["panda", "ur5"] {
        let fx = fixture::load(robot);
        let base = BaseParameterSet::compute(&fx.model());
        let y = pinocchio_stack(&fx);
        let y_b = base.base_regressor(&y);
        for (k, theta) in [
            fx.pi.clone(),
            random_theta(fx.pi.len(), 7),
            random_theta(fx.pi.len(), 8),
        ]
        .iter()
        .enumerate()
        {
            let tau = &y * DMatrix::from_column_slice(theta.len(), 1, theta);
            let theta_b = base.base_parameters(theta);
            let tau_b = &y_b * DMatrix::from_column_slice(theta_b.len(), 1, &theta_b);
            assert_close(
                &format!("{robot} θ #{k}: Y_b θ_b vs Pinocchio's Y θ"),
                &tau_b,
                &tau,
                TOL,
            );
        }
    }
}

/// p_b equals the numerical rank of `Y` stacked at other states than the selection's; prints
/// arm7's figure and the spectrum gap.
#[test]
fn base_parameter_count_is_the_rank_at_fresh_states() {
    for (robot, expected) in [("arm7", None), ("panda", Some(43)), ("ur5", Some(36))] {
        let model = described(robot);
        let base = BaseParameterSet::compute(&model);
        let (rank, s) = scaled_rank(&fresh_stack(&model, 5000, 60));
        let pb = base.count();
        println!(
            "{robot}: p_b = {pb} of {}; σ_pb/σ_max = {:.2e}, σ_(pb+1)/σ_max = {:.2e}; {:?}",
            base.standard_count,
            s[pb - 1] / s[0],
            s.get(pb).map_or(0.0, |x| x / s[0]),
            base.diagnostics
        );
        assert_eq!(pb, rank, "{robot}: p_b vs rank of a fresh stack");
        assert_eq!(base.diagnostics.svd_rank, pb, "{robot}: internal SVD cross-check");
        if let Some(e) = expected {
            assert_eq!(pb, e);
        }
        for (k, name) in base.names.iter().enumerate() {
            println!("  θ_b[{k:>2}] = {name}");
        }
    }
}

/// Folding coefficients are the exact geometric values (parallel-axis theorem): in the UR5, the
/// forearm's mass sits 0.425 m along the upper arm's z axis (the URDF's elbow origin), so it
/// adds 0.425·m to the upper arm's first moment and 0.425²·m = 0.180625·m to its inertia.
#[test]
fn folding_coefficients_are_exact_geometry() {
    let model = described("ur5");
    let base = BaseParameterSet::compute(&model);
    let names = model.parameter_names();
    let index = |name: &str| names.iter().position(|n| n == name).expect("parameter exists");
    let coefficient = |kept: &str, folded: &str| {
        let k = base
            .columns
            .iter()
            .position(|&c| c == index(kept))
            .unwrap_or_else(|| panic!("{kept} is not a base parameter"));
        base.terms[k]
            .iter()
            .find(|&&(i, _)| i == index(folded))
            .map(|&(_, c)| c)
    };
    assert_eq!(coefficient("mcz[upper_arm_link]", "m[forearm_link]"), Some(0.425));
    assert_eq!(
        coefficient("Iyy[upper_arm_link]", "m[forearm_link]"),
        Some(0.180625)
    );
    assert_eq!(
        coefficient("Iyy[upper_arm_link]", "m[wrist_3_link]"),
        Some(0.180625)
    );
    // The kept parameter itself has coefficient exactly 1 and is listed first.
    assert!(base
        .terms
        .iter()
        .zip(&base.columns)
        .all(|(t, &c)| t[0] == (c, 1.0)));
}

/// Fixed seed, no failure files: every run checks the same trees.
fn deterministic_runner(cases: u32) -> TestRunner {
    TestRunner::new(Config {
        cases,
        failure_persistence: None,
        source_file: None,
        rng_algorithm: RngAlgorithm::ChaCha,
        rng_seed: RngSeed::Fixed(0xBA5E_9A2A_3E7E_2500),
        ..Config::default()
    })
}

/// 256 random trees (up to 10 joints, branches, prismatic joints, skew axes, tilted gravity):
/// p_b is the rank of a fresh stack, and `Y_b θ_b = Y θ` for random θ at fresh states (numeric),
/// as is `Y θ'` for the representative θ' (θ_b on the kept columns, exactly 0 on the others).
#[test]
fn random_trees_base_parameters() {
    let stats = RefCell::new((0usize, 0usize, 0usize, f64::INFINITY, 0.0f64, 0usize, 0usize));
    let result = deterministic_runner(256).run(&arb_model(10), |model| {
        let base = BaseParameterSet::compute(&model);
        let n = model.dof();
        let fresh = fresh_stack(&model, 777, 40);
        let (rank, _) = scaled_rank(&fresh);
        proptest::prop_assert_eq!(base.count(), rank, "p_b vs fresh rank, {:?}", base.diagnostics);
        proptest::prop_assert_eq!(base.diagnostics.svd_rank, base.count());
        let theta = random_theta(10 * n, n as u64);
        let theta_b = base.base_parameters(&theta);
        // What generated code computes its dynamics from: θ_b on the kept columns, zeros.
        let representative = base.representative(&theta);
        let dynamics = NumericDynamics::new(&model);
        for seed in 0..3 {
            let s = random_state(&model, 900 + seed);
            let y = dynamics.regressor(&s.q, &s.qd, &s.v, &s.a);
            let tau = &y * DMatrix::from_column_slice(theta.len(), 1, &theta);
            let tau_b = base.base_regressor(&y) * DMatrix::from_column_slice(theta_b.len(), 1, &theta_b);
            let err = common::relative_error(&tau_b, &tau);
            proptest::prop_assert!(err <= TOL, "Y_b θ_b vs Y θ: {err:.3e}, {:?}", base.diagnostics);
            let tau_r = &y * DMatrix::from_column_slice(representative.len(), 1, &representative);
            let err = common::relative_error(&tau_r, &tau);
            proptest::prop_assert!(err <= TOL, "Y θ' vs Y θ: {err:.3e}");
        }
        let off_base = (0..theta.len()).filter(|i| !base.columns.contains(i));
        proptest::prop_assert!(off_base.clone().all(|i| representative[i] == 0.0));
        proptest::prop_assert!(off_base.count() + base.count() == theta.len());
        let mut st = stats.borrow_mut();
        st.0 += 1;
        st.1 += base.count();
        st.2 += 10 * n;
        st.3 = st.3.min(base.diagnostics.smallest_kept_residual);
        st.4 = st.4.max(base.diagnostics.largest_dropped_residual);
        st.5 += base.diagnostics.exact;
        st.6 += base.diagnostics.inexact;
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
    let (trees, pb, p, kept, dropped, exact, inexact) = *stats.borrow();
    println!(
        "{trees} random trees: {pb} base of {p} parameters; smallest kept residual {kept:.2e}, \
         largest dropped residual {dropped:.2e}; folding coefficients {exact} exact, {inexact} inexact"
    );
}

/// The interpreted graph of `Y_b` (what the emitter writes) against the numeric column pick, on
/// small random trees (tracing is the slow part).
#[test]
fn random_trees_interpreted_base_regressor() {
    let result = deterministic_runner(24).run(&arb_model(5), |model| {
        let base = BaseParameterSet::compute(&model);
        let robot = trace_with_base(&model, base.clone());
        let dynamics = NumericDynamics::new(&model);
        let s = random_state(&model, 31);
        let values = robot
            .evaluate(QuantityKind::BaseRegressor.name(), &s.q, &s.qd, &s.v, &s.a)
            .expect("base regressor traced");
        let interpreted = DMatrix::from_column_slice(model.dof(), base.count(), &values);
        let numeric = base.base_regressor(&dynamics.regressor(&s.q, &s.qd, &s.v, &s.a));
        let err = common::relative_error(&interpreted, &numeric);
        proptest::prop_assert!(err <= TOL, "interpreted Y_b vs numeric: {err:.3e}");
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// The UR5 described twice, as its URDF (robots/ur5.yaml) and as inline YAML transcribed from
/// it (tests/data/ur5_inline.yaml): same p_b, same columns, same θ_b.
#[test]
fn same_robot_described_twice_has_the_same_base_parameters() {
    let urdf = described("ur5");
    let inline = load_model("codegen/tests/data/ur5_inline.yaml");
    assert_eq!(urdf.dof(), inline.dof());
    let (a, b) = (
        BaseParameterSet::compute(&urdf),
        BaseParameterSet::compute(&inline),
    );
    assert_eq!(a.count(), 36);
    assert_eq!(a.count(), b.count(), "p_b");
    assert_eq!(a.columns, b.columns, "columns");
    assert_eq!(a.names, b.names, "names");
    for theta in [urdf.parameters(), random_theta(60, 3)] {
        let (ta, tb) = (a.base_parameters(&theta), b.base_parameters(&theta));
        assert_close("θ_b, URDF vs inline YAML", &column(&tb), &column(&ta), 1e-12);
    }
    // Each description's own θ_b (the inline YAML's inertias are the URDF's, transcribed).
    assert_close(
        "own θ_b",
        &column(&b.base_parameters(&inline.parameters())),
        &column(&a.base_parameters(&urdf.parameters())),
        1e-12,
    );
}

/// Two computations give identical columns, coefficients (bit for bit) and names.
#[test]
fn computation_is_deterministic() {
    for robot in ["arm7", "panda", "ur5"] {
        let model = described(robot);
        let (a, b) = (
            BaseParameterSet::compute(&model),
            BaseParameterSet::compute(&model.clone()),
        );
        assert_eq!(a.columns, b.columns, "{robot}");
        let bits = |s: &BaseParameterSet| -> Vec<Vec<(usize, u64)>> {
            s.terms
                .iter()
                .map(|t| t.iter().map(|&(i, c)| (i, c.to_bits())).collect())
                .collect()
        };
        assert_eq!(bits(&a), bits(&b), "{robot}");
        assert_eq!(a.names, b.names, "{robot}");
    }
}

/// A vendor URDF as written, with `1.5708` for π/2 (the xArm7): folding coefficients near short
/// decimals are not snapped when that changes the robot, so the representative `θ'` every
/// generated function is traced with has `θ`'s dynamics to rounding (snapping them all gives a
/// `D` about 1e-13 away).
#[test]
fn the_representative_parameters_keep_a_near_exact_robot_exact() {
    let model = load_model("codegen/tests/data/example-robot-data/xarm_description/xarm7.urdf");
    let theta = model.parameters();
    let representative = BaseParameterSet::compute(&model).representative(&theta);
    let (described, folded) = (
        NumericDynamics::new(&model),
        NumericDynamics::with_parameters(&model, &representative),
    );
    let n = model.dof();
    for seed in 0..20 {
        let s = random_state(&model, seed);
        let d = described.mass_matrix(&s.q);
        let scale = d.amax();
        let error = (folded.mass_matrix(&s.q) - &d).amax() / scale;
        assert!(
            error <= 1e-14,
            "D of θ' is {error:.1e} (relative) from D of θ at {:?}",
            s.q
        );
        let tau = described.inverse_dynamics(&s.q, &s.qd, &s.qdd);
        let tau_folded = folded.inverse_dynamics(&s.q, &s.qd, &s.qdd);
        let scale = tau.amax().max(1.0);
        let error = (tau_folded - &tau).amax() / scale;
        assert!(error <= 1e-13, "τ of θ' is {error:.1e} from τ of θ ({n} joints)");
    }
}
