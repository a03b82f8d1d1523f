//! dyngen's generator side: a robot description ([`description`]) becomes a kinematic-tree
//! [`model::Model`]; the dynamics algorithms, written once generic over the scalar type, run on
//! it with `f64` ([`dynamics::NumericDynamics`], the reference values) and with symbols, from
//! which [`generate`] writes flattened Rust. Build scripts call [`compile_robot`] or
//! [`Builder`]; [`base_parameters`] gives the identifiable combinations of the parameters.

pub mod base_parameters;
mod build_script;
pub mod description;
pub mod dynamics;
mod functions;
pub mod generate;
#[doc(hidden)]
pub mod internals;
pub mod model;
mod scalar;
mod scalar_dual;
mod spatial;
mod symbolic;

pub use build_script::{compile_robot, Builder};
pub use functions::{
    FunctionGroup, Functions, ALL_GROUPS, EVERY_GROUP_BY_DEFAULT_UP_TO_DOF, LARGE_ROBOT_DEFAULT,
};
/// The URDF crate that [`description::from_urdf_rs`] reads and [`description::to_urdf_rs`]
/// writes, re-exported so that callers use the same version.
pub use urdf_rs;
