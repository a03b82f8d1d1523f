//! Joint-level parameters in descriptions (armature, viscous and Coulomb friction, offset):
//! which regressor columns a robot gets, and their values.
//!
//! ```yaml
//! joint_parameters:                          # absent: no joint-level columns (as before)
//!   columns: [armature, viscous, coulomb, offset]   # any of them; order does not matter
//!   coulomb_smoothing: 0.01                  # optional ε: tanh(q̇/ε) instead of sign(q̇)
//!   joints:                                  # optional per-joint values (override the joint's own)
//!     joint1: { armature: 0.3, viscous: 0.8, coulomb: 2.0, offset: -0.1 }
//! ```
//!
//! Values of a joint, lowest precedence first: 0; the joint's own (URDF
//! `<dynamics damping="fv" friction="fc"/>`: damping is viscous friction, friction is Coulomb
//! friction, as Gazebo reads them; inline YAML `dynamics: { armature, viscous, coulomb,
//! offset }`); the wrapper's `joint_parameters.joints.<name>`. Only the chosen `columns` act
//! (in θ, `Y`, `D`, `τ`); the others are read and checked but not used, so a URDF with
//! `<dynamics>` tags generates the rigid-body code until its wrapper chooses columns.

use super::error::{num, DescriptionError};
use super::raw::RawDynamics;
use super::source_map::{joint_path, SourceMap};
use crate::model::{Joint, JointTermKind, JointTermValues, JointTerms};
use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt;

/// The joint-level parameters a robot gets: the choice `Choices::joint_parameters` (YAML
/// `joint_parameters:`; the module docs).
#[derive(Clone, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct JointParameters {
    /// The kinds of joint-level regressor columns (`armature`, `viscous`, `coulomb`,
    /// `offset`), each at most once; the order does not matter.
    #[serde(default, deserialize_with = "columns")]
    pub columns: Vec<JointTermKind>,
    /// `ε` (rad/s or m/s) of `tanh(q̇/ε)`, a smooth Coulomb friction; `None`: `sign(q̇)`.
    pub coulomb_smoothing: Option<f64>,
    /// Values per joint name, over the joint's own (a moving joint that is not locked).
    #[serde(default)]
    pub joints: BTreeMap<String, JointValues>,
}

/// Joint-level values of one joint, each optional: `{ armature, viscous, coulomb, offset }`.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct JointValues {
    /// Reflected rotor inertia, kg·m² (kg for prismatic joints), ≥ 0.
    pub armature: Option<f64>,
    /// Viscous friction, N·m·s/rad (N·s/m), ≥ 0.
    pub viscous: Option<f64>,
    /// Coulomb friction, N·m (N), ≥ 0.
    pub coulomb: Option<f64>,
    /// Constant torque offset, N·m (N), either sign.
    pub offset: Option<f64>,
}

impl From<JointValues> for RawDynamics {
    fn from(d: JointValues) -> RawDynamics {
        RawDynamics {
            armature: d.armature,
            viscous: d.viscous,
            coulomb: d.coulomb,
            offset: d.offset,
        }
    }
}

/// `columns:` as written: a list of keywords, each an error at its place when unknown.
fn columns<'de, D: Deserializer<'de>>(deserializer: D) -> Result<Vec<JointTermKind>, D::Error> {
    struct Column(JointTermKind);
    impl<'de> Deserialize<'de> for Column {
        fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
            // Judged in the visitor, so that the error carries the keyword's place.
            struct Keyword;
            impl Visitor<'_> for Keyword {
                type Value = Column;
                fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                    f.write_str("a column: armature, viscous, coulomb or offset")
                }
                fn visit_str<E: de::Error>(self, c: &str) -> Result<Column, E> {
                    match JointTermKind::ALL.into_iter().find(|k| k.keyword() == c) {
                        Some(kind) => Ok(Column(kind)),
                        None => Err(E::custom(format!(
                            "unknown joint-parameter column '{c}' (expected armature, viscous, coulomb or offset)"
                        ))),
                    }
                }
            }
            deserializer.deserialize_str(Keyword)
        }
    }
    struct Columns;
    impl<'de> Visitor<'de> for Columns {
        type Value = Vec<JointTermKind>;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("a list of columns, e.g. [armature, viscous, coulomb, offset]")
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            let mut out = Vec::new();
            while let Some(Column(kind)) = seq.next_element()? {
                out.push(kind);
            }
            Ok(out)
        }
    }
    deserializer.deserialize_seq(Columns)
}

