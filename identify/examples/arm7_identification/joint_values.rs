//! The true joint terms of the "real" arm7, shared by this example and the identification
//! tests (which include this file): realistic values for a 7-DOF arm with harmonic drives
//! (sources in the example's docs).

use dyngen_model::model::JointTermValues;

/// Armature kg·m², viscous N·m·s/rad, Coulomb N·m, offset N·m, joint by joint.
pub fn arm7_joint_values() -> Vec<JointTermValues> {
    let armature = [0.5, 0.5, 0.3, 0.3, 0.15, 0.05, 0.05];
    let viscous = [0.8, 0.8, 0.5, 0.5, 0.3, 0.1, 0.1];
    let coulomb = [3.0, 3.0, 2.0, 2.0, 1.2, 0.5, 0.5];
    let offset = [0.2, -0.3, 0.1, -0.1, 0.05, 0.02, -0.02];
    (0..7)
        .map(|j| JointTermValues {
            armature: armature[j],
            viscous: viscous[j],
            coulomb: coulomb[j],
            offset: offset[j],
        })
        .collect()
}
