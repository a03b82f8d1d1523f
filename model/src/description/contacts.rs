//! The frames a description holds to the world (`contacts:`), and their resolution against the
//! model's named frames.

use super::error::DescriptionError;
use super::source_map::SourceMap;
use crate::model::{Contact, Frame};
use dyngen_runtime::{ContactKind, ReferenceFrame};
use serde::de::{self, Deserializer};
use serde::Deserialize;

/// A named frame held to the world, as a description writes it:
/// `{ frame: FL_FOOT, kind: point }` or `{ frame: left_sole, kind: frame, reference:
/// local_world_aligned }`.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSpec {
    /// The frame held: the end-effector or one of `frames`.
    pub frame: String,
    /// `point`: its origin (three rows); `frame`: all of it (six rows, linear first).
    #[serde(deserialize_with = "contact_kind")]
    pub kind: ContactKind,
    /// The axes its rows and forces are written in: `local` (the frame's own, the default) or
    /// `local_world_aligned` (world axes at the frame's origin).
    #[serde(default = "local", deserialize_with = "contact_reference")]
    pub reference: ReferenceFrame,
}

impl ContactSpec {
    /// A contact at `frame`, in its own axes.
    pub fn new(frame: impl Into<String>, kind: ContactKind) -> ContactSpec {
        ContactSpec {
            frame: frame.into(),
            kind,
            reference: ReferenceFrame::Local,
        }
    }
}

fn local() -> ReferenceFrame {
    ReferenceFrame::Local
}

fn contact_kind<'de, D: Deserializer<'de>>(deserializer: D) -> Result<ContactKind, D::Error> {
    let word = String::deserialize(deserializer)?;
    [ContactKind::Point, ContactKind::Frame]
        .into_iter()
        .find(|k| k.keyword() == word)
        .ok_or_else(|| de::Error::custom(format!("contact kind `{word}`: expected `point` or `frame`")))
}

fn contact_reference<'de, D: Deserializer<'de>>(deserializer: D) -> Result<ReferenceFrame, D::Error> {
    let word = String::deserialize(deserializer)?;
    match ReferenceFrame::ALL.into_iter().find(|r| r.keyword() == word) {
        Some(ReferenceFrame::World) | None => Err(de::Error::custom(format!(
            "contact reference `{word}`: expected `local` or `local_world_aligned`"
        ))),
        Some(reference) => Ok(reference),
    }
}

/// The contacts of `specs` on a model whose named frames are `frames` (the end-effector
/// first) with `nv` velocity coordinates; errors at the place of the offending entry.
pub(crate) fn resolve(
    specs: &[ContactSpec],
    frames: &[Frame],
    nv: usize,
    map: &SourceMap,
) -> Result<Vec<Contact>, DescriptionError> {
    let mut contacts: Vec<Contact> = Vec::new();
    for (k, spec) in specs.iter().enumerate() {
        let path = format!("contacts[{k}]");
        let Some(frame) = frames.iter().position(|f| f.name == spec.frame) else {
            let known: Vec<&str> = frames.iter().map(|f| f.name.as_str()).collect();
            return Err(map.error(
                &format!("{path}.frame"),
                format!(
                    "no frame named '{}' to hold; name the end-effector or a frame listed under `frames:` ({})",
                    spec.frame,
                    known.join(", ")
                ),
            ));
        };
        if contacts.iter().any(|c| c.frame == frame) {
            return Err(map.error(
                &path,
                format!("frame '{}' is held by an earlier contact", spec.frame),
            ));
        }
        contacts.push(Contact {
            frame,
            kind: spec.kind,
            reference: spec.reference,
        });
    }
    let rows: usize = contacts.iter().map(|c| c.kind.rows()).sum();
    if !contacts.is_empty() && rows >= nv {
        return Err(map.error(
            "contacts",
            format!("the contacts hold {rows} rows of the robot's {nv} degrees of freedom: nothing would be left to move"),
        ));
    }
    Ok(contacts)
}
