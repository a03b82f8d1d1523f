//! What a downstream crate gets from the build-script API.

use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_downstream_example::Panda;
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::prelude::*;
use std::path::Path;

#[test]
fn build_script_panda_matches_generic_dynamics() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots/panda.yaml");
    let model = load(&path).unwrap_or_else(|e| panic!("{e}")).model;
    let generic = NumericDynamics::new(&model);
    let q = [0.1, -0.4, 0.3, -1.9, 0.2, 1.4, 0.6];
    let qd = [0.5, -0.2, 0.1, 0.3, -0.7, 0.4, 0.2];
    let t = JointTrig::new(&SVector::from(q));
    let d = Panda::mass_matrix(&t);
    let c = Panda::coriolis_matrix(&t, &SVector::from(qd));
    assert!(
        (d - SVector::<f64, 49>::from_column_slice(generic.mass_matrix(&q).as_slice()).reshape_generic(
            dyngen_runtime::nalgebra::Const::<7>,
            dyngen_runtime::nalgebra::Const::<7>
        ))
        .amax()
            < 1e-12
    );
    let c_generic = generic.coriolis_matrix(&q, &qd);
    assert!(
        (c.as_slice()
            .iter()
            .zip(c_generic.as_slice())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max))
            < 1e-12
    );
    assert_eq!(Panda::JOINT_NAMES[0], "panda_joint1");
    assert_eq!(Panda::parameters().as_slice(), model.parameters().as_slice());
}

#[test]
fn build_script_output_equals_the_committed_generated_code() {
    // Same description, same generator: the same functions, whichever way they were generated.
    let q = SVector::from([0.7, 0.1, -0.5, -1.2, 0.9, 2.0, -0.3]);
    let v = SVector::from([0.3, 0.2, -0.1, 0.4, -0.5, 0.6, 0.1]);
    let t = JointTrig::new(&q);
    assert_eq!(
        Panda::regressor(&t, &v, &v, &v),
        dyngen_generated::Panda::regressor(&t, &v, &v, &v)
    );
    assert_eq!(Panda::jacobian(&t), dyngen_generated::Panda::jacobian(&t));
}
