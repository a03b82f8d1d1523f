//! Checks of the model invariants. (Filled in by the description loaders' work.)

/// A model that breaks an invariant.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{0}")]
pub struct ModelError(pub String);
