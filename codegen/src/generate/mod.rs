//! From a model to Rust source: trace the algorithms symbolically, then emit.

mod crate_dir;
mod emit;
mod hash;
mod output;
mod robot_file;
mod trace;

pub use crate_dir::{descriptions_in, generate_into_crate, CrateReport, Mode, RobotReport};
pub use emit::{emit, type_name, Provenance, MODULE_ATTRIBUTES};
pub use hash::fnv1a64;
pub use output::{check_file, crate_root, module_name, write_file, WriteOutcome};
pub use robot_file::{
    generate_robot, generate_robot_with, GenerateError, GeneratedRobot, GENERATED_MARKER, MAX_GENERATED_DOF,
};
pub use trace::{
    trace, trace_with_base, Arg, Arguments, Inputs, Quantity, Shape, SymbolicRobot, BASE_FUNCTIONS,
    BASE_REGRESSOR, BASE_REGRESSOR_PRODUCTS, BASE_TORQUE_REGRESSOR,
};
