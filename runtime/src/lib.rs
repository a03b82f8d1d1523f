//! The contract between generated robot code and everything that uses it. A controller, a
//! simulator or an identification tool is written against what this crate's root exports:
//! - the traits a generated robot implements: [`Kinematics`], [`RobotDynamics`],
//!   [`Regressors`], [`BaseParameters`], [`ForwardDynamics`], [`DynamicsDerivatives`],
//!   [`FrameKinematics`] (any named frame, in any [`ReferenceFrame`]; its `Frame` enum is a
//!   [`RobotFrame`]) with [`WrenchDynamics`] ([`ExternalWrench`]es at those frames), and
//!   [`LaneDynamics`] (several states per call, in the lane types
//!   [`f64x4`] and [`f64x8`], any [`Lanes`]); on a free-flying base, one trait per group too,
//!   [`FloatingBaseDynamics`], [`FloatingRegressors`], [`FloatingBaseParameters`],
//!   [`FloatingForwardDynamics`], [`FloatingDynamicsDerivatives`] and [`FloatingFrameKinematics`],
//!   taking a [`FloatingTrig`];
//! - the parameterisations generic code is written against: [`Parameterization`], with
//!   [`Standard`] and [`Base`];
//! - the plain data they exchange: [`JointTrig`] and [`JointTrigLanes`] (with [`pack`] and
//!   [`unpack`] between vectors and lanes), [`Pose`], [`BasePose`] (a free-flying base's
//!   position and unit quaternion, with `integrate` and `difference`), [`JointLimits`], [`ParameterKind`], and
//!   the ten standard parameters per body ([`PARAMETERS_PER_BODY`], [`BODY_PARAMETER_NAMES`],
//!   [`body_parameters`]);
//! - [`ResultBuffer`] (any [`BufferedResult`]): a matrix result kept between calls of the
//!   `_into` forms (`torque_regressor_into`), written only where it can be nonzero;
//! - helpers for hand-written code beside the generated functions: [`mul_add`] (fused exactly
//!   where the build targets FMA) and [`SplitMix64`] (small, seeded, reproducible);
//! - [`prelude`], [`include_robot!`], and the [`nalgebra`] that every signature uses.
//!
//! Generated code also calls `dyngen_runtime::__private`: how a generated function runs (fused
//! multiply-adds chosen by the processor, lane registers, aligned stack frames) and the
//! switches tests use to compare those forms. It is hidden and not part of the API: it changes
//! in any release, which is why every generated module checks that it is compiled against the
//! runtime of the release that generated it (`__require_version!`, also hidden), and stops the
//! build with a message naming both versions if not.
//!
//! `#![no_std]`, allocation-free, and dependent only on `nalgebra` (without default features),
//! `libm` and `wide` (the SIMD lane types of [`LaneDynamics`]), so generated code runs on
//! embedded controllers. Invariant: this crate never depends on the generator or the
//! controller; generated code depends only on this crate and `nalgebra`.

// Unit tests run with the standard test harness.
#![cfg_attr(not(test), no_std)]

mod composed;
mod contacts;
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
mod cpu;
mod dispatch;
mod fill;
mod floating;
mod floating_robot;
mod frame_references;
mod frames;
mod joint;
mod lane_kernels;
mod lane_vectors;
#[cfg(all(
    target_arch = "x86_64",
    not(all(target_feature = "avx2", target_feature = "fma"))
))]
mod lane_vectors_x86;
mod lanes;
mod mul_add;
mod operational_space;
mod parameter;
mod parameterization;
mod random;
mod result_buffer;
mod robot;
mod stack_align;
mod tree_factor;
mod trig;
#[cfg(target_arch = "x86_64")]
mod trig_fused;
mod version;

