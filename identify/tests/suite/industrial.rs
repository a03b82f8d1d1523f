//! Identification of a 6-axis industrial arm whose joint torques span three orders of
//! magnitude (thousands of N·m at the shoulder, about one at the last wrist joint), carrying a
//! 25 kg tool the description does not know, with CAD masses 7–20% off and all four joint
//! terms (armature, viscous and Coulomb friction, offset): 30 s at 500 Hz along an optimised
//! excitation, torque noise 1% of each joint's largest torque, then validated on another
//! trajectory. The floors are the acceptance thresholds of TESTING.md.

use crate::common::joint_values;
use dyngen_identify::{
    identify, measure, optimise, with_bodies_scaled, with_joint_terms, with_payload, BaseModel,
    ExcitationOptions, FourierTrajectory, Identification, IdentifyOptions, TrajectoryLimits, WrittenEstimate,
    DEFAULT_ACCELERATION_PER_VELOCITY,
};
use dyngen_model::base_parameters::BaseParameterSet;
use dyngen_model::description::{load, load_yaml_str};
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::Model;
use nalgebra::Vector3;
use std::path::Path;

const DURATION: f64 = 30.0;
const RATE: f64 = 500.0;
const VALIDATION_DURATION: f64 = 10.0;

/// The description identification starts from: no tool, joint terms unknown (zero).
fn nominal() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/industrial6.yaml");
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

/// The robot measured: each link's mass and inertia off the description's by a factor (CAD
/// models miss cables, paint, grease), a 25 kg tool (a 16 cm-diameter ball 12 cm beyond the
/// flange, a few millimetres off the A6 axis), and joint terms of the size industrial gears
/// have (armature kg·m², viscous N·m·s/rad, Coulomb N·m, offset N·m).
fn truth(nominal: &Model) -> Model {
    let cad = with_bodies_scaled(nominal, &[1.08, 0.93, 1.1, 0.9, 1.15, 1.2]);
    let tool = with_payload(&cad, 25.0, Vector3::new(0.0015, -0.001, 0.12), 0.08);
    let values = joint_values(
        &[15.0, 15.0, 6.0, 1.0, 0.8, 0.03],
        &[80.0, 80.0, 40.0, 8.0, 5.0, 0.04],
        &[120.0, 120.0, 60.0, 15.0, 10.0, 0.2],
        &[20.0, -30.0, 10.0, 3.0, -2.0, 0.03],
    );
    with_joint_terms(&tool, &values, None)
}

struct Setup {
    nominal: Model,
    truth: Model,
    limits: TrajectoryLimits,
    excitation: FourierTrajectory,
    /// σ_j: 1% of each joint's largest torque along the excitation.
    noise: Vec<f64>,
}

fn setup() -> Setup {
    let nominal = nominal();
    let truth = truth(&nominal);
    let limits = TrajectoryLimits::from_model(&nominal, DEFAULT_ACCELERATION_PER_VELOCITY);
    let options = ExcitationOptions {
        samples: 100,
        starts: 4,
        iterations: 60,
        ..ExcitationOptions::default()
    };
    let excitation = optimise(&BaseModel::new(&nominal), &limits, &options).trajectory;
    let period = excitation.period();
    let clean = measure(&truth, &excitation, period, 100.0, &[0.0; 6], 1, true);
    let mut largest = [0.0f64; 6];
    for tau in clean.tau.as_ref().expect("torques") {
        for j in 0..6 {
            largest[j] = largest[j].max(tau[j].abs());
        }
    }
    // The shape this test is about: three orders of magnitude from the largest to the smallest.
    let (hi, lo) = (
        largest.iter().copied().fold(0.0, f64::max),
        largest.iter().copied().fold(f64::INFINITY, f64::min),
    );
    assert!(
        hi > 1000.0 && lo < 5.0 && hi / lo > 1000.0,
        "largest torques {largest:?}"
    );
    Setup {
        nominal,
        truth,
        limits,
        excitation,
        noise: largest.iter().map(|t| 0.01 * t).collect(),
    }
}

/// The identified description, as a user gets it: its YAML, loaded by the description loader.
fn written(id: &Identification) -> Model {
    let yaml = id.yaml("the test's data");
    load_yaml_str(&yaml, Path::new("identified.yaml"))
        .unwrap_or_else(|e| panic!("the written description does not load: {e}\n{yaml}"))
        .model
}

/// Validation torque RMS error of `model` per joint, in units of each joint's σ, on another
/// trajectory (measured with the same noise).
fn validation(s: &Setup, model: &Model) -> Vec<f64> {
    let mut other = FourierTrajectory::random(6, 5, 0.1, 777);
    other.fit_into(&s.limits);
    let data = measure(&s.truth, &other, VALIDATION_DURATION, RATE, &s.noise, 4242, true);
    let dynamics = NumericDynamics::new(model);
    let (qd, qdd, tau) = (
        data.qd.as_ref().expect("qd"),
        data.qdd.as_ref().expect("qdd"),
        data.tau.as_ref().expect("tau"),
    );
    let mut squares = [0.0; 6];
    for k in 0..data.len() {
        let predicted = dynamics.inverse_dynamics(&data.q[k], &qd[k], &qdd[k]);
        for j in 0..6 {
            squares[j] += (tau[k][j] - predicted[j]).powi(2);
        }
    }
    (0..6)
        .map(|j| (squares[j] / data.len() as f64).sqrt() / s.noise[j])
        .collect()
}

