//! Rigid-body dynamics, each algorithm written once, generic over the scalar type: run with
//! `f64` for reference values and with symbols to trace the code the generator emits.
//!
//! The public face is [`NumericDynamics`], the generic `f64` baseline: the values generated code
//! is tested against and what identification simulates with. The generic algorithms themselves
//! belong to the generator.
//!
//! Conventions (`ARCHITECTURE.md`, `docs/dynamics.md`): body `i` lives in joint `i`'s frame;
//! spatial vectors are angular-first in body frames; Jacobians are 6×n with linear rows
//! first, in world axes, at the end-effector frame origin; `C` is Christoffel-consistent.
//!
//! Every algorithm takes the joint transforms of `joint_transforms`, so that the joint
//! sines and cosines are computed once and shared by all quantities of a control tick.

#[doc(hidden)]
pub mod constrained;
#[doc(hidden)]
pub mod coriolis;
mod coupling;
#[doc(hidden)]
pub mod crba;
#[doc(hidden)]
pub mod derivatives;
mod energy;
#[doc(hidden)]
pub mod floating;
#[doc(hidden)]
pub mod forward_dynamics;
#[doc(hidden)]
pub mod frames;
#[doc(hidden)]
pub mod inertias;
#[doc(hidden)]
pub mod joint;
#[doc(hidden)]
pub mod joint_terms;
#[doc(hidden)]
pub mod kinematics;
#[doc(hidden)]
pub mod newton_euler;
mod numeric;
mod numeric_floating;
mod numeric_forward;
#[doc(hidden)]
pub mod regressor;
#[doc(hidden)]
pub mod regressor_products;
mod seeded_frame;
#[doc(hidden)]
pub mod singular;
#[doc(hidden)]
pub mod slotine_li;
#[doc(hidden)]
pub mod tree_ldl;

pub use constrained::{ConstrainedDerivatives, ConstrainedMotion, ConstraintError};
pub use numeric::{FrameValues, NumericDynamics};
pub use numeric_floating::{FloatingDynamics, FloatingState};

#[doc(hidden)]
pub use coriolis::coriolis_matrix;
#[doc(hidden)]
pub use crba::mass_matrix;
#[doc(hidden)]
pub use derivatives::{
    forward_dynamics_derivatives_by, inverse_dynamics_derivatives_by, Directions, Placements,
};
#[doc(hidden)]
pub use forward_dynamics::{forward_dynamics, mass_matrix_inverse};
#[doc(hidden)]
pub use frames::{local_jacobian, FrameMotion, FrameRates};
#[doc(hidden)]
pub use inertias::{body_inertias, inertias_from_parameters};
#[doc(hidden)]
pub use joint::{joint_factored_transforms, joint_transforms};
#[doc(hidden)]
pub use joint_terms::{add_armature, add_torques, joint_term_torques, joint_term_values};
#[doc(hidden)]
pub use kinematics::{body_poses, end_effector_pose, jacobian, jacobian_dot};
#[doc(hidden)]
pub use newton_euler::inverse_dynamics;
#[doc(hidden)]
pub use regressor::{regressor, regressor_by_jacobians, regressor_row_lanes, ROW_LANES};
#[doc(hidden)]
pub use regressor_products::regressor_products;
#[doc(hidden)]
pub use singular::singular_joints;
#[doc(hidden)]
pub use slotine_li::{gravity_torque, slotine_li};
