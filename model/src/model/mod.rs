//! The kinematic-tree model that every robot description becomes.
//!
//! Invariants (checked by [`Model::new`], relied upon by every algorithm):
//! - joints are in topological order: a joint's parent index is smaller than its own;
//! - every joint moves (fixed and locked joints were merged away by the loader);
//! - axes are unit vectors, rotations are orthonormal; inertias are finite, symmetric and at
//!   most slightly non-physical ([`physical_inertia`]: the loader warns about, repairs or
//!   refuses the rest, as the description asks);
//! - body `i` is the rigid body carried by joint `i` (its frame is joint `i`'s frame);
//! - a mimic joint follows a joint that is not one ([`Mimic`]); the coordinates `q` are the
//!   joints that mimic nothing, in joint order;
//! - a joint whose parent is `None` hangs from the base: the world for a fixed base, the base
//!   body for a floating one ([`Model::floating_base`]), whose frame is then the root link's.

mod contact;
mod coupling;
mod joint_terms;
pub mod physical_inertia;
mod pose;
mod validate;

pub use contact::Contact;
pub use coupling::{CoordinateMap, Mimic};
pub use joint_terms::{JointTermKind, JointTermValues, JointTerms};
pub use physical_inertia::{inertia_defect, nearest_physical, InertiaDefect, InertiaDefectKind};
#[doc(hidden)]
pub use pose::{exact_sin_cos, quarter_turns};
pub use pose::{from_xyz_rpy, Pose};
pub(crate) use validate::principal_moments;
use validate::validate;
pub use validate::{ModelError, Warning};

use dyngen_runtime::{ParameterKind, BODY_PARAMETER_NAMES, PARAMETERS_PER_BODY};
use nalgebra::{Matrix3, Vector3};

/// How a joint moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation about the axis by `q` radians (URDF `revolute` and `continuous`).
    Revolute,
    /// Translation along the axis by `q` metres (URDF `prismatic`).
    Prismatic,
}

/// Joint position, velocity and effort limits, as given by the description.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    pub lower: f64,
    pub upper: f64,
    pub velocity: f64,
    pub effort: f64,
}

/// One moving joint of the tree.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// Name from the description (URDF joint name).
    pub name: String,
    /// Index of the parent joint, or `None` when the joint hangs from the fixed base.
    pub parent: Option<usize>,
    pub kind: JointKind,
    /// Joint frame in the parent joint's frame (or in the base frame) at `q = 0`.
    pub origin: Pose,
    /// Unit axis in the joint frame.
    pub axis: Vector3<f64>,
    /// `None` for continuous joints.
    pub limits: Option<Limits>,
}

/// Mass properties of a rigid body, expressed in its joint frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Inertia {
    pub mass: f64,
    /// Centre of mass in the body frame.
    pub com: Vector3<f64>,
    /// Rotational inertia about the centre of mass, body-frame axes.
    pub inertia_com: Matrix3<f64>,
}

/// The rigid body carried by a joint (all links welded to it are already merged in).
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// Name of the link that the joint moves (the child link in URDF).
    pub name: String,
    pub inertia: Inertia,
}

/// A named frame rigidly attached to a body, e.g. the end-effector.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    pub name: String,
    /// Index of the joint (body) that carries the frame; `None` for the floating base body
    /// (an IMU on a trunk), as a joint's `parent` is `None` on the base.
    pub parent: Option<usize>,
    /// Frame pose in the parent joint's frame (in the base body's frame when on the base).
    pub placement: Pose,
}

/// A fixed-base kinematic tree with its inertial parameters. It satisfies the invariants of
/// this module or is not built: the only way to one is [`Model::new`], which checks them.
#[derive(Clone, Debug, PartialEq)]
pub struct Model {
    name: String,
    joints: Vec<Joint>,
    bodies: Vec<Body>,
    gravity: Vector3<f64>,
    /// The frames generated code computes: the end-effector first, then the frames the
    /// description named, with distinct names.
    frames: Vec<Frame>,
    /// Joint-level parameters (armature, friction, offset): which columns `Y` gets after the
    /// inertial ones, and their values. Default: none.
    joint_terms: JointTerms,
    /// Per joint, the joint it mimics (`None`: the joint is a coordinate). Default: none.
    mimics: Vec<Option<Mimic>>,
    /// Per joint, where its position comes from (derived from `mimics`).
    coordinate_maps: Vec<CoordinateMap>,
    /// The body of a free-flying base (the root link and every link welded to it), or `None`
    /// for a base fixed to the world. Default: fixed.
    floating_base: Option<Body>,
    /// Named frames held to the world (the group `contacts`). Default: none.
    contacts: Vec<Contact>,
}

