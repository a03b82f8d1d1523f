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

pub(crate) mod coriolis;
mod coupling;
pub(crate) mod crba;
pub(crate) mod derivatives;
mod energy;
pub(crate) mod floating;
pub(crate) mod forward_dynamics;
pub(crate) mod frames;
pub(crate) mod inertias;
pub(crate) mod joint;
pub(crate) mod joint_terms;
pub(crate) mod kinematics;
pub(crate) mod newton_euler;
mod numeric;
mod numeric_floating;
mod numeric_forward;
pub(crate) mod regressor;
pub(crate) mod regressor_products;
mod seeded_frame;
pub(crate) mod singular;
pub(crate) mod slotine_li;
mod tree_ldl;

pub use numeric::{FrameValues, NumericDynamics};
pub use numeric_floating::{FloatingDynamics, FloatingState};

pub(crate) use coriolis::coriolis_matrix;
pub(crate) use crba::mass_matrix;
pub(crate) use derivatives::{
    forward_dynamics_derivatives_by, inverse_dynamics_derivatives_by, Directions, Placements,
};
pub(crate) use forward_dynamics::{forward_dynamics, mass_matrix_inverse};
pub(crate) use frames::{local_jacobian, FrameMotion, FrameRates};
pub(crate) use inertias::{body_inertias, inertias_from_parameters};
pub(crate) use joint::{joint_factored_transforms, joint_transforms};
pub(crate) use joint_terms::{add_armature, add_torques, joint_term_torques, joint_term_values};
pub(crate) use kinematics::{body_poses, end_effector_pose, jacobian, jacobian_dot};
pub(crate) use newton_euler::inverse_dynamics;
pub(crate) use regressor::{regressor, regressor_by_jacobians, regressor_row_lanes, ROW_LANES};
pub(crate) use regressor_products::regressor_products;
pub(crate) use singular::singular_joints;
pub(crate) use slotine_li::{gravity_torque, slotine_li};
