//! dyngen's YAML robot files, in two forms.
//!
//! **Form (a), the robot inline** (URDF semantics, URDF names):
//!
//! ```yaml
//! name: arm7
//! gravity: [0.0, 0.0, -9.81]            # optional
//! end_effector: { name: tool, link: link7, xyz: [0, 0, 0.1], rpy: [0, 0, 0] }   # or a link name
//! links:
//!   - name: base_link                   # no inertial: massless
//!   - name: link1
//!     inertial:
//!       mass: 3.4525
//!       origin: { xyz: [0, -0.03, 0.12], rpy: [0, 0, 0] }
//!       inertia: { ixx: 0.02, ixy: 0.001, ixz: 0.0, iyy: 0.02, iyz: 0.0, izz: 0.01 }
//! joints:
//!   - name: joint1
//!     type: revolute
//!     parent: base_link
//!     child: link1
//!     origin: { xyz: [0, 0, 0.1575], rpy: [0, 0, 0] }
//!     axis: [0, 0, 1]
//!     limit: { lower: -2.96, upper: 2.96, velocity: 1.48, effort: 320 }
//! ```
//!
//! **Form (b), a wrapper around a URDF file**:
//!
//! ```yaml
//! urdf: urdf/panda.urdf                 # relative to this file
//! name: panda                           # optional
//! end_effector: panda_hand_tcp
//! frames: [panda_link4, { name: sensor, link: panda_link8, xyz: [0, 0, 0.05] }]   # or `all`
//! locked_joints: { panda_finger_joint1: 0.0, panda_finger_joint2: 0.0 }
//! gravity: [0.0, 0.0, -9.81]
//! snap_angles: 1e-4                     # optional: 1.5708 → π/2 (each change noted)
//! functions: [regressors, forward_dynamics]   # optional: the groups to generate (or `all`)
//! inertia: repair                       # optional: as_written (default) | repair | strict
//! floating_base: true                   # optional: the root link flies free (default false)
//! ```
//!
//! Every key but the robot's (`urdf`, or `links` and `joints`, and `name`) is one of the user's
//! [`Choices`], in either form: [`Choices`] documents each (`joint_parameters:` among them:
//! armature, friction and offset columns and values). Form (a) joints may add a `dynamics:` map
//! of their own joint-level values.
//!
//! Unknown keys are errors (a typo must not be ignored).

use super::choices::Choices;
use super::error::{DescriptionError, Location};
use super::joint_parameters::JointValues;
use super::raw::{RawDynamics, RawInertial, RawJoint, RawLimit, RawLink, RawMimic, RawRobot};
use super::source_map::{read_regular_file, SourceMap};
use super::{urdf, yaml_spans};
use serde::de::IgnoredAny;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A robot file: the robot, either `urdf` (form b) or `links` + `joints` (form a), never both;
/// and the user's [`Choices`], each a key beside them.
#[derive(Debug, Deserialize)]
pub(crate) struct RobotFile {
    /// Robot name, used to name generated code. Required for form (a); for form (b) it
    /// defaults to the URDF `<robot name>`.
    name: Option<String>,
    /// Form (b): path of the URDF file to load, relative to this YAML file.
    urdf: Option<String>,
    /// Form (a): the links, in any order.
    links: Option<Vec<LinkSpec>>,
    /// Form (a): the joints. Their order fixes the order of sibling branches.
    joints: Option<Vec<JointSpec>>,
    /// Every key but the four above, each a key of [`Choices`] ([`Choices::KEYS`]) or an error.
    /// Before `choices`: serde's `flatten` lends all remaining keys to a map and hands a
    /// struct only its own, so this sees the choices' keys too.
    #[serde(flatten)]
    other_keys: BTreeMap<String, IgnoredAny>,
    /// The user's choices (`end_effector`, `frames`, …): [`Choices`] documents each key.
    #[serde(flatten)]
    choices: Choices,
}

/// The keys of a robot file that are the robot, not a choice: the fields of [`RobotFile`].
const DESCRIPTION_KEYS: [&str; 4] = ["name", "urdf", "links", "joints"];

