//! The link/joint graph as written, before any check: what both readers (URDF and YAML)
//! produce, so that every check and every rule of the tree is written once.
//!
//! Numbers are kept exactly as read (NaN included) and joint types as text: judging them is
//! the job of the checks, which report them with the place of the item.

/// A robot description as a list of links and joints, in file order.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct RawRobot {
    pub name: Option<String>,
    pub links: Vec<RawLink>,
    pub joints: Vec<RawJoint>,
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RawLink {
    pub name: String,
    /// `None`: the link has no mass (URDF without `<inertial>`).
    pub inertial: Option<RawInertial>,
}

/// URDF `<inertial>`: the inertia tensor is about the centre of mass, in the frame placed at
/// `xyz`/`rpy` in the link frame.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RawInertial {
    pub xyz: [f64; 3],
    pub rpy: [f64; 3],
    pub mass: f64,
    /// `[ixx, ixy, ixz, iyy, iyz, izz]`.
    pub inertia: [f64; 6],
}

#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RawJoint {
    pub name: String,
    /// URDF joint type as written (`revolute`, `continuous`, `prismatic`, `fixed`, ...).
    pub kind: String,
    pub parent: String,
    pub child: String,
    pub xyz: [f64; 3],
    pub rpy: [f64; 3],
    /// As written (URDF default `[1, 0, 0]`), not yet normalized.
    pub axis: [f64; 3],
    pub limit: Option<RawLimit>,
    pub mimic: Option<RawMimic>,
    /// Joint-level values as written (URDF `<dynamics>`, YAML `dynamics:`); `None`: not given.
    pub dynamics: RawDynamics,
}

/// Joint-level values of one joint, each optional: URDF `<dynamics damping friction>` gives
/// `viscous` and `coulomb`; YAML `dynamics: { armature, viscous, coulomb, offset }` any of them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct RawDynamics {
    pub armature: Option<f64>,
    pub viscous: Option<f64>,
    pub coulomb: Option<f64>,
    pub offset: Option<f64>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RawLimit {
    pub lower: f64,
    pub upper: f64,
    pub velocity: f64,
    pub effort: f64,
}

/// URDF `<mimic>`: `q = multiplier * q_joint + offset`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RawMimic {
    pub joint: String,
    pub multiplier: f64,
    pub offset: f64,
}