impl Inertia {
    /// The ten standard parameters `[m, m·c, I_O]` with `I_O` about the body-frame origin,
    /// in the order `[m, mcx, mcy, mcz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]`.
    pub fn parameters(&self) -> [f64; PARAMETERS_PER_BODY] {
        dyngen_runtime::body_parameters(self.mass, &self.com, &self.inertia_com)
    }

    /// The same body seen from another frame: `pose` is this body's frame in the new frame.
    pub fn transformed(&self, pose: &Pose) -> Inertia {
        Inertia {
            mass: self.mass,
            com: pose.transform_point(&self.com),
            inertia_com: pose.rotation * self.inertia_com * pose.rotation.transpose(),
        }
    }

    /// Two bodies welded together (both expressed in the same frame).
    pub fn merged(&self, other: &Inertia) -> Inertia {
        let mass = self.mass + other.mass;
        if mass == 0.0 {
            return Inertia {
                mass: 0.0,
                com: Vector3::zeros(),
                inertia_com: self.inertia_com + other.inertia_com,
            };
        }
        // A massless part (an end-effector link, a frame) leaves the body unchanged, bit for
        // bit: `(c m + 0) / m` need not round back to `c`.
        if other.mass == 0.0 || self.mass == 0.0 {
            let (massive, massless) = if other.mass == 0.0 {
                (self, other)
            } else {
                (other, self)
            };
            return Inertia {
                mass,
                com: massive.com,
                inertia_com: massive.inertia_com + massless.inertia_com,
            };
        }
        let com = (self.com * self.mass + other.com * other.mass) / mass;
        let shift = |b: &Inertia| {
            let d = b.com - com;
            b.inertia_com + (Matrix3::identity() * d.dot(&d) - d * d.transpose()) * b.mass
        };
        Inertia {
            mass,
            com,
            inertia_com: shift(self) + shift(other),
        }
    }
}

impl Model {
    /// A model of moving `joints` (topological order) carrying `bodies` (`joints[i]` carries
    /// `bodies[i]`), with `gravity` in the base frame and the `end_effector` frame, checked.
    pub fn new(
        name: impl Into<String>,
        joints: Vec<Joint>,
        bodies: Vec<Body>,
        gravity: Vector3<f64>,
        end_effector: Frame,
    ) -> Result<Model, ModelError> {
        let n = joints.len();
        let model = Model {
            name: name.into(),
            joints,
            bodies,
            gravity,
            frames: vec![end_effector],
            joint_terms: JointTerms::default(),
            mimics: vec![None; n],
            coordinate_maps: coupling::coordinate_maps(&[], n),
            floating_base: None,
            contacts: Vec::new(),
        };
        validate(&model)?;
        Ok(model)
    }

    /// The same robot with more named frames after the end-effector (replacing any it had).
    /// A frame with the end-effector's name must be the end-effector, and is kept once.
    pub fn with_frames(mut self, frames: Vec<Frame>) -> Result<Model, ModelError> {
        self.frames.truncate(1);
        for frame in frames {
            if frame != self.frames[0] {
                self.frames.push(frame);
            }
        }
        validate(&self)?;
        Ok(self)
    }

    /// The same robot with joint-level parameters (which regressor columns, and values).
    pub fn with_joint_terms(mut self, joint_terms: JointTerms) -> Result<Model, ModelError> {
        self.joint_terms = joint_terms;
        validate(&self)?;
        Ok(self)
    }

    /// The same robot with mimic joints: `mimics[j]` is the joint that joint `j` follows.
    pub fn with_mimics(mut self, mimics: Vec<Option<Mimic>>) -> Result<Model, ModelError> {
        self.coordinate_maps = coupling::coordinate_maps(&mimics, self.joints.len());
        self.mimics = mimics;
        validate(&self)?;
        Ok(self)
    }

