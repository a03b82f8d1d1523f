//! A contact of a model: one of its frames, held to the world.

use crate::model::Model;
use dyngen_runtime::{ContactError, ContactKind, ReferenceFrame};
use std::fmt;

/// A frame of the model held to the world.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Contact {
    /// An index into [`Model::frames`].
    pub frame: usize,
    pub kind: ContactKind,
    /// The axes its rows (and forces) are written in: [`ReferenceFrame::Local`] or
    /// [`ReferenceFrame::LocalWorldAligned`]; `World` is refused, as in Pinocchio.
    pub reference: ReferenceFrame,
}

impl Contact {
    /// A contact at the frame named `frame`.
    pub fn at(
        model: &Model,
        frame: &str,
        kind: ContactKind,
        reference: ReferenceFrame,
    ) -> Result<Contact, ConstraintError> {
        let index = model
            .frames()
            .iter()
            .position(|f| f.name == frame)
            .ok_or_else(|| ConstraintError::UnknownFrame(frame.to_owned()))?;
        Ok(Contact {
            frame: index,
            kind,
            reference,
        })
    }
}

/// Why a constrained quantity of the generic dynamics was not computed.
#[derive(Clone, Debug, PartialEq)]
pub enum ConstraintError {
    /// No frame of that name.
    UnknownFrame(String),
    /// A frame index past the model's frames.
    FrameIndex(usize),
    /// The solve refused (redundant rows without regularisation, bad settings, …).
    Solve(ContactError),
}

impl From<ContactError> for ConstraintError {
    fn from(e: ContactError) -> Self {
        ConstraintError::Solve(e)
    }
}

impl fmt::Display for ConstraintError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConstraintError::UnknownFrame(name) => write!(f, "no frame named `{name}`"),
            ConstraintError::FrameIndex(i) => write!(f, "frame index {i} is past the model's frames"),
            ConstraintError::Solve(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for ConstraintError {}
