//! Identification from a description whose inertia no real body has (loaded as written, dyngen's
//! default): the least squares do not care, the consistent estimate starts from the nearest
//! physical inertia and says so, and the identified description is physical.

use dyngen_identify::{identify, measure, pseudo_inertia_margins, IdentifyOptions};
use dyngen_identify::{FourierTrajectory, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY};
use dyngen_model::description::{load, load_yaml_str};
use dyngen_model::model::{Body, Model};
use std::path::Path;

/// A two-joint arm whose forearm has a principal moment of -1e-4 kg·m² (a rod along x).
fn description() -> Model {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../codegen/tests/data/non-physical/negative-moment.urdf");
    let loaded = load(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(loaded.warnings.len(), 1, "{:?}", loaded.warnings);
    loaded.model
}

/// The same arm with every body physical (the loader's `inertia: repair`).
fn repaired(model: &Model) -> Model {
    let bodies = model
        .bodies()
        .iter()
        .map(|b| Body {
            name: b.name.clone(),
            inertia: b.inertia.repaired(),
        })
        .collect();
    model.clone().with_bodies(bodies).expect("physical bodies")
}

#[test]
fn the_consistent_estimate_starts_from_the_nearest_physical_inertia_and_says_so() {
    let nominal = description();
    assert!(nominal.bodies()[1].inertia.defect().is_some());
    // The real robot is physical: the description's forearm, repaired.
    let truth = repaired(&nominal);
    let limits = TrajectoryLimits::from_model(&nominal, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut trajectory = FourierTrajectory::random(2, 5, 0.1, 7);
    trajectory.fit_into(&limits);
    let samples = measure(&truth, &trajectory, 10.0, 200.0, &[0.01, 0.01], 3, true);

    let id = identify(&nominal, &samples, &IdentifyOptions::default()).expect("identifiable");
    assert_eq!(id.notes.len(), 1, "{:#?}", id.notes);
    let note = &id.notes[0];
    assert!(
        note.starts_with(
            "body 'lower' of the description: inertia is not physical: principal moment -1e-4 kg·m² \
             is negative"
        ) && note.contains("the consistent estimate starts from the nearest physical inertia"),
        "{note}"
    );
    for (b, margin) in pseudo_inertia_margins(&nominal, &id.consistent.theta)
        .iter()
        .enumerate()
    {
        assert!(
            *margin > 0.0,
            "body {b}: pseudo-inertia not positive definite ({margin})"
        );
    }
    let b = id.base.theta_b.len() as f64;
    assert!(
        id.consistent.misfit <= b,
        "misfit {} for {b} base parameters",
        id.consistent.misfit
    );

    // The start is the repaired copy: identifying from it gives the same estimate, bit for bit.
    let from_repaired = identify(&truth, &samples, &IdentifyOptions::default()).expect("identifiable");
    assert!(from_repaired.notes.is_empty(), "{:?}", from_repaired.notes);
    assert_eq!(id.consistent.theta, from_repaired.consistent.theta);

    // The identified description is physical: it loads in the default mode without an inertia
    // warning, and says where its start came from.
    let yaml = id.yaml("test data");
    assert!(
        yaml.contains("# note: body 'lower' of the description: inertia is not physical"),
        "{yaml}"
    );
    let loaded = load_yaml_str(&yaml, Path::new("identified.yaml")).unwrap_or_else(|e| panic!("{e}\n{yaml}"));
    assert!(
        loaded.warnings.iter().all(|w| !w.contains("inertia is")),
        "{:#?}",
        loaded.warnings
    );
    assert!(loaded.model.bodies().iter().all(|b| b.inertia.defect().is_none()));
}
