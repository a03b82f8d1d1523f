//! From a model to Rust source: trace the algorithms symbolically, then emit.

mod crate_dir;
pub(crate) mod emit;
mod hash;
mod output;
mod robot_file;
pub(crate) mod trace;

pub use crate::symbolic::OpCounts;
pub use crate_dir::{descriptions_in, generate_into_crate, CrateReport, Mode, RobotReport};
pub use output::{check_file, write_file, WriteOutcome};
pub use robot_file::{
    generate_robot, generate_robot_with, GenerateError, GeneratedRobot, GENERATED_MARKER, MAX_GENERATED_DOF,
};

// The build-script API names its module and type the way `cargo xtask gen` does.
pub(crate) use emit::type_name;
pub(crate) use output::module_name;
