//! What a user chooses on top of a robot description: the end-effector and the other frames
//! to generate, joints locked at a value, gravity, what to do with near-exact angles and non-physical inertias. A bare URDF
//! gets them from [`UrdfOptions`]; a YAML file from its keys.

use serde::de::{self, value::MapAccessDeserializer, Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use std::fmt;

/// Options for loading a bare URDF (a YAML wrapper sets the same things with its keys).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UrdfOptions {
    /// The frame whose pose and Jacobian are generated. `None`: the leaf link at the end of
    /// the longest chain (a note says which).
    pub end_effector: Option<FrameSpec>,
    /// The named frames generated besides the end-effector (the group `frames`). Default:
    /// the end-effector only.
    pub frames: FrameSelection,
    /// Joints made rigid at the given position (radians or metres), e.g. gripper fingers;
    /// the links they carry are merged into the body that carries the joint.
    pub locked_joints: Vec<(String, f64)>,
    /// Gravity acceleration in the base frame; default `[0, 0, -9.81]`.
    pub gravity: Option<[f64; 3]>,
    /// Make origin angles within this many radians of a quarter turn exact quarter turns,
    /// and axis components this close to 0 exactly 0 (at most 1e-3; each change is noted).
    /// `None`: such values are kept and warned about.
    pub snap_angles: Option<f64>,
    /// What to do with a link whose inertia no real body can have (a negative principal
    /// moment, a broken triangle inequality, mass without extent about an axis). Default:
    /// load it as written, with a warning.
    pub inertia: NonPhysicalInertia,
    /// The robot moves freely in the world on its root link (a legged robot, a humanoid, a
    /// mobile manipulator): its configuration gains the base pose, its velocity the base
    /// twist, and the root link's inertia becomes the base body's. Default: the root link is
    /// fixed to the world.
    pub floating_base: bool,
}

/// What the loader does with a link whose inertia no real body can have: YAML
/// `inertia: as_written | repair | strict`, [`UrdfOptions::inertia`],
/// [`Builder::inertia`](crate::Builder::inertia), `dyngen --inertia`.
///
/// The dynamics (`D`, `g`, `J`, `τ`) are well defined either way; physical consistency
/// matters to identification, which starts from the nearest physical inertia of a
/// description that is not physical. A defect beyond
/// [`GROSS_DEFECT`](crate::model::physical_inertia::GROSS_DEFECT) (a triangle excess
/// `I3 − I1 − I2` above half the largest moment) is wrong numbers rather than rounded ones:
/// refused unless repaired, or unless the link is welded to the fixed base (it then never
/// enters the dynamics).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NonPhysicalInertia {
    /// Keep the inertia as written; one warning per link says how far from physical it is.
    #[default]
    AsWritten,
    /// Replace it by the nearest physical inertia (same principal axes, each moment moved no
    /// further than the defect); one note per link gives the values before and after.
    Repair,
    /// Refuse it, as an error with the link's place.
    Strict,
}

impl NonPhysicalInertia {
    /// The value as YAML writes it (`as_written`, `repair`, `strict`).
    pub fn keyword(self) -> &'static str {
        match self {
            NonPhysicalInertia::AsWritten => "as_written",
            NonPhysicalInertia::Repair => "repair",
            NonPhysicalInertia::Strict => "strict",
        }
    }
}

/// A frame rigidly attached to a link, optionally moved by a fixed offset: the end-effector,
/// or one of `frames`.
///
/// In YAML either a link name (`end_effector: tool0`) or a map
/// (`end_effector: { name: tcp, link: link7, xyz: [0, 0, 0.1], rpy: [0, 0, 0] }`); the link
/// may be one that a fixed or locked joint merged into its parent's body.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameSpec {
    /// Name of the frame in the generated code; `None`: the link name.
    pub name: Option<String>,
    /// The link the frame is attached to.
    pub link: String,
    /// Offset of the frame in the link frame (metres); default zero.
    pub xyz: [f64; 3],
    /// Rotation of the frame in the link frame (roll, pitch, yaw about fixed axes, radians);
    /// default zero.
    pub rpy: [f64; 3],
}

impl FrameSpec {
    /// The frame of link `link` itself.
    pub fn link(link: impl Into<String>) -> Self {
        FrameSpec {
            name: None,
            link: link.into(),
            xyz: [0.0; 3],
            rpy: [0.0; 3],
        }
    }

    /// The name the frame gets: `name`, else the link name.
    pub fn frame_name(&self) -> &str {
        self.name.as_deref().unwrap_or(&self.link)
    }
}

/// The map form of a frame in YAML.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FrameMap {
    /// Name of the frame; default: the link name.
    name: Option<String>,
    /// The link the frame is attached to (required).
    link: String,
    /// Offset in the link frame, metres; default `[0, 0, 0]`.
    #[serde(default)]
    xyz: [f64; 3],
    /// Rotation in the link frame (roll, pitch, yaw about fixed axes), radians; default zero.
    #[serde(default)]
    rpy: [f64; 3],
}