fn raw_get(d: &RawDynamics, kind: JointTermKind) -> Option<f64> {
    match kind {
        JointTermKind::Armature => d.armature,
        JointTermKind::Viscous => d.viscous,
        JointTermKind::Coulomb => d.coulomb,
        JointTermKind::Offset => d.offset,
    }
}

/// Checks one value: finite, and not negative unless it is an offset.
fn check_value(
    kind: JointTermKind,
    x: f64,
    map: &SourceMap,
    path: &str,
    joint: &str,
) -> Result<f64, DescriptionError> {
    let err = |msg: String| map.error(path, msg).about(format!("joint '{joint}'"));
    if !x.is_finite() {
        return Err(err(format!("{} {} is not finite", kind.keyword(), num(x))));
    }
    if kind.is_non_negative() && x < 0.0 {
        return Err(err(format!(
            "{} {} is negative: armature and friction cannot be",
            kind.keyword(),
            num(x)
        )));
    }
    Ok(x)
}

/// What the joint-level parameters need from the assembly.
pub(crate) struct JointSources<'a> {
    /// Raw joint index of every model joint, in model order.
    pub raw_index: &'a [usize],
    /// Raw joints' values as written, by raw index.
    pub raw: &'a [RawDynamics],
    /// Raw joints' motions and whether locked, by raw index.
    pub moving: &'a dyn Fn(usize) -> bool,
    pub joint_by_name: &'a std::collections::HashMap<String, usize>,
    pub robot_map: &'a SourceMap,
}

/// The model's [`JointTerms`] from the description; see the module docs.
pub(crate) fn joint_terms(
    spec: Option<&JointParameters>,
    map: &SourceMap,
    joints: &[Joint],
    src: &JointSources<'_>,
) -> Result<JointTerms, DescriptionError> {
    let Some(spec) = spec else {
        return Ok(JointTerms::default());
    };
    let mut kinds = Vec::new();
    for (i, &kind) in spec.columns.iter().enumerate() {
        if kinds.contains(&kind) {
            let msg = format!("joint-parameter column '{}' is listed twice", kind.keyword());
            return Err(map.error(&format!("joint_parameters.columns[{i}]"), msg));
        }
        kinds.push(kind);
    }
    if let Some(eps) = spec.coulomb_smoothing {
        if !(eps.is_finite() && eps > 0.0) {
            let msg = format!(
                "coulomb_smoothing {} must be a positive number (rad/s or m/s)",
                num(eps)
            );
            return Err(map.error("joint_parameters.coulomb_smoothing", msg));
        }
    }
    for name in spec.joints.keys() {
        let path = format!("joint_parameters.joints.{name}");
        let err = |msg: &str| map.error(&path, msg).about(format!("joint '{name}'"));
        match src.joint_by_name.get(name) {
            None => return Err(err("the robot has no joint of that name")),
            Some(&r) if !(src.moving)(r) => {
                return Err(err(
                    "the joint is fixed or locked: it has no joint-level parameters",
                ))
            }
            Some(_) => {}
        }
    }
    let mut values = Vec::with_capacity(joints.len());
    for (joint, &r) in joints.iter().zip(src.raw_index) {
        let mut v = JointTermValues::default();
        let own = src.raw[r];
        let wrapper = spec.joints.get(&joint.name).copied().map(RawDynamics::from);
        for kind in JointTermKind::ALL {
            if let Some(x) = raw_get(&own, kind) {
                let path = format!("{}.dynamics", joint_path(r));
                v.set(kind, check_value(kind, x, src.robot_map, &path, &joint.name)?);
            }
            if let Some(x) = wrapper.as_ref().and_then(|w| raw_get(w, kind)) {
                let path = format!("joint_parameters.joints.{}.{}", joint.name, kind.keyword());
                v.set(kind, check_value(kind, x, map, &path, &joint.name)?);
            }
        }
        values.push(v);
    }
    Ok(JointTerms {
        kinds: JointTerms::normalized_kinds(&kinds),
        coulomb_smoothing: spec.coulomb_smoothing,
        values,
    })
}
