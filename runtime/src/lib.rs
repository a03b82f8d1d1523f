//! The contract between generated robot code and everything that uses it: the traits a
//! generated robot implements ([`Kinematics`], [`RobotDynamics`], [`BaseParameters`]), the
//! parameterisations a controller is generic over ([`Parameterization`]: [`Standard`],
//! [`Base`]), and the plain data they exchange ([`JointTrig`], [`Pose`], [`JointLimits`],
//! [`ParameterKind`]).
//!
//! `#![no_std]`, allocation-free, and dependent only on `nalgebra` (without default features),
//! `libm` and `wide` (the SIMD lane types of [`LaneDynamics`]), so generated code runs on
//! embedded controllers. Invariant: this crate never
//! depends on the generator or the controller; generated code depends only on this crate and
//! `nalgebra`.

// Unit tests run with the standard test harness.
#![cfg_attr(not(test), no_std)]

#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
mod cpu;
mod dispatch;
mod eight_lanes;
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
mod eight_lanes_x86;
mod fill;
mod frame;
mod joint;
mod lanes;
mod mul_add;
mod parameter;
mod parameterization;
mod random;
mod robot;
mod trig;
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
mod trig_fused;

#[cfg(target_arch = "x86_64")]
pub use dispatch::Fused;
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
pub use dispatch::Fused512;
pub use dispatch::{
    avx512_lanes, dispatch, dispatch_eight, fused_multiply_adds, set_avx512_lanes, set_fused_multiply_adds,
    Kernel, MulAdd, Unfused,
};
pub use eight_lanes::EightLanes;
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
pub use eight_lanes_x86::{Avx2Eight, Avx512Eight};
pub use fill::fill_zero;
pub use frame::align_stack_frame;
pub use joint::{JointLimits, JointTrig};
pub use lanes::{f64x4, f64x8, pack, sign, unpack, JointTrigLanes, LaneDynamics, Lanes};
pub use libm;
pub use mul_add::mul_add;
pub use nalgebra;
pub use parameter::{body_parameters, ParameterKind, PARAMETERS_PER_BODY};
pub use parameterization::{Base, BaseParameters, Parameterization, Standard};
pub use random::SplitMix64;
pub use robot::{Kinematics, Pose, RobotDynamics};

/// The traits whose functions a user of generated code calls: `use dyngen_runtime::prelude::*;`
/// brings `Arm7::mass_matrix(&t)` and `Arm7::jacobian(&t)` into reach.
pub mod prelude {
    pub use crate::{BaseParameters, JointTrig, Kinematics, LaneDynamics, Parameterization, RobotDynamics};
}

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
