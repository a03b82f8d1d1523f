//! The bodies' inertias the recursions take, from a model's standard parameters or from any
//! parameter vector (the traced `θ` of the generator, the estimates of identification).

use crate::model::Model;
use crate::scalar::Scalar;
use crate::spatial::RigidInertia;
use dyngen_runtime::PARAMETERS_PER_BODY;

/// The bodies' inertias of `model` (its standard parameters) as scalars.
pub fn body_inertias<S: Scalar>(model: &Model) -> Vec<RigidInertia<S>> {
    model
        .bodies()
        .iter()
        .map(|b| RigidInertia::from_parameters(&b.inertia.parameters().map(S::from_f64)))
        .collect()
}

/// Body inertias from the inertial parameters (ten per body, the first `10·n` entries of
/// [`Model::parameters`]).
pub fn inertias_from_parameters<S: Scalar>(theta: &[S]) -> Vec<RigidInertia<S>> {
    theta
        .chunks_exact(PARAMETERS_PER_BODY)
        .map(|p| RigidInertia::from_parameters(&std::array::from_fn(|k| p[k])))
        .collect()
}
