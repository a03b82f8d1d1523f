//! The identified robot as a URDF: written with its wrapper, loaded back, it has the
//! identified robot's dynamics (inverse dynamics and mass matrix at random states, generic
//! numeric code on both sides) to 1e-12; without joint terms the URDF alone suffices.

use crate::common;

use common::{arm7, arm7_noise, arm7_nominal, arm7_truth};
use dyngen_identify::{
    identify, measure, wrapper_path, FourierTrajectory, Identification, IdentifyOptions, TrajectoryLimits,
    DEFAULT_ACCELERATION_PER_VELOCITY,
};
use dyngen_model::description::load;
use dyngen_model::dynamics::NumericDynamics;
use dyngen_model::model::Model;
use dyngen_runtime::SplitMix64;

fn identified(nominal: &Model, truth: &Model) -> Identification {
    let limits = TrajectoryLimits::from_model(nominal, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut t = FourierTrajectory::random(7, 5, 0.1, 12);
    t.fit_into(&limits);
    let samples = measure(truth, &t, 10.0, 100.0, &arm7_noise(truth), 4, true);
    identify(nominal, &samples, &IdentifyOptions::default()).expect("identified")
}

/// The largest difference of inverse dynamics and mass matrix between `a` and `b` at 100
/// random states within the joint limits, relative to the largest torque or entry.
fn largest_difference(a: &Model, b: &Model) -> f64 {
    assert_eq!(a.dof(), b.dof());
    let (da, db) = (NumericDynamics::new(a), NumericDynamics::new(b));
    let mut rng = SplitMix64::new(3);
    let mut worst = 0.0f64;
    for _ in 0..100 {
        let q: Vec<f64> = a
            .joints()
            .iter()
            .map(|j| {
                let l = j.limits.expect("limited");
                l.lower + (l.upper - l.lower) * rng.unit()
            })
            .collect();
        let qd: Vec<f64> = (0..a.dof()).map(|_| 2.0 * rng.unit() - 1.0).collect();
        let qdd: Vec<f64> = (0..a.dof()).map(|_| 4.0 * rng.unit() - 2.0).collect();
        let (ta, tb) = (
            da.inverse_dynamics(&q, &qd, &qdd),
            db.inverse_dynamics(&q, &qd, &qdd),
        );
        worst = worst.max((&ta - &tb).amax() / ta.amax().max(1.0));
        let (ma, mb) = (da.mass_matrix(&q), db.mass_matrix(&q));
        worst = worst.max((&ma - &mb).amax() / mb.amax());
    }
    worst
}

/// arm7 with every joint term identified: the URDF carries the inertials and the friction
/// (`<dynamics damping friction>`), the wrapper the columns, armature and offsets; loaded
/// through the wrapper it is the identified robot. The URDF alone loads too, as the rigid
/// robot with the same inertials.
#[test]
fn the_urdf_with_its_wrapper_is_the_identified_robot() {
    let nominal = arm7_nominal();
    let id = identified(&nominal, &arm7_truth());
    let dir = tempfile::tempdir().expect("temp dir");
    let urdf_path = dir.path().join("arm7_identified.urdf");
    let files = id.urdf("the test's data", &urdf_path).expect("a URDF");
    let wrapper = files
        .wrapper
        .as_ref()
        .expect("armature and offsets need a wrapper");
    assert_eq!(
        wrapper_path(&urdf_path),
        dir.path().join("arm7_identified.dyngen.yaml")
    );
    assert!(wrapper.contains("urdf: arm7_identified.urdf"), "{wrapper}");
    assert!(files.urdf.contains("<dynamics damping="), "{}", files.urdf);
    assert!(
        files
            .urdf
            .contains("arm7_identified.dyngen.yaml beside it loads it as that robot")
            && files.urdf.contains("- armature (no URDF element): joint1 "),
        "{}",
        files.urdf
    );
    std::fs::write(&urdf_path, &files.urdf).expect("write");
    std::fs::write(wrapper_path(&urdf_path), wrapper).expect("write");

    let loaded = load(&wrapper_path(&urdf_path)).unwrap_or_else(|e| panic!("{e}"));
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(loaded.model.parameter_count(), id.model.parameter_count());
    let difference = largest_difference(&id.model, &loaded.model);
    println!("identified arm7 against its URDF and wrapper: {difference:.1e}");
    assert!(difference <= 1e-12, "{difference:e}");

    // Alone, the URDF is the rigid robot: the same inertial parameters, no joint terms.
    let alone = load(&urdf_path).unwrap_or_else(|e| panic!("{e}")).model;
    assert_eq!(alone.parameter_count(), id.model.inertial_parameter_count());
    for (a, b) in alone.parameters().iter().zip(&id.model.parameters()) {
        assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} vs {b}");
    }
}

/// A rigid robot at the default gravity whose end-effector is the leaf: the URDF alone is the
/// identified robot, and no wrapper is made.
#[test]
fn without_joint_terms_the_urdf_alone_suffices() {
    let rigid = arm7();
    let truth = dyngen_identify::with_payload(&rigid, 1.5, nalgebra::Vector3::new(0.0, 0.0, 0.05), 0.04);
    let id = identified(&rigid, &truth);
    let dir = tempfile::tempdir().expect("temp dir");
    let urdf_path = dir.path().join("arm7.urdf");
    let files = id.urdf("the test's data", &urdf_path).expect("a URDF");
    assert_eq!(files.wrapper, None, "{:?}", files.missing);
    assert!(files.missing.is_empty(), "{:?}", files.missing);
    std::fs::write(&urdf_path, &files.urdf).expect("write");
    let loaded = load(&urdf_path).unwrap_or_else(|e| panic!("{e}"));
    let difference = largest_difference(&id.model, &loaded.model);
    println!("identified rigid arm7 against its URDF: {difference:.1e}");
    assert!(difference <= 1e-12, "{difference:e}");
}
