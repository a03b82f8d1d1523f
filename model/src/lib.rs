//! dyngen's robot model: a robot description ([`description`]: URDF, dyngen's YAML or a
//! [`urdf_rs::Robot`]) becomes a kinematic-tree [`model::Model`], whose rigid-body dynamics
//! [`dynamics::NumericDynamics`] (and [`dynamics::FloatingDynamics`] on a floating base)
//! evaluates in `f64`; [`base_parameters`] gives the identifiable combinations of its
//! parameters, and [`Functions`] is what a user chooses to generate.
//!
//! The algorithms are written once, generic over the scalar type; `dyngen-codegen` runs the
//! same algorithms on symbols to write the flattened code. What only the generator reaches
//! (the scalar trait, the spatial algebra, the generic algorithms) is in `#[doc(hidden)]`
//! modules: plumbing between dyngen's crates, free to change with any release.

pub mod base_parameters;
pub mod description;
pub mod dynamics;
#[doc(hidden)]
pub mod frame_names;
mod functions;
pub mod model;
#[doc(hidden)]
pub mod scalar;
#[doc(hidden)]
pub mod scalar_dual;
#[doc(hidden)]
pub mod spatial;

pub use functions::{
    FunctionGroup, Functions, ALL_GROUPS, EVERY_GROUP_BY_DEFAULT_UP_TO_DOF, LARGE_ROBOT_DEFAULT,
};
/// The URDF crate that [`description::from_urdf_rs`] reads and [`description::to_urdf_rs`]
/// writes, re-exported so that callers use the same version.
pub use urdf_rs;