impl<'de> Deserialize<'de> for FrameSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct SpecVisitor;
        impl<'de> Visitor<'de> for SpecVisitor {
            type Value = FrameSpec;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a link name, or a map with `link` and optional `name`, `xyz`, `rpy`")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                Ok(FrameSpec::link(v))
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                let m = FrameMap::deserialize(MapAccessDeserializer::new(map))?;
                Ok(FrameSpec {
                    name: m.name,
                    link: m.link,
                    xyz: m.xyz,
                    rpy: m.rpy,
                })
            }
        }
        deserializer.deserialize_any(SpecVisitor)
    }
}

/// The frames generated besides the end-effector: YAML `frames: [tool0, { name: sensor,
/// link: link7, xyz: [0, 0, 0.05] }]` or `frames: all`, [`UrdfOptions::frames`],
/// [`Builder::frames`](crate::Builder::frames), `dyngen --frame`.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum FrameSelection {
    /// The end-effector only.
    #[default]
    EndEffector,
    /// The end-effector and these frames (a frame named like the end-effector must be it).
    Listed(Vec<FrameSpec>),
    /// The end-effector and the frame of every link that moves: with a joint, or with a
    /// floating base (links welded to a fixed base have a constant pose and a zero Jacobian,
    /// and are left out).
    AllLinks,
}

impl<'de> Deserialize<'de> for FrameSelection {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct SelectionVisitor;
        impl<'de> Visitor<'de> for SelectionVisitor {
            type Value = FrameSelection;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("`all`, or a list of frames (each a link name or a map with `link`)")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Self::Value, E> {
                match v {
                    "all" => Ok(FrameSelection::AllLinks),
                    other => Err(E::custom(format!(
                        "frames: expected `all` or a list of frames, found '{other}' (a single \
                         frame is written as a list: `frames: [{other}]`)"
                    ))),
                }
            }
            fn visit_seq<A: de::SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut frames = Vec::new();
                while let Some(frame) = seq.next_element::<FrameSpec>()? {
                    frames.push(frame);
                }
                Ok(FrameSelection::Listed(frames))
            }
        }
        deserializer.deserialize_any(SelectionVisitor)
    }
}

/// `locked_joints` in YAML: a map from joint name to position, kept in file order, with
/// repeated names rejected (a plain map would silently keep one of them).
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct LockedJoints(pub Vec<(String, f64)>);

impl<'de> Deserialize<'de> for LockedJoints {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct LockedVisitor;
        impl<'de> Visitor<'de> for LockedVisitor {
            type Value = LockedJoints;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a map from joint name to locked position, e.g. { finger_joint1: 0.0 }")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                let mut out: Vec<(String, f64)> = Vec::new();
                while let Some((name, value)) = map.next_entry::<String, f64>()? {
                    if out.iter().any(|(n, _)| *n == name) {
                        return Err(de::Error::custom(format!("joint '{name}' is locked twice")));
                    }
                    out.push((name, value));
                }
                Ok(LockedJoints(out))
            }
        }
        deserializer.deserialize_map(LockedVisitor)
    }
}

/// The user's choices as the loader uses them, with the file they were written in (the YAML
/// wrapper, or the URDF itself when they came from [`UrdfOptions`]).
pub(crate) struct Settings<'a> {
    pub name: Option<String>,
    pub gravity: Option<[f64; 3]>,
    pub end_effector: Option<FrameSpec>,
    pub frames: FrameSelection,
    pub locked_joints: Vec<(String, f64)>,
    pub snap_angles: Option<f64>,
    pub inertia: NonPhysicalInertia,
    pub floating_base: bool,
    /// `joint_parameters:` of a YAML file (a bare URDF has none: no joint-level columns).
    pub joint_parameters: Option<super::joint_parameters::JointParametersSpec>,
    /// Places of `end_effector`, `frames[k]`, `gravity`, `locked_joints.<joint>`, `snap_angles`, `inertia`.
    pub map: &'a super::source_map::SourceMap,
}

impl Settings<'_> {
    /// The snapping asked for, checked: a tolerance in (0, 1e-3] rad.
    pub fn snap(&self) -> Result<super::near_exact::Snap, super::DescriptionError> {
        use super::near_exact::{Snap, REPORTED};
        match self.snap_angles {
            Some(t) if !(t > 0.0 && t <= REPORTED) => Err(self.map.error(
                "snap_angles",
                format!("snap_angles {t} must be a tolerance in radians, above 0 and at most {REPORTED}"),
            )),
            t => Ok(Snap(t)),
        }
    }
}
