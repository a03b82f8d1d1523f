//! Least squares, the consistent estimate and the identified description on the arm7 set-up.

use crate::common;

use common::{arm7_noise, arm7_nominal, arm7_truth};
use dyngen_codegen::generate::generate_robot;
use dyngen_identify::measure;
use dyngen_identify::pseudo_inertia_margins;
use dyngen_identify::{identify, IdentifyOptions};
use dyngen_identify::{FourierTrajectory, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY};
use dyngen_model::base_parameters::BaseParameterSet;
use dyngen_model::description::load_yaml_str;
use dyngen_model::model::JointTermKind;

fn trajectory(seed: u64) -> FourierTrajectory {
    let nominal = arm7_nominal();
    let limits = TrajectoryLimits::from_model(&nominal, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut t = FourierTrajectory::random(7, 5, 0.1, seed);
    t.fit_into(&limits);
    t
}

/// Noise-free torques with exact derivatives: least squares gives the true base parameters
/// (`K θ_true`, computed from the true θ, not by the code under test) to 1e-8.
#[test]
fn noise_free_identification_recovers_base_parameters() {
    let truth = arm7_truth();
    let nominal = arm7_nominal();
    let samples = measure(&truth, &trajectory(3), 10.0, 100.0, &[0.0; 7], 1, true);
    let id = identify(&nominal, &samples, &IdentifyOptions::default()).expect("identifiable");
    // Base parameters depend on the kinematics only: the truth's are the nominal's.
    let base = BaseParameterSet::compute(&nominal);
    let expected = base.base_parameters(&truth.parameters());
    let scale = expected.iter().map(|x| x.abs()).fold(0.0, f64::max);
    for (k, (got, want)) in id.base.theta_b.iter().zip(&expected).enumerate() {
        let err = (got - want).abs() / want.abs().max(1e-3 * scale);
        assert!(
            err <= 1e-8,
            "{}: {got} vs {want} (relative {err:.2e})",
            id.base.names[k]
        );
    }
}

/// Noisy torques (σ = 1% of rated torque), positions only (filter and differences): the
/// consistent estimate satisfies its constraints, stays as compatible with the data as the
/// least squares (whitened misfit about the number of base parameters or less), and its YAML
/// loads back to the same parameters and generates.
#[test]
fn consistent_estimate_satisfies_constraints_and_its_yaml_regenerates() {
    let truth = arm7_truth();
    let nominal = arm7_nominal();
    let noise = arm7_noise(&truth);
    let samples = measure(&truth, &trajectory(5), 20.0, 250.0, &noise, 2, false);
    let id = identify(&nominal, &samples, &IdentifyOptions::default()).expect("identifiable");
    assert!(id.differentiated);
    let theta = &id.consistent.theta;
    for (b, margin) in pseudo_inertia_margins(&nominal, theta).iter().enumerate() {
        assert!(
            *margin > 0.0,
            "body {b}: pseudo-inertia not positive definite ({margin})"
        );
    }
    for j in 0..7 {
        for kind in [
            JointTermKind::Armature,
            JointTermKind::Viscous,
            JointTermKind::Coulomb,
        ] {
            let i = nominal.joint_term_index(j, kind).expect("column");
            assert!(theta[i] > 0.0, "{kind:?} of joint {j}: {}", theta[i]);
        }
    }
    let b = id.base.theta_b.len() as f64;
    assert!(
        id.consistent.misfit <= b,
        "misfit {} for {b} base parameters",
        id.consistent.misfit
    );

    let yaml = id.yaml("test data");
    let loaded = load_yaml_str(&yaml, std::path::Path::new("identified.yaml"))
        .unwrap_or_else(|e| panic!("{e}\n{yaml}"));
    let reloaded = loaded.model.parameters();
    for (i, (a, b)) in reloaded.iter().zip(theta).enumerate() {
        assert!(
            (a - b).abs() <= 1e-9 * (1.0 + b.abs()),
            "parameter {i}: {a} vs {b}"
        );
    }
    assert_eq!(loaded.model.joints().len(), 7);
    let scratch = tempfile::Builder::new()
        .prefix("dyngen-identified-")
        .tempdir()
        .expect("scratch dir");
    let dir = scratch.path();
    let path = dir.join("arm7_identified.yaml");
    std::fs::write(&path, &yaml).expect("write");
    let generated = generate_robot(&path, "arm7_identified.yaml", "Arm7Identified", "test")
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(generated
        .code
        .contains("impl RobotDynamics<7, 98> for Arm7Identified"));
}

/// A compiled robot's generated `Y_b` gives the same identification as the generic numeric
/// regressor (here the committed arm7, rigid-body columns only).
#[test]
fn compiled_robot_identifies_like_the_description() {
    use dyngen_generated::arm7::Arm7;
    use dyngen_identify::identify_with;
    use dyngen_identify::Compiled;
    let arm7 = common::arm7();
    let truth = dyngen_identify::with_payload(&arm7, 1.5, nalgebra::Vector3::new(0.0, 0.0, 0.05), 0.04);
    let samples = measure(&truth, &trajectory(8), 5.0, 100.0, &[0.0; 7], 1, true);
    let numeric = identify(&arm7, &samples, &IdentifyOptions::default()).expect("numeric");
    let compiled = Compiled::<Arm7, 7, 70, 43>::default();
    let generated = identify_with(&arm7, &compiled, &samples, &IdentifyOptions::default()).expect("compiled");
    for (a, b) in numeric.base.theta_b.iter().zip(&generated.base.theta_b) {
        assert!((a - b).abs() <= 1e-9 * (1.0 + a.abs()), "{a} vs {b}");
    }
    // A compiled robot of other kinematics is refused, not used.
    let other = common::arm7_nominal();
    let err = identify_with(&other, &compiled, &samples, &IdentifyOptions::default()).expect_err("mismatch");
    assert!(
        err.to_string().contains("are not those of the description"),
        "{err}"
    );
}
