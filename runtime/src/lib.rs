//! dyngen's runtime: what generated robot code links against (the [`RobotDynamics`] trait and
//! [`JointTrig`]), and the controllers and simulator that are generic over any such robot.
//!
//! Invariant: this crate never depends on the generator; generated code depends only on this
//! crate and `nalgebra`.

pub mod controller;
mod parameterization;
mod random;
mod robot;
pub mod sim;

pub use nalgebra;
pub use parameterization::{mass_matrix_through_regressor, Base, BaseParameters, Parameterization, Standard};
pub use random::SplitMix64;
pub use robot::{JointTrig, Pose, RobotDynamics};

/// Includes a robot generated into `OUT_DIR` by a build script (`dyngen_codegen::compile_robot`)
/// as module `$module`, with the attributes that flattened generated code needs (an included
/// file cannot carry them itself).
///
/// `dyngen_runtime::include_robot!(panda);` makes `panda::Panda`.
#[macro_export]
macro_rules! include_robot {
    ($module:ident) => {
#[rustfmt::skip]
        #[allow(
            clippy::approx_constant,
            clippy::excessive_precision,
            clippy::unreadable_literal,
            clippy::too_many_lines,
            clippy::many_single_char_names,
            clippy::similar_names,
            clippy::neg_multiply
        )]
        pub mod $module {
            include!(concat!(env!("OUT_DIR"), "/", stringify!($module), ".rs"));
        }
    };
}