    /// The same robot on a free-flying base whose body is `base` (in the root link's frame,
    /// which the root joints' origins are given in). Its configuration is then the base pose
    /// and `q` (`nq = dof + 7`), its velocity the base twist and `q̇` (`nv = dof + 6`).
    pub fn with_floating_base(mut self, base: Body) -> Result<Model, ModelError> {
        self.floating_base = Some(base);
        validate(&self)?;
        Ok(self)
    }

    /// The same robot with `contacts` held to the world (replacing any it had).
    pub fn with_contacts(mut self, contacts: Vec<Contact>) -> Result<Model, ModelError> {
        self.contacts = contacts;
        validate(&self)?;
        if !self.contacts.is_empty() && crate::dynamics::constrained::free_degrees(&self) == 0 {
            return Err(ModelError(format!(
                "the contacts' {} rows hold every one of the robot's {} degrees of freedom: nothing would be left to move",
                self.contact_rows(),
                self.nv()
            )));
        }
        Ok(self)
    }

    /// The frames held to the world, in the order of their rows.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// The rows the contacts hold: three per point, six per frame.
    pub fn contact_rows(&self) -> usize {
        self.contacts.iter().map(|c| c.kind.rows()).sum()
    }

    /// The body of the free-flying base, `None` for a fixed base.
    pub fn floating_base(&self) -> Option<&Body> {
        self.floating_base.as_ref()
    }

    /// Length of the velocity vector: `dof()`, plus the base twist's six on a floating base.
    pub fn nv(&self) -> usize {
        self.dof() + if self.floating_base.is_some() { 6 } else { 0 }
    }

    /// Length of the configuration vector: `dof()`, plus the base position and unit
    /// quaternion's seven on a floating base.
    pub fn nq(&self) -> usize {
        self.dof() + if self.floating_base.is_some() { 7 } else { 0 }
    }

    /// Per joint, the joint it follows (`None` for the joints that are coordinates).
    pub fn mimics(&self) -> &[Option<Mimic>] {
        &self.mimics
    }

    /// Whether some joint mimics another (then `dof() < joints().len()`).
    pub fn has_mimics(&self) -> bool {
        self.mimics.iter().any(Option::is_some)
    }

    /// Per joint, the coordinate of `q` its position comes from, with multiplier and offset.
    pub fn coordinate_maps(&self) -> &[CoordinateMap] {
        &self.coordinate_maps
    }

    /// The joints that are coordinates (mimic nothing), in joint order: `q_k` is the position
    /// of joint `coordinate_joints()[k]`.
    pub fn coordinate_joints(&self) -> Vec<usize> {
        (0..self.joints.len())
            .filter(|&j| self.mimics[j].is_none())
            .collect()
    }

    /// The same kinematics with other bodies (e.g. identified, or carrying a payload).
    pub fn with_bodies(mut self, bodies: Vec<Body>) -> Result<Model, ModelError> {
        self.bodies = bodies;
        validate(&self)?;
        Ok(self)
    }

    /// The joint-level parameters (none unless the description chose columns).
    pub fn joint_terms(&self) -> &JointTerms {
        &self.joint_terms
    }

    /// The same robot under another gravity (e.g. none, for energy checks).
    pub fn with_gravity(mut self, gravity: Vector3<f64>) -> Result<Model, ModelError> {
        self.gravity = gravity;
        validate(&self)?;
        Ok(self)
    }

    /// Robot name from the description.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Moving joints in topological order; `joints()[i]` carries `bodies()[i]`.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// One rigid body per moving joint, in joint order.
    pub fn bodies(&self) -> &[Body] {
        &self.bodies
    }

    /// Gravity acceleration in the base frame.
    pub fn gravity(&self) -> Vector3<f64> {
        self.gravity
    }

    /// The frame a controller tracks by default, the first of [`Model::frames`].
    pub fn end_effector(&self) -> &Frame {
        &self.frames[0]
    }

    /// The body that carries the end-effector: always a moving one.
    pub fn end_effector_body(&self) -> usize {
        self.frames[0]
            .parent
            .expect("the end-effector rides on a moving body (validated)")
    }

    /// Every frame generated code computes: the end-effector, then the named frames.
    pub fn frames(&self) -> &[Frame] {
        &self.frames
    }

