//! Checks of the model invariants, and the physical-validity test of a rigid body's inertia.
//!
//! Every algorithm relies on the invariants listed in the [module docs](super); the loaders
//! guarantee them, and [`Model::validate`] re-checks them on the finished model so that a bug
//! in a loader (or a hand-built model) is caught before it turns into wrong generated code.

use super::physical_inertia::{percent, GROSS_DEFECT};
use super::{Inertia, Model, Pose};
use nalgebra::{Matrix3, SymmetricEigen, Vector3};
use std::collections::HashSet;
use std::fmt;

/// A model that breaks an invariant.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("{0}")]
pub struct ModelError(pub String);

/// Relative tolerance of the inertia tests (negative moments, triangle inequality, no extent),
/// as a fraction of the largest principal moment.
///
/// Published inertias are rounded to a few significant digits, so a flat plate (`I1 + I2 = I3`
/// exactly) may come out a hair on the wrong side; one part per million forgives that
/// rounding and nothing that matters physically.
pub const INERTIA_REL_TOL: f64 = 1e-6;

/// Tolerance on unit axes and orthonormal rotations.
const UNIT_TOL: f64 = 1e-9;

/// Something legal in a model but probably not what the author meant.
#[derive(Clone, Debug, PartialEq)]
pub enum Warning {
    /// A moving body with zero mass that carries no further joints: nothing resists its joint,
    /// so the mass matrix is singular.
    MasslessLeaf {
        /// The joint that carries the body.
        joint: String,
        /// The body (link) name.
        body: String,
    },
    /// A moving body whose total mass is zero (bodies further out may still give its joint inertia).
    MasslessBody {
        /// The joint that carries the body.
        joint: String,
        /// The body (link) name.
        body: String,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::MasslessLeaf { joint, body } => write!(
                f,
                "link '{body}': zero mass and no children (joint '{joint}' moves nothing; \
                 the mass matrix is singular)"
            ),
            Warning::MasslessBody { joint, body } => {
                write!(
                    f,
                    "link '{body}': the body moved by joint '{joint}' has zero total mass"
                )
            }
        }
    }
}

/// Principal moments of a symmetric rotational inertia, in ascending order.
///
/// NaN for a matrix that is not finite (the eigen-solver would never converge on it). The
/// solver works on the matrix scaled to entries of at most 1, so that no intermediate
/// overflows even for absurd inputs like `1e308`.
pub fn principal_moments(inertia: &Matrix3<f64>) -> [f64; 3] {
    if inertia.iter().any(|v| !v.is_finite()) {
        return [f64::NAN; 3];
    }
    let scale = inertia.amax();
    if scale == 0.0 {
        return [0.0; 3];
    }
    let unit = inertia / scale;
    let sym = (unit + unit.transpose()) * 0.5;
    let eig = SymmetricEigen::new(sym).eigenvalues * scale;
    let mut m = [eig[0], eig[1], eig[2]];
    m.sort_by(f64::total_cmp);
    m
}

impl Model {
    /// Legal but suspicious bodies (zero mass), for the loader to report.
    pub fn warnings(&self) -> Vec<Warning> {
        // A `Model` is valid by construction, so only the warnings remain to be had.
        validate(self).unwrap_or_default()
    }
}

