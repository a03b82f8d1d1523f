//! Why a constrained quantity of the generic dynamics was not computed.

use dyngen_runtime::ContactError;
use std::fmt;

/// Why a constrained quantity of the generic dynamics was not computed.
#[derive(Clone, Debug, PartialEq)]
pub enum ConstraintError {
    /// A frame index past the model's frames.
    FrameIndex(usize),
    /// The solve refused (redundant rows without regularisation, bad settings, …).
    Solve(ContactError),
    /// What this function does not compute.
    Unsupported(&'static str),
}

impl From<ContactError> for ConstraintError {
    fn from(e: ContactError) -> Self {
        ConstraintError::Solve(e)
    }
}

impl fmt::Display for ConstraintError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConstraintError::FrameIndex(i) => write!(f, "frame index {i} is past the model's frames"),
            ConstraintError::Solve(e) => e.fmt(f),
            ConstraintError::Unsupported(what) => write!(f, "not supported: {what}"),
        }
    }
}

impl std::error::Error for ConstraintError {}
