//! A contact of a model: one of its named frames, held to the world.

use super::{Model, ModelError};
use dyngen_runtime::{ContactKind, ReferenceFrame};

/// A named frame of the model held to the world: its origin (a point contact, three rows) or
/// all of it (a frame contact, six rows), the rows and forces written in the frame's own axes
/// or in world axes at its origin.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Contact {
    /// An index into [`Model::frames`].
    pub frame: usize,
    pub kind: ContactKind,
    /// [`ReferenceFrame::Local`] or [`ReferenceFrame::LocalWorldAligned`]; `World` is no
    /// contact's (as in Pinocchio), and [`Model::with_contacts`] refuses it.
    pub reference: ReferenceFrame,
}

impl Contact {
    /// A contact at the frame of `model` named `frame`.
    pub fn at(
        model: &Model,
        frame: &str,
        kind: ContactKind,
        reference: ReferenceFrame,
    ) -> Result<Contact, ModelError> {
        let index = (model.frames().iter())
            .position(|f| f.name == frame)
            .ok_or_else(|| ModelError(format!("no frame named `{frame}`")))?;
        Ok(Contact {
            frame: index,
            kind,
            reference,
        })
    }
}

/// The checks [`Model::with_contacts`] makes: existing frames, each held once, in `Local` or
/// `LocalWorldAligned` axes, and fewer rows than the robot has degrees of freedom.
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
        if contacts[..k].iter().any(|o| o.frame == c.frame) {
            return Err(format!("frame '{}' is held by two contacts", frame.name));
        }
    }
    let rows: usize = contacts.iter().map(|c| c.kind.rows()).sum();
    if !contacts.is_empty() && rows >= model.nv() {
        return Err(format!(
            "the contacts hold {rows} rows of the robot's {} degrees of freedom: nothing would be left to move",
            model.nv()
        ));
    }
    Ok(())
}
