//! dyngen's generator: the dynamics algorithms of `dyngen-model`, run on symbols, become
//! flattened Rust ([`generate`]). Build scripts call [`compile_robot`] or [`Builder`], which
//! also writes a robot as a C library ([`Builder::c_library`], `docs/c-library.md`).
//!
//! The model side (descriptions, [`model::Model`], the generic `f64` dynamics, base parameters)
//! lives in `dyngen-model` and is re-exported here, so that a build script needs one
//! dependency; crates that only load and evaluate robots depend on `dyngen-model` alone.

mod build_script;
mod c_library;
pub mod generate;
#[doc(hidden)]
pub mod internals;
mod symbolic;

pub use build_script::{compile_robot, Builder};
pub use c_library::{CLibrary, CLibraryReport};
pub use dyngen_model::{base_parameters, description, dynamics, model};
pub use dyngen_model::{
    urdf_rs, FunctionGroup, Functions, ALL_GROUPS, EVERY_GROUP_BY_DEFAULT_UP_TO_DOF, LARGE_ROBOT_DEFAULT,
};
// The model crate's plumbing, under the paths the generator's modules name it by.
use dyngen_model::{frame_names, scalar, scalar_dual, spatial};
