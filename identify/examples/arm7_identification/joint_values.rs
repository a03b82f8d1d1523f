//! The true joint terms of the "real" arm7, and joint terms written one array per kind,
//! shared by this example and the identification tests (which include this file): realistic values for a 7-DOF arm with harmonic drives
//! (sources in the example's docs).

use dyngen_model::model::JointTermValues;

/// Armature kg·m², viscous N·m·s/rad, Coulomb N·m, offset N·m, joint by joint.
pub fn arm7_joint_values() -> Vec<JointTermValues> {
    joint_values(
        &[0.5, 0.5, 0.3, 0.3, 0.15, 0.05, 0.05],
        &[0.8, 0.8, 0.5, 0.5, 0.3, 0.1, 0.1],
        &[3.0, 3.0, 2.0, 2.0, 1.2, 0.5, 0.5],
        &[0.2, -0.3, 0.1, -0.1, 0.05, 0.02, -0.02],
    )
}

/// Joint terms joint by joint from one array per kind (armature kg·m², viscous N·m·s/rad,
/// Coulomb N·m, offset N·m).
pub fn joint_values(
    armature: &[f64],
    viscous: &[f64],
    coulomb: &[f64],
    offset: &[f64],
) -> Vec<JointTermValues> {
    (0..armature.len())
        .map(|j| JointTermValues {
            armature: armature[j],
            viscous: viscous[j],
            coulomb: coulomb[j],
            offset: offset[j],
        })
        .collect()
}
