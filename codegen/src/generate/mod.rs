//! From a model to Rust source: trace the algorithms symbolically, then emit.

mod code_size;
mod crate_dir;
pub(crate) mod emit;
mod hash;
mod output;
pub(crate) mod quantities;
mod robot_file;
pub(crate) mod trace;
mod trace_contact_derivatives;
pub(crate) mod trace_contacts;
pub(crate) mod trace_floating;

pub use crate::symbolic::OpCounts;
pub use code_size::{
    composed_functions, estimate as estimate_code_size, frame_references, shapes, CodeSize, Shapes,
    FLAT_FUNCTIONS_UP_TO, FRAMES_IN_EVERY_REFERENCE_UP_TO, MAX_GENERATED_BYTES,
};
pub use crate_dir::{descriptions_in, generate_into_crate, CrateReport, Mode, RobotReport};
pub(crate) use output::is_generated;
pub use output::{check_file, write_file, WriteOutcome};
pub use robot_file::{generate_robot, generate_robot_with, GenerateError, GeneratedRobot, GENERATED_MARKER};

// The naming rule every front end shares (the build-script API, `dyngen gen`, `dyngen info`,
// `cargo xtask gen`): a description's file stem gives the module, the module the type.
pub use emit::type_name;
pub use output::module_name;