/// Every key a robot file may have: the robot's, then the choices'.
fn keys() -> impl Iterator<Item = &'static str> {
    DESCRIPTION_KEYS.into_iter().chain(Choices::KEYS.iter().copied())
}

/// A link (a rigid body), as URDF `<link>`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LinkSpec {
    /// Unique link name.
    name: String,
    /// Mass properties; absent: the link is massless (a pure frame).
    inertial: Option<InertialSpec>,
}

/// Mass properties, as URDF `<inertial>`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct InertialSpec {
    /// Mass in kg, not negative.
    mass: f64,
    /// The centre-of-mass frame in the link frame: `xyz` is the centre of mass, `rpy` the
    /// orientation of the axes the inertia is given in. Default: identity.
    origin: Option<OriginSpec>,
    /// Rotational inertia about the centre of mass, in the `origin` axes, kg·m².
    inertia: InertiaSpec,
}

/// The six independent entries of a symmetric inertia tensor (all required, as in URDF).
/// Should be positive definite and satisfy the triangle inequality (or be all zero: a point
/// mass); what happens when it does not is the file's `inertia:` choice.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct InertiaSpec {
    ixx: f64,
    ixy: f64,
    ixz: f64,
    iyy: f64,
    iyz: f64,
    izz: f64,
}

/// A placement, as URDF `<origin>`: translation `xyz` (m) then rotation `rpy` (rad; roll about
/// x, pitch about y, yaw about z, fixed axes: `R = Rz(yaw) Ry(pitch) Rx(roll)`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
struct OriginSpec {
    /// Default `[0, 0, 0]`.
    #[serde(default)]
    xyz: [f64; 3],
    /// Default `[0, 0, 0]`.
    #[serde(default)]
    rpy: [f64; 3],
}

/// A joint, as URDF `<joint>`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct JointSpec {
    /// Unique joint name.
    name: String,
    /// `revolute`, `continuous` (revolute without limits), `prismatic` or `fixed`.
    #[serde(rename = "type")]
    kind: String,
    /// The link the joint is attached to.
    parent: String,
    /// The link the joint moves; every link has at most one parent joint.
    child: String,
    /// The joint frame in the parent link frame at zero position. Default: identity.
    origin: Option<OriginSpec>,
    /// Rotation or translation axis in the joint frame (normalized). Default `[1, 0, 0]`.
    axis: Option<[f64; 3]>,
    /// Required for `revolute` and `prismatic`; ignored for `continuous`.
    limit: Option<LimitSpec>,
    /// This joint copies another: `q = multiplier * q_joint + offset` (it then has no
    /// coordinate of its own; chains are resolved), or stays locked if `locked_joints` says so.
    mimic: Option<MimicSpec>,
    /// Joint-level values `{ armature, viscous, coulomb, offset }` (each optional; used for
    /// the columns `joint_parameters.columns` chooses).
    dynamics: Option<JointValues>,
}

/// Joint limits, as URDF `<limit>` (all four required).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct LimitSpec {
    /// Lowest position (rad or m); not above `upper`.
    lower: f64,
    /// Highest position (rad or m).
    upper: f64,
    /// Largest speed (rad/s or m/s), not negative.
    velocity: f64,
    /// Largest torque or force (N·m or N), not negative.
    effort: f64,
}

/// As URDF `<mimic>`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MimicSpec {
    /// The joint that is copied.
    joint: String,
    /// Default 1.
    multiplier: Option<f64>,
    /// Default 0.
    offset: Option<f64>,
}

/// A YAML file read: the robot graph, where its items are, and the user's choices.
pub(crate) struct Parsed {
    pub robot: RawRobot,
    /// Places of links and joints: this file (form a) or the URDF (form b).
    pub robot_map: SourceMap,
    /// Places of the YAML keys and values (`end_effector`, `locked_joints.<joint>`, …).
    pub yaml_map: SourceMap,
    pub name: Option<String>,
    pub choices: Choices,
    /// The keys of `choices` the file writes.
    pub written: Vec<String>,
    /// Files read to get here (the URDF of form b).
    pub read: Vec<PathBuf>,
}