/// Checks the model invariants: topological order, unit axes, orthonormal rotations, finite
/// numbers, inertias at most slightly non-physical, a valid end-effector frame; returns the
/// warnings.
pub(super) fn validate(model: &Model) -> Result<Vec<Warning>, ModelError> {
    let err = |msg: String| Err(ModelError(msg));
    let n = model.joints.len();
    if model.bodies.len() != n {
        return err(format!("{} joints but {} bodies", n, model.bodies.len()));
    }
    if n == 0 {
        return err("the model has no moving joints".into());
    }
    if !finite3(&model.gravity) {
        return err("gravity is not finite".into());
    }
    let mut names = HashSet::new();
    for (i, joint) in model.joints.iter().enumerate() {
        let name = &joint.name;
        if !names.insert(name.as_str()) {
            return err(format!("joint '{name}' appears twice"));
        }
        if let Some(p) = joint.parent {
            if p >= i {
                return err(format!(
                    "joint '{name}' (index {i}) has parent index {p}: not in topological order"
                ));
            }
        }
        check_pose(&joint.origin).map_err(|m| ModelError(format!("joint '{name}': origin {m}")))?;
        if !finite3(&joint.axis) || (joint.axis.norm() - 1.0).abs() > UNIT_TOL {
            return err(format!("joint '{name}': axis is not a unit vector"));
        }
        if let Some(l) = &joint.limits {
            let all = [l.lower, l.upper, l.velocity, l.effort];
            if all.iter().any(|v| !v.is_finite()) || l.lower > l.upper {
                return err(format!("joint '{name}': invalid limits"));
            }
        }
        check_inertia(&model.bodies[i].inertia)
            .map_err(|m| ModelError(format!("body '{}': {m}", model.bodies[i].name)))?;
    }
    if let Some(base) = &model.floating_base {
        check_inertia(&base.inertia).map_err(|m| ModelError(format!("base body '{}': {m}", base.name)))?;
    }
    for (k, frame) in model.frames.iter().enumerate() {
        let what = match k {
            0 => "end-effector",
            _ => "frame",
        };
        match (frame.parent, &model.floating_base) {
            (Some(p), _) if p >= n => {
                return err(format!(
                    "{what} '{}': parent joint {p} does not exist",
                    frame.name
                ));
            }
            (None, _) if k == 0 => {
                return err(format!(
                    "end-effector '{}' is on the base: it must ride on a moving joint's body",
                    frame.name
                ));
            }
            (None, None) => {
                return err(format!(
                    "frame '{}' is on the fixed base: it does not move",
                    frame.name
                ));
            }
            _ => {}
        }
        check_pose(&frame.placement)
            .map_err(|m| ModelError(format!("{what} '{}': placement {m}", frame.name)))?;
        if model.frames[..k].iter().any(|f| f.name == frame.name) {
            return err(format!("frame '{}' is defined twice", frame.name));
        }
    }
    let names: Vec<&str> = model.joints.iter().map(|j| j.name.as_str()).collect();
    super::coupling::check_mimics(&model.mimics, &names).map_err(ModelError)?;
    check_joint_terms(model).map_err(ModelError)?;
    super::contact::check_contacts(model).map_err(ModelError)?;

    let mut has_child = vec![false; n];
    for p in model.joints.iter().filter_map(|j| j.parent) {
        has_child[p] = true;
    }
    let warnings = model
        .bodies
        .iter()
        .zip(&model.joints)
        .zip(has_child)
        .filter(|((body, _), _)| body.inertia.mass == 0.0)
        .map(|((body, joint), has_child)| {
            let (joint, body) = (joint.name.clone(), body.name.clone());
            if has_child {
                Warning::MasslessBody { joint, body }
            } else {
                Warning::MasslessLeaf { joint, body }
            }
        })
        .collect();
    Ok(warnings)
}

/// Joint-level parameters: kinds in column order without repeats, one value set per joint
/// (or none), finite values, non-negative armature and friction, a positive smoothing.
fn check_joint_terms(model: &Model) -> Result<(), String> {
    let t = &model.joint_terms;
    if crate::model::JointTerms::normalized_kinds(&t.kinds) != t.kinds {
        return Err("joint-parameter kinds are not in column order or repeat".into());
    }
    if !t.values.is_empty() && t.values.len() != model.joints.len() {
        return Err(format!(
            "{} joint-parameter sets for {} joints",
            t.values.len(),
            model.joints.len()
        ));
    }
    if !t.kinds.is_empty() && model.has_mimics() {
        return Err("joint-level parameters on a robot with mimic joints are not supported".into());
    }
    if let Some(eps) = t.coulomb_smoothing {
        if !(eps.is_finite() && eps > 0.0) {
            return Err(format!("Coulomb smoothing {eps} is not a positive number"));
        }
    }
    for (v, joint) in t.values.iter().zip(&model.joints) {
        for kind in crate::model::JointTermKind::ALL {
            let x = v.get(kind);
            if !x.is_finite() || (kind.is_non_negative() && x < 0.0) {
                return Err(format!(
                    "joint '{}': {} {x} is invalid",
                    joint.name,
                    kind.keyword()
                ));
            }
        }
    }
    Ok(())
}

