//! Rigid-body dynamics algorithms, each written once, generic over [`Scalar`].
//!
//! Conventions (`ARCHITECTURE.md`, `docs/dynamics.md`): body `i` lives in joint `i`'s frame;
//! spatial vectors are angular-first in body frames; Jacobians are 6×n with linear rows
//! first, in world axes, at the end-effector frame origin; `C` is Christoffel-consistent.
//!
//! Every function takes the joint transforms of [`joint_transforms`], so that the joint
//! sines and cosines are computed once and shared by all quantities of a control tick.

mod coriolis;
mod coupling;
mod crba;
mod derivatives;
mod forward_dynamics;
mod joint;
mod joint_terms;
mod kinematics;
mod numeric;
mod numeric_forward;
mod regressor;
mod regressor_products;
mod seeded_frame;
mod singular;
mod slotine_li;
mod tree_ldl;

pub use coriolis::coriolis_matrix;
pub use coupling::{expand, project, project_both, project_columns, project_rows};
pub use crba::mass_matrix;
pub use derivatives::{
    forward_dynamics_derivatives, forward_dynamics_derivatives_by, inverse_dynamics_derivatives,
    inverse_dynamics_derivatives_by, Directions,
};
pub use forward_dynamics::{factor_mass_matrix, forward_dynamics, mass_matrix_inverse};
pub use joint::{joint_transform, joint_transforms};
pub use joint_terms::{
    add_armature, add_torques, coulomb_shape, fill_joint_term_columns, joint_term_torques,
};
pub use kinematics::{body_poses, end_effector_pose, jacobian, jacobian_dot};
pub use numeric::NumericDynamics;
pub use regressor::regressor;
pub use regressor_products::regressor_products;
pub use singular::singular_joints;
pub use slotine_li::{gravity_torque, inverse_dynamics, slotine_li};
pub use tree_ldl::TreeLdl;

use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::RigidInertia;

/// The bodies' inertias of `model` (its standard parameters) as scalars.
pub fn body_inertias<S: Scalar>(model: &Model) -> Vec<RigidInertia<S>> {
    model
        .bodies()
        .iter()
        .map(|b| RigidInertia::from_parameters(&b.inertia.parameters().map(S::from_f64)))
        .collect()
}

/// The joint-level values that act in `model` (chosen kinds only; the others are 0).
pub fn joint_term_values(model: &Model) -> Vec<crate::model::JointTermValues> {
    (0..model.dof())
        .map(|j| model.joint_terms().effective(j))
        .collect()
}

/// Body inertias from the inertial parameters (ten per body, the first `10·n` entries of
/// [`Model::parameters`]).
pub fn inertias_from_parameters<S: Scalar>(theta: &[S]) -> Vec<RigidInertia<S>> {
    theta
        .chunks_exact(crate::model::PARAMS_PER_BODY)
        .map(|p| RigidInertia::from_parameters(&std::array::from_fn(|k| p[k])))
        .collect()
}
