//! A [`urdf_rs::Robot`] (what `k`, `urdf-viz` and openrr hold) → the raw link/joint graph, so
//! that it goes through exactly the checks and the assembly of a URDF file.
//!
//! urdf-rs has already parsed the XML and filled in its defaults, and a few of them cannot be
//! told apart from values written out:
//! - `Link::inertial` is not optional: an all-zero inertial (mass, inertia and origin) is how
//!   urdf-rs stores a link without `<inertial>`, and it is read as a massless link, exactly as
//!   the file reader does for a missing `<inertial>` (both give the same zero body).
//! - `Joint::limit` is not optional: an all-zero limit (lower, upper, velocity, effort) is how
//!   urdf-rs stores a joint without `<limit>`, and it is read as no limit. A revolute or
//!   prismatic joint then fails with the file reader's "needs a limit" (a joint whose range,
//!   velocity and effort are all zero could not move anyway).
//! - URDF 1.2's "no limit" is infinity; dyngen rejects non-finite limits as it does in a file.
//!
//! What dyngen does not model is reported, never dropped silently: the URDF 1.2 acceleration,
//! deceleration and jerk limits each give a note. `<dynamics damping friction>` is read as the
//! file reader reads it (viscous and Coulomb friction).
//! Visuals, collisions, materials, calibration and safety controllers do not enter the dynamics
//! and are skipped, as the file reader skips them.

use super::error::{item, render, DescriptionError};
use super::raw::{RawDynamics, RawInertial, RawJoint, RawLimit, RawLink, RawMimic, RawRobot};
use std::path::PathBuf;

/// How messages name an in-memory robot, in place of a file: `<urdf_rs::Robot 'panda'>`.
pub(crate) fn place(robot: &urdf_rs::Robot) -> PathBuf {
    if robot.name.is_empty() {
        PathBuf::from("<urdf_rs::Robot>")
    } else {
        PathBuf::from(format!("<urdf_rs::Robot '{}'>", robot.name))
    }
}

/// The raw graph of `robot`, and notes about what dyngen does not use. Empty names are errors
/// here (the file reader rejects them while reading); everything else is judged by the checks.
pub(crate) fn read(robot: &urdf_rs::Robot) -> Result<(RawRobot, Vec<String>), DescriptionError> {
    let file = place(robot);
    let mut notes = Vec::new();
    let mut links = Vec::with_capacity(robot.links.len());
    for (i, link) in robot.links.iter().enumerate() {
        if link.name.is_empty() {
            let msg = format!("the link at index {i} has an empty name");
            return Err(DescriptionError::new(&file, msg));
        }
        links.push(RawLink {
            name: link.name.clone(),
            inertial: inertial(&link.inertial),
        });
    }
    let mut joints = Vec::with_capacity(robot.joints.len());
    for (i, joint) in robot.joints.iter().enumerate() {
        if joint.name.is_empty() {
            let msg = format!("the joint at index {i} has an empty name");
            return Err(DescriptionError::new(&file, msg));
        }
        let label = item("joint", &joint.name);
        for (role, link) in [("parent", &joint.parent.link), ("child", &joint.child.link)] {
            if link.is_empty() {
                let msg = format!("the {role} link name is empty");
                return Err(DescriptionError::new(&file, msg).about(label));
            }
        }
        let l = &joint.limit;
        let extra: Vec<&str> = [
            ("acceleration", l.acceleration),
            ("deceleration", l.deceleration),
            ("jerk", l.jerk),
        ]
        .into_iter()
        .filter(|(_, v)| !v.is_infinite())
        .map(|(what, _)| what)
        .collect();
        if !extra.is_empty() {
            let msg = format!(
                "{} limit not used: dyngen models position, velocity and effort limits only",
                extra.join(", ")
            );
            notes.push(render(&file, None, Some(&label), &msg));
        }
        joints.push(RawJoint {
            name: joint.name.clone(),
            kind: kind(&joint.joint_type).to_owned(),
            parent: joint.parent.link.clone(),
            child: joint.child.link.clone(),
            xyz: joint.origin.xyz.0,
            rpy: joint.origin.rpy.0,
            axis: joint.axis.xyz.0,
            limit: limit(l),
            mimic: joint.mimic.as_ref().map(|m| RawMimic {
                joint: m.joint.clone(),
                // urdfdom's defaults, as the file reader uses.
                multiplier: m.multiplier.unwrap_or(1.0),
                offset: m.offset.unwrap_or(0.0),
            }),
            // As the file reader reads `<dynamics damping friction>`: viscous and Coulomb
            // friction (used when the description asks for those columns).
            dynamics: joint
                .dynamics
                .as_ref()
                .map_or(RawDynamics::default(), |d| RawDynamics {
                    viscous: Some(d.damping),
                    coulomb: Some(d.friction),
                    ..RawDynamics::default()
                }),
        });
    }
    let raw = RawRobot {
        name: (!robot.name.is_empty()).then(|| robot.name.clone()),
        links,
        joints,
    };
    Ok((raw, notes))
}

/// The joint type as URDF spells it, for the checks to judge (as they judge a file's text).
fn kind(joint_type: &urdf_rs::JointType) -> &'static str {
    use urdf_rs::JointType as T;
    match joint_type {
        T::Revolute => "revolute",
        T::Continuous => "continuous",
        T::Prismatic => "prismatic",
        T::Fixed => "fixed",
        T::Floating => "floating",
        T::Planar => "planar",
        T::Spherical => "spherical",
    }
}

/// `None` for urdf-rs's stand-in for a missing `<inertial>` (all zeros); see the module docs.
fn inertial(i: &urdf_rs::Inertial) -> Option<RawInertial> {
    let t = &i.inertia;
    let inertia = [t.ixx, t.ixy, t.ixz, t.iyy, t.iyz, t.izz];
    let mut values = i
        .origin
        .xyz
        .iter()
        .chain(i.origin.rpy.iter())
        .chain(&inertia)
        .chain(std::iter::once(&i.mass.value));
    if values.all(|v| *v == 0.0) {
        return None;
    }
    Some(RawInertial {
        xyz: i.origin.xyz.0,
        rpy: i.origin.rpy.0,
        mass: i.mass.value,
        inertia,
    })
}

/// `None` for urdf-rs's stand-in for a missing `<limit>` (all zeros); see the module docs.
fn limit(l: &urdf_rs::JointLimit) -> Option<RawLimit> {
    let raw = RawLimit {
        lower: l.lower,
        upper: l.upper,
        velocity: l.velocity,
        effort: l.effort,
    };
    let zero = [raw.lower, raw.upper, raw.velocity, raw.effort]
        .iter()
        .all(|v| *v == 0.0);
    (!zero).then_some(raw)
}