fn finite3(v: &Vector3<f64>) -> bool {
    v.iter().all(|x| x.is_finite())
}

fn check_pose(pose: &Pose) -> Result<(), String> {
    let r = &pose.rotation;
    if !finite3(&pose.translation) || r.iter().any(|v| !v.is_finite()) {
        return Err("is not finite".into());
    }
    let off = (r.transpose() * r - Matrix3::identity()).abs().max();
    if off > UNIT_TOL || r.determinant() < 0.0 {
        return Err("rotation is not orthonormal".into());
    }
    Ok(())
}

fn check_inertia(inertia: &Inertia) -> Result<(), String> {
    if !inertia.mass.is_finite() || inertia.mass < 0.0 {
        return Err(format!(
            "mass {} is not a finite non-negative number",
            inertia.mass
        ));
    }
    if !finite3(&inertia.com) {
        return Err("centre of mass is not finite".into());
    }
    let tensor = &inertia.inertia_com;
    if tensor.iter().any(|v| !v.is_finite()) {
        return Err("inertia has a number that is not finite".into());
    }
    let asym = (tensor - tensor.transpose()).abs().max();
    if asym > INERTIA_REL_TOL * tensor.abs().max() {
        return Err("inertia matrix is not symmetric".into());
    }
    match inertia.defect() {
        Some(defect) if defect.exceeds(MODEL_GROSS_DEFECT) => Err(format!(
            "{defect}, by more than a model allows (a triangle excess I3 − I1 − I2 of {} of the \
             largest moment)",
            percent(GROSS_DEFECT)
        )),
        _ => Ok(()),
    }
}