/// The floors on noisy data: the noise of every joint found (the wrist's is not swamped by
/// the base's), validation within 1.2 σ on every joint, a consistent estimate as compatible
/// with the data as the least squares (whitened misfit at most 2b), a written description
/// that loads.
fn check_noisy(with_derivatives: bool) {
    let s = setup();
    let samples = measure(
        &s.truth,
        &s.excitation,
        DURATION,
        RATE,
        &s.noise,
        42,
        with_derivatives,
    );
    let id = identify(&s.nominal, &samples, &IdentifyOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(id.differentiated, !with_derivatives);
    let b = id.base.theta_b.len();
    println!(
        "noise re-estimated {} times (settled: {}); σ estimated / true per joint: {:.3?}",
        id.base.noise_iterations,
        id.base.noise_settled,
        id.base
            .joint_noise
            .iter()
            .zip(&s.noise)
            .map(|(e, t)| e / t)
            .collect::<Vec<_>>()
    );
    assert!(id.base.noise_settled);
    for (j, (estimated, true_sigma)) in id.base.joint_noise.iter().zip(&s.noise).enumerate() {
        assert!(
            (estimated / true_sigma - 1.0).abs() <= 0.05,
            "joint {j}: σ estimated {estimated}, true {true_sigma}"
        );
    }
    println!(
        "consistent estimate: misfit {:.3e} for {b} base parameters, from {} ({} steps); every start: {:?}",
        id.consistent.misfit, id.consistent.start, id.consistent.iterations, id.consistent.misfits
    );
    assert!(
        id.consistent.misfit <= 2.0 * b as f64,
        "misfit {} for {b} base parameters",
        id.consistent.misfit
    );
    assert!(id.consistent.compatible);
    assert_eq!(id.written, WrittenEstimate::Consistent);
    assert!(id.warnings.is_empty(), "{:?}", id.warnings);
    let rms = validation(&s, &written(&id));
    println!("validation torque RMS error / σ per joint: {rms:.3?}");
    for (j, r) in rms.iter().enumerate() {
        assert!(*r <= 1.2, "joint {j}: validation RMS {r:.3} σ");
    }
}

#[test]
fn positions_and_torques_only_meet_the_floors() {
    check_noisy(false);
}

#[test]
fn exact_velocities_and_accelerations_meet_the_floors() {
    check_noisy(true);
}

/// Noise-free torques with exact derivatives: the least squares and the consistent estimate
/// both give the true base parameters (`K θ_true`, from the true θ, not by the code under
/// test) to 1e-6 relative (to a billionth of the largest for one that is zero), and the
/// written description loads.
#[test]
fn noise_free_data_recovers_the_true_base_parameters() {
    let s = setup();
    let samples = measure(&s.truth, &s.excitation, 10.0, 200.0, &[0.0; 6], 1, true);
    let id = identify(&s.nominal, &samples, &IdentifyOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    let expected = BaseParameterSet::compute(&s.nominal).base_parameters(&s.truth.parameters());
    let largest = expected.iter().map(|x| x.abs()).fold(0.0, f64::max);
    let mut worst = (0.0f64, 0);
    for (estimate, name) in [
        (&id.base.theta_b, "least squares"),
        (&id.consistent.theta_b, "consistent"),
    ] {
        for (k, (got, want)) in estimate.iter().zip(&expected).enumerate() {
            let error = (got - want).abs() / want.abs().max(1e-9 * largest);
            assert!(
                error <= 1e-6,
                "{name}, {}: {got} vs {want} (relative {error:.2e})",
                id.base.names[k]
            );
            if name == "consistent" && error > worst.0 {
                worst = (error, k);
            }
        }
    }
    println!(
        "consistent estimate: largest relative error {:.2e} ({}), misfit {:.2e}",
        worst.0, id.base.names[worst.1], id.consistent.misfit
    );
    assert_eq!(id.written, WrittenEstimate::Consistent);
    written(&id);
}

/// Data no physically consistent robot explains (the wrist's torque sensor wired with the
/// wrong sign): a warning that says so, and still a written description that loads.
#[test]
fn data_no_consistent_robot_fits_is_a_warning_not_a_failure() {
    let s = setup();
    let mut samples = measure(&s.truth, &s.excitation, 10.0, 200.0, &s.noise, 7, true);
    for tau in samples.tau.as_mut().expect("torques") {
        tau[5] = -tau[5];
    }
    let id = identify(&s.nominal, &samples, &IdentifyOptions::default()).unwrap_or_else(|e| panic!("{e}"));
    println!("warnings: {:#?}", id.warnings);
    assert!(!id.consistent.compatible);
    assert!(
        id.warnings
            .iter()
            .any(|w| w.starts_with("no physically consistent parameters fit the data")),
        "{:?}",
        id.warnings
    );
    assert!(id
        .yaml("data")
        .contains("# warning: no physically consistent parameters"));
    written(&id);
}
