//! The generator's machinery that dyngen's own tests, `dyngen-testkit` and developer tools
//! reach into: the generic algorithms, the symbolic graph, the tracer and the emitter. Not
//! part of the documented API and free to change with any release; every item here has this
//! one public path.

/// The dynamics algorithms generic over the scalar type (`f64`, symbols, dual numbers).
pub mod dynamics {
    pub use crate::dynamics::crba::mass_matrix;
    pub use crate::dynamics::derivatives::{
        forward_dynamics_derivatives_by, inverse_dynamics_derivatives_by, Directions, Placements,
    };
    pub use crate::dynamics::forward_dynamics::{forward_dynamics, mass_matrix_inverse};
    pub use crate::dynamics::frames::{local_jacobian, FrameMotion, FrameRates};
    pub use crate::dynamics::inertias::{body_inertias, inertias_from_parameters};
    pub use crate::dynamics::joint::{joint_factored_transforms, joint_transforms};
    pub use crate::dynamics::joint_terms::joint_term_values;
    pub use crate::dynamics::kinematics::{body_poses, jacobian};
    pub use crate::dynamics::newton_euler::inverse_dynamics;
    pub use crate::dynamics::regressor::{regressor, regressor_by_jacobians};
    pub use crate::dynamics::regressor_products::regressor_products;
    pub use crate::dynamics::singular::singular_joints;
    pub use crate::dynamics::slotine_li::gravity_torque;
    pub use crate::dynamics::tree_ldl::velocity_parents;
}

/// The scalar type the generic algorithms are written against.
pub mod scalar {
    pub use crate::scalar::Scalar;
}

/// The spatial algebra of the generic algorithms, written out so every operation is traced.
pub mod spatial {
    pub use crate::spatial::{
        FactoredTransform, Force, JointFrame, Mat3, Motion, RigidInertia, Transform, Vec3,
    };
}

/// The numerical rank tools the base-parameter selection is built on.
pub mod base_parameters {
    pub use crate::base_parameters::rank::{numerical_rank, stacked_regressor};
}

/// The expression graph the algorithms are traced into.
pub mod symbolic {
    pub use crate::symbolic::{record, Expr, Graph, Id, LaneExpr, Node};
}

/// Tracing a model into one graph, and emitting a traced robot as a Rust module.
pub mod generate {
    pub use crate::generate::emit::{
        emit, emit_with, type_name, Provenance, Sizes, CHUNK_VALUES, MODULE_ATTRIBUTES, SIZES,
    };
    pub use crate::generate::quantities::{Arg, Coefficient, Dims, QuantityKind, Shape};
    pub use crate::generate::trace::{
        trace, trace_functions, trace_with_base, Arguments, Inputs, Quantity, SymbolicRobot,
    };
    pub use crate::generate::trace_contacts::ContactInputs;
}
