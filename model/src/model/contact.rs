//! A contact of a model: one of its named frames, held to the world or to another of its
//! frames (a loop closure).

use super::{Model, ModelError};
use dyngen_runtime::{ContactKind, ReferenceFrame};

/// A named frame of the model held to the world, or to another named frame (`to`, a loop
/// closure: a four-bar's rods, a parallel gripper): its origin (a point contact, three rows) or
/// all of it (a frame contact, six rows), the rows and forces written in the frame's own axes
/// or in world axes at its origin. A loop's rows are the motion of `frame` relative to `to`'s
/// body, and its force acts on `frame`'s body (the opposite one on `to`'s).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Contact {
    /// An index into [`Model::frames`].
    pub frame: usize,
    pub kind: ContactKind,
    /// [`ReferenceFrame::Local`] or [`ReferenceFrame::LocalWorldAligned`]; `World` is no
    /// contact's (as in Pinocchio), and [`Model::with_contacts`] refuses it.
    pub reference: ReferenceFrame,
    /// The frame it is held to (an index into [`Model::frames`]); `None`: the world.
    pub to: Option<usize>,
}

impl Contact {
    /// A contact at the frame of `model` named `frame`.
    pub fn at(
        model: &Model,
        frame: &str,
        kind: ContactKind,
        reference: ReferenceFrame,
    ) -> Result<Contact, ModelError> {
        Ok(Contact {
            frame: frame_index(model, frame)?,
            kind,
            reference,
            to: None,
        })
    }

    /// This contact, holding its frame to the frame of `model` named `to` rather than to the
    /// world.
    pub fn to(self, model: &Model, to: &str) -> Result<Contact, ModelError> {
        Ok(Contact {
            to: Some(frame_index(model, to)?),
            ..self
        })
    }
}

fn frame_index(model: &Model, name: &str) -> Result<usize, ModelError> {
    (model.frames().iter())
        .position(|f| f.name == name)
        .ok_or_else(|| ModelError(format!("no frame named `{name}`")))
}

/// The checks of each contact [`Model::with_contacts`] makes: existing frames, each held to the
/// world once, a loop between frames of two bodies, in `Local` or `LocalWorldAligned` axes.
pub(super) fn check_contacts(model: &Model) -> Result<(), String> {
    let contacts = model.contacts();
    for (k, c) in contacts.iter().enumerate() {
        let Some(frame) = model.frames().get(c.frame) else {
            return Err(format!("contact {k}: frame index {} does not exist", c.frame));
        };
        if c.reference == ReferenceFrame::World {
            return Err(format!(
                "contact at frame '{}': its rows are written in `local` or `local_world_aligned` axes, not `world`",
                frame.name
            ));
        }
        if let Some(to) = c.to {
            let Some(other) = model.frames().get(to) else {
                return Err(format!("contact {k}: frame index {to} does not exist"));
            };
            if other.parent == frame.parent {
                return Err(format!(
                    "a loop between '{}' and '{}', frames of one body, holds nothing",
                    frame.name, other.name
                ));
            }
        }
        if contacts[..k].iter().any(|o| o.frame == c.frame && o.to == c.to) {
            return Err(format!("frame '{}' is held by two contacts", frame.name));
        }
    }
    Ok(())
}