    /// Number of degrees of freedom: the moving joints that mimic no other (the length of `q`).
    pub fn dof(&self) -> usize {
        self.coordinate_maps.len() - self.mimics.iter().flatten().count()
    }

    /// Number of inertial parameters, ten per body (the first entries of θ); a mimic joint's
    /// body has its ten like any other.
    pub fn inertial_parameter_count(&self) -> usize {
        PARAMETERS_PER_BODY * self.joints.len()
    }

    /// Length of θ: the inertial parameters, then the joint-level ones.
    pub fn parameter_count(&self) -> usize {
        self.inertial_parameter_count() + self.joint_terms.per_joint() * self.joints.len()
    }

    /// The standard parameter vector θ: ten parameters per body, body after body in joint
    /// order; then, joint after joint, the chosen joint-level parameters
    /// ([`crate::model::JointTerms`]).
    pub fn parameters(&self) -> Vec<f64> {
        let mut theta: Vec<f64> = self.bodies.iter().flat_map(|b| b.inertia.parameters()).collect();
        for j in 0..self.joints.len() {
            let v = self.joint_terms.value(j);
            theta.extend(self.joint_terms.kinds.iter().map(|&k| v.get(k)));
        }
        theta
    }

    /// Names of the entries of [`Model::parameters`], e.g. `"mcx[link3]"`, `"fv[joint3]"`.
    pub fn parameter_names(&self) -> Vec<String> {
        let mut names: Vec<String> = self
            .bodies
            .iter()
            .flat_map(|b| {
                BODY_PARAMETER_NAMES
                    .iter()
                    .map(move |p| format!("{p}[{}]", b.name))
            })
            .collect();
        for j in &self.joints {
            names.extend(
                self.joint_terms
                    .kinds
                    .iter()
                    .map(|k| format!("{}[{}]", k.symbol(), j.name)),
            );
        }
        names
    }

    /// Index in θ of joint `joint`'s parameter of kind `kind`, if the model has that column.
    pub fn joint_term_index(&self, joint: usize, kind: JointTermKind) -> Option<usize> {
        let pos = self.joint_terms.kinds.iter().position(|&k| k == kind)?;
        Some(self.inertial_parameter_count() + joint * self.joint_terms.per_joint() + pos)
    }

    /// The joint and kind of joint-level parameter column `column` (the inverse of
    /// [`Model::joint_term_index`]; `column` at or after the inertial ones).
    pub fn joint_term_of_column(&self, column: usize) -> (usize, JointTermKind) {
        let k = column - self.inertial_parameter_count();
        let per_joint = self.joint_terms.per_joint();
        (k / per_joint, self.joint_terms.kinds[k % per_joint])
    }

    /// The same model with parameters θ (as [`Model::parameters`]): the joint-level values
    /// of the chosen kinds are taken from θ (the inertial part is not a `Model` field that a
    /// vector can set without a body decomposition; see `NumericDynamics::with_parameters`).
    pub fn joint_term_values_from(&self, theta: &[f64]) -> Vec<JointTermValues> {
        (0..self.joints.len())
            .map(|j| {
                let mut v = JointTermValues::default();
                for &k in &self.joint_terms.kinds {
                    if let Some(i) = self.joint_term_index(j, k) {
                        v.set(k, theta[i]);
                    }
                }
                v
            })
            .collect()
    }

    /// The kind of each entry of [`Model::parameters`].
    pub fn parameter_kinds(&self) -> Vec<ParameterKind> {
        let per_body = (0..PARAMETERS_PER_BODY).map(ParameterKind::of_body_entry);
        let mut kinds: Vec<ParameterKind> = self.bodies.iter().flat_map(|_| per_body.clone()).collect();
        for _ in &self.joints {
            kinds.extend(self.joint_terms.kinds.iter().map(|k| k.parameter_kind()));
        }
        kinds
    }

    /// Joints from the base down to `joint` (inclusive), base first.
    pub fn chain_to(&self, joint: usize) -> Vec<usize> {
        let mut chain = vec![joint];
        let mut j = joint;
        while let Some(p) = self.joints[j].parent {
            chain.push(p);
            j = p;
        }
        chain.reverse();
        chain
    }
}
