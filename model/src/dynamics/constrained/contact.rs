//! What a user constrains and how the solve is set: contacts at named frames, the anchors they
//! are held to, Baumgarte gains and the proximal settings.

use crate::model::Model;
use dyngen_runtime::ReferenceFrame;
use nalgebra::{Matrix3, Vector3};
use std::fmt;

/// How much of a frame's motion a contact holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ContactKind {
    /// The frame's origin (three rows): a foot on the ground, a fingertip.
    Point,
    /// The whole frame (six rows, linear first): a flat foot, a hand gripping a handle.
    Frame,
}

impl ContactKind {
    /// The rows a contact of this kind adds.
    pub fn rows(self) -> usize {
        match self {
            ContactKind::Point => 3,
            ContactKind::Frame => 6,
        }
    }
}

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

/// Where a contact's frame is held: a pose in the world (a point contact uses only its
/// translation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Anchor {
    pub rotation: Matrix3<f64>,
    pub translation: Vector3<f64>,
}

/// Baumgarte stabilisation: each contact's rows ask for `−K_p e − K_d J ν` (`e` its frame's
/// placement error from its anchor) instead of zero acceleration, which pulls a contact that
/// drifted (integration error, a touchdown off the anchor) back to where it is held.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stabilisation<'a> {
    /// One per contact, in the contacts' order.
    pub anchors: &'a [Anchor],
    pub kp: f64,
    pub kd: f64,
}

/// The proximal solve: `mu` regularises the Delassus matrix (0 solves the rows exactly, which
/// needs independent rows), and the iterations refine the solution until the constraint
/// residual or the change of `λ` is below `accuracy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProximalSettings {
    pub mu: f64,
    pub max_iterations: usize,
    pub accuracy: f64,
}

impl Default for ProximalSettings {
    /// Exact rows in one solve: independent rows, no regularisation.
    fn default() -> Self {
        ProximalSettings {
            mu: 0.0,
            max_iterations: 1,
            accuracy: 1e-12,
        }
    }
}

/// Why a constrained solve gave no answer.
#[derive(Clone, Debug, PartialEq)]
pub enum ConstraintError {
    /// No frame of that name.
    UnknownFrame(String),
    /// A frame index past the model's frames.
    FrameIndex(usize),
    /// Rows in world axes (a spatial quantity at the world origin) are not a contact's.
    WorldReference(usize),
    /// As many anchors as contacts are needed for Baumgarte stabilisation.
    Anchors { contacts: usize, anchors: usize },
    /// `mu` negative, no iteration, or a non-finite setting or gain.
    Settings(&'static str),
    /// The Delassus matrix is singular: the rows are redundant (or a frame cannot move in some
    /// row's direction) and need `mu > 0`.
    Redundant { row: usize },
    /// A restitution coefficient outside `[0, 1]`.
    Restitution(f64),
}

impl fmt::Display for ConstraintError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConstraintError::UnknownFrame(name) => write!(f, "no frame named `{name}`"),
            ConstraintError::FrameIndex(i) => write!(f, "frame index {i} is past the model's frames"),
            ConstraintError::WorldReference(k) => write!(
                f,
                "contact {k} is written in world axes; a contact's rows are LOCAL or LOCAL_WORLD_ALIGNED"
            ),
            ConstraintError::Anchors { contacts, anchors } => {
                write!(f, "{contacts} contacts but {anchors} anchors")
            }
            ConstraintError::Settings(what) => write!(f, "proximal settings: {what}"),
            ConstraintError::Redundant { row } => write!(
                f,
                "the constraint rows are redundant (row {row} depends on the others): solve with mu > 0"
            ),
            ConstraintError::Restitution(r) => {
                write!(f, "restitution {r} is outside [0, 1]")
            }
        }
    }
}

impl std::error::Error for ConstraintError {}
