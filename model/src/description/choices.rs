//! What a user chooses on top of a robot description, declared once: [`Choices`].
//!
//! A YAML description writes its choices as keys beside the robot (`end_effector: tool0`);
//! for a bare URDF or a `urdf_rs::Robot` the caller gives them (`load_with`, `from_urdf_rs`,
//! `dyngen_codegen::Builder`, the `dyngen` flags). The keys are the field names of
//! [`Choices`], listed once by the declaration itself ([`Choices::KEYS`]): the YAML reader
//! checks a file's keys against them, and messages that name keys take them from there.

use super::contacts::ContactSpec;
use super::joint_parameters::JointParameters;
use crate::Functions;
use serde::de::{self, value::MapAccessDeserializer, Deserializer, MapAccess, Visitor};
use serde::Deserialize;
use std::fmt;

/// Declares [`Choices`] and what is derived from its one list of fields: the keys, which keys
/// a value chooses, and a description's choices combined with a caller's.
macro_rules! declare_choices {
    (
        $(#[$attr:meta])*
        pub struct Choices {
            $( $(#[$field_attr:meta])* pub $field:ident: $ty:ty, )*
        }
    ) => {
        $(#[$attr])*
        pub struct Choices {
            $( $(#[$field_attr])* pub $field: $ty, )*
        }

        impl Choices {
            /// Every key, as a YAML description writes it (the field names), in declaration
            /// order.
            pub const KEYS: &'static [&'static str] = &[$(stringify!($field)),*];

            /// The keys this value chooses: those whose value is not the default.
            pub fn chosen_keys(&self) -> Vec<&'static str> {
                let default = Choices::default();
                let mut keys = Vec::new();
                $(
                    if self.$field != default.$field {
                        keys.push(stringify!($field));
                    }
                )*
                keys
            }

            /// `self`, with every choice `other` makes (each key `other` chooses replaces
            /// this value's; the other keys stay as they are).
            pub fn with(mut self, other: Choices) -> Choices {
                let default = Choices::default();
                $(
                    if other.$field != default.$field {
                        self.$field = other.$field;
                    }
                )*
                self
            }
        }
    };
}

declare_choices! {
    /// What a user chooses on top of a robot description: each field is one key of a YAML
    /// description, one setter of `dyngen_codegen::Builder`, one flag of `dyngen` where it has
    /// one. The default chooses nothing: the description as written, the generator's defaults.
    ///
    /// A bare URDF (or a `urdf_rs::Robot`) gets all of them from the caller. A YAML
    /// description writes its own; a caller may choose the keys it does not write, and a key
    /// chosen by both is an error naming the key.
    ///
    /// ```
    /// use dyngen_model::description::{Choices, FrameSelection};
    /// let choices = Choices {
    ///     frames: FrameSelection::AllLinks,
    ///     snap_angles: Some(1e-4),
    ///     ..Choices::default()
    /// };
    /// assert_eq!(choices.chosen_keys(), ["frames", "snap_angles"]);
    /// assert!(Choices::KEYS.contains(&"floating_base"));
    /// let more = choices.with(Choices { floating_base: true, ..Choices::default() });
    /// assert_eq!(more.chosen_keys(), ["frames", "snap_angles", "floating_base"]);
    /// ```
    #[derive(Clone, Debug, Default, PartialEq, Deserialize)]
    #[serde(default)]
    pub struct Choices {
        /// The frame whose pose and Jacobian are generated: a link name
        /// (`end_effector: tool0`), or a frame at a fixed offset from a link
        /// (`end_effector: { name: tcp, link: link7, xyz: [0, 0, 0.1], rpy: [0, 0, 0] }`;
        /// [`FrameSpec`]). Default: the leaf link at the end of the longest chain (a note says
        /// which).
        pub end_effector: Option<FrameSpec>,
        /// The named frames generated besides the end-effector (the group `frames`): a list,
        /// each written like `end_effector`, or `all` for every link that moves
        /// ([`FrameSelection`]). Default: the end-effector only.
        pub frames: FrameSelection,
        /// Joints made rigid at a position (radians, or metres for a prismatic joint), e.g.
        /// gripper fingers: `locked_joints: { finger_joint1: 0.0 }`, in order. The links they
        /// carry are welded to the body that carries the joint. The position must lie within
        /// the joint's limits; a locked mimic joint stays where it is locked, and the master
        /// of an unlocked mimic joint cannot be locked. Default: none.
        #[serde(deserialize_with = "locked_joints")]
        pub locked_joints: Vec<(String, f64)>,
        /// Gravity acceleration in the base frame, m/s². Default `[0, 0, -9.81]` (z up).
        pub gravity: Option<[f64; 3]>,
        /// Make origin angles within this many radians of a quarter turn exact quarter turns,
        /// and axis components this close to 0 exactly 0 (above 0, at most 1e-3), each change
        /// a note. Default: none; every angle and axis is used as written, and those within
        /// 1e-3 of exact get a warning with the tolerance that would make them exact.
        pub snap_angles: Option<f64>,
        /// What to do with a link whose inertia no real body can have (a negative principal
        /// moment, a broken triangle inequality, mass without extent about an axis):
        /// `as_written`, `repair` or `strict` ([`NonPhysicalInertia`]). Default: as written,
        /// with a warning.
        pub inertia: NonPhysicalInertia,
        /// The root link moves freely in the world (a legged robot, a humanoid, a mobile
        /// manipulator): the configuration gains the base pose, the velocity the base twist,
        /// and the root link's inertia becomes the base body's. Default `false`: the root link
        /// is fixed to the world.
        pub floating_base: bool,
        /// Joint-level parameters (armature, viscous and Coulomb friction, offset): which
        /// regressor columns the robot gets, and values that override the description's own
        /// ([`JointParameters`]). Default: none (no joint-level columns).
        pub joint_parameters: Option<JointParameters>,
        /// The groups of functions to generate besides kinematics and dynamics:
        /// `functions: [regressors, forward_dynamics]`, or `all` ([`Functions`]). Default: every
        /// group up to 12 joints; above, kinematics, dynamics, forward dynamics and frames (a
        /// note says what was left out).
        pub functions: Option<Functions>,
        /// Named frames held to the world, for constrained dynamics (the group `contacts`):
        /// `contacts: [{ frame: FL_FOOT, kind: point }, { frame: left_sole, kind: frame,
        /// reference: local_world_aligned }]` ([`ContactSpec`]). Each names the end-effector or
        /// a frame of `frames`. Default: none.
        pub contacts: Vec<ContactSpec>,
        /// Which reference frames of the frame functions (the group `frames`) are
        /// straight-line code of their own: `all`, or `aligned` (`local_world_aligned` only,
        /// `local` and `world` converted from it at run time) ([`FrameReferences`]). Default:
        /// `all` while the frames' code is small, `aligned` for many frames on a large robot
        /// (a note says which).
        pub frame_references: FrameReferences,
        /// How the functions that have two forms are written: `flat` (one straight-line
        /// function each) or `composed` (computed from the robot's smaller generated functions
        /// through the tree factor of `D`, in loops) ([`CodeShape`]). Default: `flat` while a
        /// function's straight-line code is small, `composed` where it would be megabytes (a
        /// note says which).
        pub code_shape: CodeShape,
    }
}

/// The error for a key chosen both by a description and by the caller.
pub(crate) fn chosen_twice(key: &str) -> String {
    match key {
        "functions" => "the functions to generate were chosen twice, by `functions:` in the \
                        description and by the caller: choose them in one place"
            .to_owned(),
        _ => format!(
            "`{key}` was chosen twice, by `{key}:` in the description and by the caller: choose \
             it in one place"
        ),
    }
}

/// What the loader does with a link whose inertia no real body can have: the choice
/// [`Choices::inertia`] (YAML `inertia: as_written | repair | strict`).
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

/// Which reference frames of the frame functions are straight-line code of their own: the
/// choice [`Choices::frame_references`] (YAML `frame_references: all | aligned`).
///
/// A frame quantity in each of the three reference frames is three straight-line functions;
/// `local` and `world` are each a few operations per Jacobian column away from
/// `local_world_aligned`. On a humanoid with every link a frame the three take most of the
/// module, so converting at run time keeps the frames' code about a third (the module and its
/// compile time about half), for a conversion per call in `local` and `world`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameReferences {
    /// `all` where the frames' code is small, `aligned` where it is large (the generator's
    /// estimate of the module's size decides).
    #[default]
    Auto,
    /// Every reference frame its own straight-line function: the fastest.
    All,
    /// `local_world_aligned` straight-line; `local` and `world` converted from it at run time.
    Aligned,
}

/// How the functions that have two forms are written: the choice [`Choices::code_shape`] (YAML
/// `code_shape: flat | composed`).
///
/// Straight-line code is fastest while a function fits the instruction caches, but some
/// functions' code grows fast with the robot: on a humanoid the derivatives of forward dynamics
/// are megabytes of it, on a mobile manipulator with hands `D⁻¹`, and they take minutes to
/// compile. Composed, such a function calls the robot's `D`, inverse dynamics and its
/// derivatives and solves through the tree factor of `D` in loops: no code of its own, for a
/// slower call. The functions with a composed form are listed in `docs/descriptions.md`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CodeShape {
    /// `flat` where a function's straight-line code is small, `composed` where it is large (the
    /// generator's estimate of its size decides).
    #[default]
    Auto,
    /// Every function one straight-line function.
    Flat,
    /// Every function that has a composed form in that form.
    Composed,
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

/// A link's own frame ([`FrameSpec::link`]): `"tool0".into()`.
impl From<&str> for FrameSpec {
    fn from(link: &str) -> Self {
        FrameSpec::link(link)
    }
}

/// A link's own frame ([`FrameSpec::link`]).
impl From<String> for FrameSpec {
    fn from(link: String) -> Self {
        FrameSpec::link(link)
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

/// The frames generated besides the end-effector: the choice [`Choices::frames`] (YAML
/// `frames: [tool0, { name: sensor, link: link7, xyz: [0, 0, 0.05] }]` or `frames: all`).
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

/// `locked_joints` as YAML writes it: a map from joint name to position, kept in file order,
/// with repeated names rejected (a plain map would silently keep one of them).
fn locked_joints<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<(String, f64)>, D::Error> {
    struct LockedVisitor;
    impl<'de> Visitor<'de> for LockedVisitor {
        type Value = Vec<(String, f64)>;
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
            Ok(out)
        }
    }
    deserializer.deserialize_map(LockedVisitor)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde::de::value::Error;
    use serde::forward_to_deserialize_any;

    /// A deserializer that only records the fields serde asks for.
    struct FieldNames(&'static [&'static str]);

    impl<'de> Deserializer<'de> for &mut FieldNames {
        type Error = Error;
        fn deserialize_any<V: Visitor<'de>>(self, _: V) -> Result<V::Value, Error> {
            Err(de::Error::custom("not a struct"))
        }
        fn deserialize_struct<V: Visitor<'de>>(
            self,
            _: &'static str,
            fields: &'static [&'static str],
            _: V,
        ) -> Result<V::Value, Error> {
            self.0 = fields;
            Err(de::Error::custom("recorded"))
        }
        forward_to_deserialize_any! {
            bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf
            option unit unit_struct newtype_struct seq tuple tuple_struct map enum identifier
            ignored_any
        }
    }

    #[test]
    fn the_keys_are_the_keys_serde_reads() {
        let mut names = FieldNames(&[]);
        let _ = Choices::deserialize(&mut names);
        assert_eq!(names.0, Choices::KEYS);
    }

    #[test]
    fn with_takes_the_keys_the_other_chooses_and_keeps_the_rest() {
        let moon = Choices {
            gravity: Some([0.0, 0.0, -1.62]),
            locked_joints: vec![("finger".into(), 0.0)],
            ..Choices::default()
        };
        let other = Choices {
            floating_base: true,
            locked_joints: vec![("wrist".into(), 0.5)],
            ..Choices::default()
        };
        let both = moon.with(other);
        assert_eq!(both.chosen_keys(), ["locked_joints", "gravity", "floating_base"]);
        assert_eq!(both.locked_joints, [("wrist".to_owned(), 0.5)]);
        assert_eq!(both.gravity, Some([0.0, 0.0, -1.62]));
    }
}
