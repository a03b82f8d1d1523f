//! The arm7 set-up shared by the identification tests.
#![allow(dead_code)]

pub mod closed_loop;

use dyngen_identify::{with_joint_terms, with_payload};
use dyngen_model::description::load;
use dyngen_model::model::{JointTermValues, Model};
use nalgebra::Vector3;
use std::path::Path;

pub fn arm7() -> Model {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/arm7.yaml");
    load(&path).unwrap_or_else(|e| panic!("{e}")).model
}

#[path = "../../../examples/arm7_identification/joint_values.rs"]
mod joint_values;
pub use joint_values::{arm7_joint_values, joint_values};

/// The description identification starts from: arm7 with every joint column, values zero.
pub fn arm7_nominal() -> Model {
    with_joint_terms(&arm7(), &[JointTermValues::default(); 7], None)
}

/// The "real" arm7: the description, a 1.5 kg payload 0.05 m beyond the flange, and the
/// joint terms of [`arm7_joint_values`].
pub fn arm7_truth() -> Model {
    let payload = with_payload(&arm7(), 1.5, Vector3::new(0.0, 0.0, 0.05), 0.04);
    with_joint_terms(&payload, &arm7_joint_values(), None)
}

/// σ = 1% of each joint's rated torque (effort limit).
pub fn arm7_noise(model: &Model) -> Vec<f64> {
    model
        .joints()
        .iter()
        .map(|j| 0.01 * j.limits.map_or(1.0, |l| l.effort))
        .collect()
}