/// Parses a YAML robot file; for form (b) reads the URDF it points to.
pub(crate) fn parse(text: &str, file: &Path) -> Result<Parsed, DescriptionError> {
    check_flow_nesting(text, file)?;
    let spec: RobotFile = serde_yaml::from_str(text).map_err(|e| {
        // serde reads a flattened struct from a copy of the values, without their places:
        // the choices are read again on their own, and an error about one of their keys
        // (`gravity: invalid length 2, ...`) is reported from there, with its line and column.
        let about_a_choice = |e: &serde_yaml::Error| {
            let message = e.to_string();
            Choices::KEYS.iter().any(|k| {
                message
                    .strip_prefix(k)
                    .is_some_and(|rest| rest.starts_with([':', '.', '[']))
            })
        };
        match serde_yaml::from_str::<Choices>(text) {
            Err(choice) if about_a_choice(&choice) => serde_error(file, &choice),
            _ => serde_error(file, &e),
        }
    })?;
    let yaml_map = yaml_spans::index(text, file);
    let RobotFile {
        name,
        urdf,
        links,
        joints,
        other_keys,
        choices,
    } = spec;
    if let Some(unknown) = other_keys.keys().find(|k| !Choices::KEYS.contains(&k.as_str())) {
        let expected: Vec<String> = keys().map(|k| format!("`{k}`")).collect();
        let msg = format!(
            "unknown field `{unknown}`, expected one of {}",
            expected.join(", ")
        );
        return Err(yaml_map.key_error(unknown, msg));
    }
    let mut parsed = Parsed {
        robot: RawRobot::default(),
        robot_map: SourceMap::new(file),
        yaml_map,
        name,
        choices,
        written: other_keys.into_keys().collect(),
        read: Vec::new(),
    };
    let both = |key: &str| {
        let msg = format!(
            "`urdf:` and `{key}:` cannot be used together: wrap a URDF file or write the robot inline, not both"
        );
        Err(parsed.yaml_map.error(key, msg))
    };
    match (urdf, links, joints) {
        (Some(_), Some(_), _) => both("links"),
        (Some(_), None, Some(_)) => both("joints"),
        (Some(urdf_rel), None, None) => {
            let urdf_path = file.parent().unwrap_or(Path::new("")).join(&urdf_rel);
            let text = read_regular_file(&urdf_path).map_err(|e| {
                let msg = format!("cannot read URDF file '{}': {e}", urdf_path.display());
                parsed.yaml_map.error("urdf", msg)
            })?;
            parsed.read.push(urdf_path.clone());
            let (robot, robot_map) = urdf::read(&text, &urdf_path)?;
            parsed.robot = robot;
            parsed.robot_map = robot_map;
            Ok(parsed)
        }
        (None, Some(links), joints) => {
            if parsed.name.is_none() {
                return Err(
                    DescriptionError::new(file, "`name:` is required for a robot written inline")
                        .at(Some(Location { line: 1, column: 1 })),
                );
            }
            parsed.robot = RawRobot {
                name: parsed.name.clone(),
                links: links.into_iter().map(raw_link).collect(),
                joints: joints.unwrap_or_default().into_iter().map(raw_joint).collect(),
            };
            parsed.robot_map = parsed.yaml_map.clone();
            Ok(parsed)
        }
        (None, None, _) => Err(DescriptionError::new(
            file,
            "no robot: give either `urdf:` (a URDF file to wrap) or `links:` and `joints:`",
        )
        .at(Some(Location { line: 1, column: 1 }))),
    }
}

fn raw_link(l: LinkSpec) -> RawLink {
    RawLink {
        name: l.name,
        inertial: l.inertial.map(|i| {
            let origin = i.origin.unwrap_or_default();
            let InertiaSpec {
                ixx,
                ixy,
                ixz,
                iyy,
                iyz,
                izz,
            } = i.inertia;
            RawInertial {
                xyz: origin.xyz,
                rpy: origin.rpy,
                mass: i.mass,
                inertia: [ixx, ixy, ixz, iyy, iyz, izz],
            }
        }),
    }
}

