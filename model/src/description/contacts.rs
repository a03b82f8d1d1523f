//! The frames a description holds to the world or to each other (`contacts:`), and their
//! resolution against the model's named frames.

use super::error::DescriptionError;
use super::source_map::SourceMap;
use crate::model::{Contact, Frame};
use dyngen_runtime::{ContactKind, ReferenceFrame};
use serde::de::{self, Deserializer};
use serde::Deserialize;

/// A named frame held to the world, or to another named frame, as a description writes it:
/// `{ frame: FL_FOOT, kind: point }`, `{ frame: left_sole, kind: frame, reference:
/// local_world_aligned }` or `{ frame: rod_end, to: crank_pin, kind: point }` (a loop closure).
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
    /// The frame it is held to, on another body (a loop closure); absent: the world.
    #[serde(default)]
    pub to: Option<String>,
}

impl ContactSpec {
    /// A contact at `frame`, in its own axes.
    pub fn new(frame: impl Into<String>, kind: ContactKind) -> ContactSpec {
        ContactSpec {
            frame: frame.into(),
            kind,
            reference: ReferenceFrame::Local,
            to: None,
        }
    }

    /// This contact, holding its frame to the frame named `to` rather than to the world.
    pub fn to(self, to: impl Into<String>) -> ContactSpec {
        ContactSpec {
            to: Some(to.into()),
            ..self
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
/// first); errors at the place of the offending entry. What the set holds together is
/// `Model::with_contacts`'s to check.
pub(crate) fn resolve(
    specs: &[ContactSpec],
    frames: &[Frame],
    map: &SourceMap,
) -> Result<Vec<Contact>, DescriptionError> {
    let mut contacts: Vec<Contact> = Vec::new();
    let known = || {
        let names: Vec<&str> = frames.iter().map(|f| f.name.as_str()).collect();
        names.join(", ")
    };
    let find = |name: &str, place: &str, role: &str| {
        frames.iter().position(|f| f.name == name).ok_or_else(|| {
            map.error(
                place,
                format!(
                    "no frame named '{name}' to {role}; name the end-effector or a frame listed under `frames:` ({})",
                    known()
                ),
            )
        })
    };
    for (k, spec) in specs.iter().enumerate() {
        let path = format!("contacts[{k}]");
        let frame = find(&spec.frame, &format!("{path}.frame"), "hold")?;
        let to = match &spec.to {
            None => None,
            Some(name) => {
                let place = format!("{path}.to");
                let to = find(name, &place, "hold to")?;
                if frames[to].parent == frames[frame].parent {
                    return Err(map.error(
                        &place,
                        format!(
                            "'{}' and '{name}' are frames of one body: a loop between them holds nothing",
                            spec.frame
                        ),
                    ));
                }
                Some(to)
            }
        };
        if contacts.iter().any(|c| c.frame == frame && c.to == to) {
            return Err(map.error(
                &path,
                format!("frame '{}' is held by an earlier contact", spec.frame),
            ));
        }
        contacts.push(Contact {
            frame,
            kind: spec.kind,
            reference: spec.reference,
            to,
        });
    }
    Ok(contacts)
}
