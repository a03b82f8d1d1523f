//! Models with joint friction and armature, for the tests of the joint-level terms.

use crate::random_model::SplitMix64;
use dyngen_codegen::model::{JointTermKind, JointTermValues, JointTerms, Model};

/// `model` with every kind of joint term and random physical values: armature in [0, 0.5],
/// viscous in [0, 2], Coulomb in [0, 3] (smoothed by `tanh(q̇/ε)` with `smoothing: Some(ε)`),
/// offset in [−1, 1].
pub fn with_joint_terms(model: Model, smoothing: Option<f64>, seed: u64) -> Model {
    let mut rng = SplitMix64::new(seed);
    let terms = JointTerms {
        kinds: JointTermKind::ALL.to_vec(),
        coulomb_smoothing: smoothing,
        values: (0..model.dof())
            .map(|_| JointTermValues {
                armature: rng.uniform((0.0, 0.5)),
                viscous: rng.uniform((0.0, 2.0)),
                coulomb: rng.uniform((0.0, 3.0)),
                offset: rng.uniform((-1.0, 1.0)),
            })
            .collect(),
    };
    model.with_joint_terms(terms).expect("physical values")
}