/// The largest triangle excess a model's body may have, as a fraction of its largest moment:
/// the loader's [`GROSS_DEFECT`] (bodies merged from links within it stay within it, see
/// `physical_inertia`), with a margin for the rounding of the merge, so that a description
/// the loader accepts is never an invalid model.
const MODEL_GROSS_DEFECT: f64 = GROSS_DEFECT + 2.0 * INERTIA_REL_TOL;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Body, Frame, Joint, JointKind};

    fn one_joint(inertia: Inertia) -> Model {
        Model {
            name: "m".into(),
            joints: vec![Joint {
                name: "j".into(),
                parent: None,
                kind: JointKind::Revolute,
                origin: Pose::identity(),
                axis: Vector3::z(),
                limits: None,
            }],
            bodies: vec![Body {
                name: "b".into(),
                inertia,
            }],
            gravity: Vector3::new(0.0, 0.0, -9.81),
            joint_terms: Default::default(),
            mimics: vec![None],
            floating_base: None,
            contacts: Vec::new(),
            coordinate_maps: super::super::coupling::coordinate_maps(&[None], 1),
            frames: vec![Frame {
                name: "ee".into(),
                parent: Some(0),
                placement: Pose::identity(),
            }],
        }
    }

    fn inertia(mass: f64, diag: [f64; 3]) -> Inertia {
        Inertia {
            mass,
            com: Vector3::zeros(),
            inertia_com: Matrix3::from_diagonal(&diag.into()),
        }
    }

    #[test]
    fn valid_model_passes() {
        assert_eq!(validate(&one_joint(inertia(1.0, [1.0, 1.0, 1.0]))), Ok(vec![]));
    }

    #[test]
    fn triangle_inequality_is_checked_beyond_slight_defects() {
        let e = validate(&one_joint(inertia(1.0, [1.0, 1.0, 5.0]))).unwrap_err();
        assert!(
            e.0.contains("not physical: triangle inequality broken by 60%")
                && e.0.contains("more than a model allows"),
            "{e}"
        );
        // a flat plate is exactly on the boundary and is fine; a slight defect is a model too
        // (the loader decides whether to warn, repair or refuse)
        assert!(validate(&one_joint(inertia(1.0, [1.0, 1.0, 2.0]))).is_ok());
        assert!(validate(&one_joint(inertia(1.0, [1.0, 1.0, 2.5]))).is_ok());
    }

    #[test]
    fn a_large_negative_moment_is_rejected() {
        let e = validate(&one_joint(inertia(1.0, [-1.0, 1.0, 1.0]))).unwrap_err();
        assert!(
            e.0.contains("not physical: principal moment -1 kg·m² is negative"),
            "{e}"
        );
        assert!(validate(&one_joint(inertia(1.0, [-0.01, 1.0, 1.0]))).is_ok());
    }

    #[test]
    fn topological_order_is_checked() {
        let mut m = one_joint(inertia(1.0, [1.0, 1.0, 1.0]));
        m.joints[0].parent = Some(0);
        assert!(validate(&m).unwrap_err().0.contains("topological"));
    }

    #[test]
    fn axis_and_rotation_are_checked() {
        let mut m = one_joint(inertia(1.0, [1.0, 1.0, 1.0]));
        m.joints[0].axis = Vector3::new(0.0, 0.0, 2.0);
        assert!(validate(&m).unwrap_err().0.contains("unit"));
        let mut m = one_joint(inertia(1.0, [1.0, 1.0, 1.0]));
        m.frames[0].placement.rotation[(0, 0)] = 2.0;
        assert!(validate(&m).unwrap_err().0.contains("orthonormal"));
    }

    #[test]
    fn only_a_floating_base_carries_frames_and_never_the_end_effector() {
        let on_base = |k: usize| {
            let mut m = one_joint(inertia(1.0, [1.0, 1.0, 1.0]));
            m.frames.push(Frame {
                name: "imu".into(),
                parent: Some(0),
                placement: Pose::identity(),
            });
            m.frames[k].parent = None;
            m
        };
        let e = validate(&on_base(1)).unwrap_err();
        assert!(e.0.contains("frame 'imu' is on the fixed base"), "{e}");
        let floating = Body {
            name: "trunk".into(),
            inertia: inertia(2.0, [1.0, 1.0, 1.0]),
        };
        let mut m = on_base(1);
        m.floating_base = Some(floating.clone());
        assert!(validate(&m).is_ok());
        let mut m = on_base(0);
        m.floating_base = Some(floating);
        let e = validate(&m).unwrap_err();
        assert!(e.0.contains("end-effector 'ee' is on the base"), "{e}");
        let mut m = one_joint(inertia(1.0, [1.0, 1.0, 1.0]));
        m.frames[0].parent = Some(3);
        assert!(validate(&m)
            .unwrap_err()
            .0
            .contains("parent joint 3 does not exist"));
    }

    #[test]
    fn massless_leaf_is_a_warning() {
        let w = validate(&one_joint(inertia(0.0, [0.0, 0.0, 0.0]))).unwrap();
        assert_eq!(
            w,
            vec![Warning::MasslessLeaf {
                joint: "j".into(),
                body: "b".into()
            }]
        );
        assert!(w[0].to_string().contains("zero mass and no children"));
    }

    #[test]
    fn nan_is_rejected() {
        let mut m = one_joint(inertia(1.0, [1.0, 1.0, 1.0]));
        m.bodies[0].inertia.com.x = f64::NAN;
        assert!(validate(&m).is_err());
    }
}