fn raw_joint(j: JointSpec) -> RawJoint {
    let origin = j.origin.unwrap_or_default();
    RawJoint {
        name: j.name,
        kind: j.kind,
        parent: j.parent,
        child: j.child,
        xyz: origin.xyz,
        rpy: origin.rpy,
        axis: j.axis.unwrap_or([1.0, 0.0, 0.0]),
        limit: j.limit.map(|l| RawLimit {
            lower: l.lower,
            upper: l.upper,
            velocity: l.velocity,
            effort: l.effort,
        }),
        mimic: j.mimic.map(|m| RawMimic {
            joint: m.joint,
            multiplier: m.multiplier.unwrap_or(1.0),
            offset: m.offset.unwrap_or(0.0),
        }),
        dynamics: j.dynamics.map(RawDynamics::from).unwrap_or_default(),
    }
}

/// serde's message, with its " at line L column C" moved to the front as `file:L:C:`.
fn serde_error(file: &Path, e: &serde_yaml::Error) -> DescriptionError {
    let text = e.to_string();
    let location = e.location().map(|l| Location {
        line: l.line(),
        column: l.column(),
    });
    let message = match &location {
        Some(l) => {
            let suffix = format!(" at line {} column {}", l.line, l.column);
            text.strip_suffix(&suffix)
                .map(str::to_owned)
                .unwrap_or_else(|| text.clone())
        }
        None => text.clone(),
    };
    DescriptionError::new(file, message).at(location)
}

/// Deepest `[`/`{` nesting accepted. A robot file needs three or four levels; the YAML parser
/// takes time quadratic in the depth (a megabyte of `{a: ` takes minutes), so deeper input is
/// rejected before parsing.
pub(crate) const MAX_FLOW_NESTING: usize = 64;

/// Rejects flow collections nested deeper than [`MAX_FLOW_NESTING`], with the place of the
/// first bracket too deep. Brackets in quoted scalars and comments do not count (a quote
/// opens a scalar only where a token starts); a plain scalar with brackets in it (`a[1]`) may
/// count, which only matters beyond the limit. As a backstop against a quote this scan
/// misreads, brackets are also counted regardless of quotes, with a limit 16 times higher.
fn check_flow_nesting(text: &str, file: &Path) -> Result<(), DescriptionError> {
    #[derive(PartialEq)]
    enum In {
        Plain,
        Single,
        Double,
        Comment,
    }
    let mut state = In::Plain;
    let (mut depth, mut raw_depth, mut line, mut column) = (0usize, 0usize, 1usize, 0usize);
    let mut prev = '\n';
    let mut escaped = false;
    for c in text.chars() {
        column += 1;
        let token_start = prev.is_whitespace() || matches!(prev, '[' | '{' | ',');
        if state != In::Comment {
            match c {
                '[' | '{' => raw_depth += 1,
                ']' | '}' => raw_depth = raw_depth.saturating_sub(1),
                _ => {}
            }
        }
        match (&state, c) {
            (_, '\n') => {
                line += 1;
                column = 0;
                if state == In::Comment {
                    state = In::Plain;
                }
            }
            (In::Plain, '#') if prev.is_whitespace() => state = In::Comment,
            (In::Plain, '\'') if token_start => state = In::Single,
            (In::Plain, '"') if token_start => state = In::Double,
            (In::Plain, '[' | '{') => depth += 1,
            (In::Plain, ']' | '}') => depth = depth.saturating_sub(1),
            (In::Single, '\'') => state = In::Plain,
            (In::Double, '"') if !escaped => state = In::Plain,
            _ => {}
        }
        if depth > MAX_FLOW_NESTING || raw_depth > 16 * MAX_FLOW_NESTING {
            let msg = format!(
                "more than {MAX_FLOW_NESTING} nested levels of `[` and `{{`: not a robot description"
            );
            return Err(DescriptionError::new(file, msg).at(Some(Location { line, column })));
        }
        escaped = state == In::Double && c == '\\' && !escaped;
        prev = c;
    }
    Ok(())
}
