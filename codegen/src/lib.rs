//! dyngen's generator side: robot descriptions → kinematic-tree [`model::Model`] →
//! dynamics algorithms generic over a [`scalar::Scalar`] (run with `f64` as the generic
//! reference, and with symbolic values for code generation).

pub mod base_parameters;
mod build_script;
pub mod description;
pub mod dynamics;
pub mod generate;
pub mod model;
pub mod scalar;
pub mod scalar_dual;
pub mod spatial;
pub mod symbolic;

pub use build_script::{compile_robot, Builder};
/// The URDF crate that [`description::from_urdf_rs`] reads and [`description::to_urdf_rs`]
/// writes, re-exported so that callers use the same version.
pub use urdf_rs;