pub use contacts::{
    assemble_derivatives, constrained_forward_dynamics, constrained_forward_dynamics_derivatives,
    contact_inertia, delassus_inertia, impulse_dynamics, operational_space_inertia, placement_error,
    solve_contacts, solve_contacts_with_delassus, ConstrainedDerivatives, ContactDynamics, ContactError,
    ContactInertia, ContactKind, ContactMatrices, ContactSolution, ContactStep, ContactSystem,
    ProximalSettings, Stabilisation,
};
pub use floating::{BasePose, NonUnitQuaternion, QUATERNION_NORM_TOLERANCE};
pub use floating_robot::{
    ConfigurationError, FloatingBaseDynamics, FloatingBaseParameters, FloatingDynamicsDerivatives,
    FloatingForwardDynamics, FloatingFrameKinematics, FloatingRegressors, FloatingTrig,
};
pub use frames::{ExternalWrench, FrameKinematics, ReferenceFrame, RobotFrame, WrenchDynamics};
pub use joint::{JointLimits, JointTrig};
pub use lanes::{f64x4, f64x8, pack, unpack, JointTrigLanes, LaneDynamics, Lanes};
pub use mul_add::mul_add;
pub use nalgebra;
pub use operational_space::{operational_space, Inversion, OperationalSpace, OperationalSpaceError};
pub use parameter::{body_parameters, ParameterKind, BODY_PARAMETER_NAMES, PARAMETERS_PER_BODY};
pub use parameterization::{Base, BaseParameters, Parameterization, Standard};
pub use random::SplitMix64;
pub use result_buffer::{BufferedResult, ResultBuffer};
pub use robot::{DynamicsDerivatives, ForwardDynamics, Kinematics, Pose, Regressors, RobotDynamics};

/// What generated code calls and no one else should: how a generated function runs (its body a
/// [`Kernel`](__private::Kernel) generic over [`MulAdd`](__private::MulAdd), run by
/// [`dispatch`](__private::dispatch) or [`dispatch_eight`](__private::dispatch_eight)), the
/// helpers its bodies call, and the switches tests use to compare the fused and unfused forms.
///
/// Not part of the API: nothing here follows semver, and anything may change or disappear in
/// any release. Generated code (and the generator, for the same `sign`) may use it because the
/// generator and this crate are released together, and every generated module checks that they
/// match (`__require_version!`).
#[doc(hidden)]
pub mod __private {
    #[cfg(target_arch = "x86_64")]
    pub use crate::dispatch::Fused;
    #[cfg(all(
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    pub use crate::dispatch::Fused512;
    pub use crate::dispatch::{dispatch, dispatch_eight, dispatch_many, Kernel, MulAdd, Unfused};
    /// What a function composed from smaller generated ones (`code_shape: composed`) runs.
    pub mod composed {
        pub use crate::composed::*;
    }
    pub use crate::fill::fill_zero;
    /// A frame's quantities in `local` and `world` from those in base axes.
    pub mod frame_references {
        pub use crate::frame_references::*;
    }
    pub use crate::lane_kernels::{dispatch_lanes, lane_out, lanes_in, trig_in, LaneKernel, LaneVector};
    pub use crate::lane_vectors::{EightLanes, FourLanes};
    #[cfg(all(
        target_arch = "x86_64",
        not(all(target_feature = "avx2", target_feature = "fma"))
    ))]
    pub use crate::lane_vectors_x86::{Avx2Eight, Avx2Four, Avx512Eight};
    pub use crate::lanes::sign;
    pub use crate::result_buffer::claim;
    pub use crate::stack_align::align_stack_frame;
    /// The tree factorisation of `D` and its solves, generic over the scalar: the model traces
    /// them, composed functions run them.
    pub mod tree_factor {
        pub use crate::tree_factor::*;
    }
    pub use libm;

    // The switches between the fused and unfused forms, for tests and measurements: a program
    // that set them would change every generated function's results process-wide.
    pub use crate::dispatch::{avx512_lanes, fused_multiply_adds, set_avx512_lanes, set_fused_multiply_adds};
}

/// The traits whose functions a user of generated code calls: `use dyngen_runtime::prelude::*;`
/// brings `Arm7::mass_matrix(&t)` and `Arm7::jacobian(&t)` into reach.
pub mod prelude {
    pub use crate::{
        BaseParameters, DynamicsDerivatives, ExternalWrench, FloatingBaseDynamics, FloatingBaseParameters,
        FloatingDynamicsDerivatives, FloatingForwardDynamics, FloatingFrameKinematics, FloatingRegressors,
        FloatingTrig, ForwardDynamics, FrameKinematics, JointTrig, Kinematics, LaneDynamics,
        Parameterization, ReferenceFrame, Regressors, ResultBuffer, RobotDynamics, RobotFrame,
        WrenchDynamics,
    };
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
