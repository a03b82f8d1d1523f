//! Each link and joint checked on its own, and turned into model quantities.
//!
//! Everything that can be judged without the rest of the tree is judged here, with the place
//! of the item: finite numbers, known joint types, a usable axis, ordered limits, whether an
//! inertia is physical (what is then done about it: `non_physical`). The tree rules (names,
//! parents, cycles) are in `tree`.

use super::choices::NonPhysicalInertia;
use super::error::{item, num, vec3, DescriptionError, Diagnostics};
use super::near_exact::{Finding, Snap};
use super::non_physical::{self, NonPhysicalLink};
use super::raw::{RawInertial, RawJoint, RawLink};
use super::source_map::{joint_path, link_path, SourceMap};
use crate::model::{from_xyz_rpy, principal_moments, Inertia, JointKind, Limits, Pose};
use nalgebra::{Matrix3, Vector3};

/// How a joint moves, once its type is known to be supported.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Motion {
    Fixed,
    Moving(JointKind),
}

/// A joint's own geometry and limits, checked.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct JointShape {
    pub motion: Motion,
    /// Joint frame in the parent link frame.
    pub origin: Pose,
    /// Unit axis (meaningless for fixed joints).
    pub axis: Vector3<f64>,
    /// `None` for continuous and fixed joints.
    pub limits: Option<Limits>,
}

const KNOWN_TYPES: &str = "revolute, continuous, prismatic or fixed";

/// Checks every joint on its own; see the module docs.
pub(crate) fn check_joints(
    joints: &[RawJoint],
    map: &SourceMap,
    snap: Snap,
    diags: &mut Diagnostics,
) -> Result<Vec<JointShape>, DescriptionError> {
    joints
        .iter()
        .enumerate()
        .map(|(i, j)| check_joint(i, j, map, snap, diags))
        .collect()
}

/// Near-exact values go to the warnings when left as written, to the notes when snapped.
fn report(findings: Vec<Finding>, map: &SourceMap, at: &str, label: &str, diags: &mut Diagnostics) {
    for f in findings {
        let line = map.diagnostic(at, Some(label), &f.message);
        if f.snapped {
            diags.notes.push(line);
        } else {
            diags.warnings.push(line);
        }
    }
}

fn check_joint(
    i: usize,
    j: &RawJoint,
    map: &SourceMap,
    snap: Snap,
    diags: &mut Diagnostics,
) -> Result<JointShape, DescriptionError> {
    let path = joint_path(i);
    let label = item("joint", &j.name);
    let err = |field: &str, msg: String| map.error(&format!("{path}{field}"), msg).about(label.clone());

    let motion = match j.kind.as_str() {
        "revolute" | "continuous" => Motion::Moving(JointKind::Revolute),
        "prismatic" => Motion::Moving(JointKind::Prismatic),
        "fixed" => Motion::Fixed,
        "floating" => {
            let msg = "type 'floating' is not supported inside the tree; a robot whose root link \
                       moves freely is loaded with `floating_base: true` (`Choices::floating_base`, \
                       `--floating-base`)";
            return Err(err(".type", msg.to_owned()));
        }
        "planar" => return Err(err(".type", "type 'planar' is not supported".to_owned())),
        other => {
            return Err(err(
                ".type",
                format!("unknown joint type '{other}' (expected {KNOWN_TYPES})"),
            ));
        }
    };

    for (what, v) in [("xyz", &j.xyz), ("rpy", &j.rpy)] {
        if !finite(v) {
            return Err(err(".origin", format!("origin {what} {} is not finite", vec3(v))));
        }
    }
    if let Some(msg) = too_large(&j.xyz, "origin xyz") {
        return Err(err(".origin", msg));
    }
    let (rpy, near) = snap.rpy("origin", j.rpy);
    report(near, map, &format!("{path}.origin"), &label, diags);
    let origin = from_xyz_rpy(j.xyz, rpy);
    let warn = |diags: &mut Diagnostics, field: &str, msg: String| {
        diags
            .warnings
            .push(map.diagnostic(&format!("{path}{field}"), Some(&label), &msg));
    };
    if let Some(msg) = far(&j.xyz, "origin") {
        warn(diags, ".origin", msg);
    }

    let axis = if motion == Motion::Fixed {
        Vector3::x()
    } else {
        if !finite(&j.axis) {
            return Err(err(".axis", format!("axis {} is not finite", vec3(&j.axis))));
        }
        // Scaled first: huge components overflow the plain norm and tiny ones underflow it
        // (its squares vanish), and either gives an axis that is not a unit vector.
        let a = Vector3::from(j.axis);
        let scale = a.amax();
        if scale == 0.0 {
            return Err(err(".axis", format!("axis {} has zero length", vec3(&j.axis))));
        }
        let (unit, norm) = if (1e-150..1e150).contains(&scale) {
            // Plain: the usual rounding for an axis that is not a unit vector.
            (a / a.norm(), a.norm())
        } else {
            let scaled = a / scale;
            (scaled / scaled.norm(), scale * scaled.norm())
        };
        // A unit vector to rounding is kept as written: dividing it by its norm again can
        // move it by an ulp, and a model written out (`to_urdf_rs`) must load back unchanged.
        let unit = if (norm - 1.0).abs() <= 4.0 * f64::EPSILON {
            a
        } else {
            unit
        };
        if (norm - 1.0).abs() > 1e-6 {
            let shown = vec3(&[unit.x, unit.y, unit.z]);
            let msg = format!("axis {} is not a unit vector: using {shown}", vec3(&j.axis));
            diags
                .notes
                .push(map.diagnostic(&format!("{path}.axis"), Some(&label), &msg));
        }
        let (unit, near) = snap.axis([unit.x, unit.y, unit.z]);
        report(near, map, &format!("{path}.axis"), &label, diags);
        Vector3::from(unit)
    };

    if let Some(m) = &j.mimic {
        if !(m.multiplier.is_finite() && m.offset.is_finite()) {
            return Err(err(".mimic", "mimic multiplier or offset is not finite".into()));
        }
    }

    let limits = match (&j.limit, j.kind.as_str()) {
        (Some(l), _)
            if ![l.lower, l.upper, l.velocity, l.effort]
                .iter()
                .all(|v| v.is_finite()) =>
        {
            let msg = format!(
                "limit (lower {}, upper {}, velocity {}, effort {}) has a number that is not finite",
                num(l.lower),
                num(l.upper),
                num(l.velocity),
                num(l.effort)
            );
            return Err(err(".limit", msg));
        }
        (Some(l), "revolute" | "prismatic") => {
            if l.lower > l.upper {
                let msg = format!(
                    "lower limit {} is greater than upper limit {}",
                    num(l.lower),
                    num(l.upper)
                );
                return Err(err(".limit", msg));
            }
            if l.velocity < 0.0 || l.effort < 0.0 {
                let msg = format!(
                    "velocity {} and effort {} limits must not be negative",
                    num(l.velocity),
                    num(l.effort)
                );
                return Err(err(".limit", msg));
            }
            if l.lower == l.upper {
                let msg = format!(
                    "lower and upper limits are both {}: the joint cannot move (lock it with \
                     `locked_joints` instead)",
                    num(l.lower)
                );
                warn(diags, ".limit", msg);
            }
            for (what, v) in [("velocity", l.velocity), ("effort", l.effort)] {
                if v == 0.0 {
                    let msg = format!("{what} limit is 0: the joint could not move; give the real limit");
                    warn(diags, ".limit", msg);
                }
            }
            Some(Limits {
                lower: l.lower,
                upper: l.upper,
                velocity: l.velocity,
                effort: l.effort,
            })
        }
        (None, "revolute" | "prismatic") => {
            let msg = format!(
                "a {} joint needs a limit (lower, upper, velocity, effort)",
                j.kind
            );
            return Err(err("", msg));
        }
        _ => None,
    };

    Ok(JointShape {
        motion,
        origin,
        axis,
        limits,
    })
}

/// Every link's mass properties, in the link frame, and the links whose inertia is not
/// physical (reported once the tree is known: `non_physical::report`).
pub(crate) struct CheckedLinks {
    pub inertias: Vec<Inertia>,
    pub non_physical: Vec<NonPhysicalLink>,
}

/// Checks every link's mass properties; an inertia that is not physical is kept, repaired or
/// refused as `inertia` says.
pub(crate) fn check_links(
    links: &[RawLink],
    map: &SourceMap,
    snap: Snap,
    inertia: NonPhysicalInertia,
    diags: &mut Diagnostics,
) -> Result<CheckedLinks, DescriptionError> {
    let mut checked = CheckedLinks {
        inertias: Vec::with_capacity(links.len()),
        non_physical: Vec::new(),
    };
    for (i, l) in links.iter().enumerate() {
        let link = match &l.inertial {
            None => Inertia {
                mass: 0.0,
                com: Vector3::zeros(),
                inertia_com: Matrix3::zeros(),
            },
            Some(inertial) => {
                let (link, found) = check_inertial(i, &l.name, inertial, map, snap, inertia, diags)?;
                checked.non_physical.extend(found);
                link
            }
        };
        checked.inertias.push(link);
    }
    Ok(checked)
}

fn check_inertial(
    i: usize,
    name: &str,
    inertial: &RawInertial,
    map: &SourceMap,
    snap: Snap,
    choice: NonPhysicalInertia,
    diags: &mut Diagnostics,
) -> Result<(Inertia, Option<NonPhysicalLink>), DescriptionError> {
    let path = format!("{}.inertial", link_path(i));
    let label = item("link", name);
    let err = |field: &str, msg: String| map.error(&format!("{path}{field}"), msg).about(label.clone());
    let RawInertial {
        xyz,
        rpy,
        mass,
        inertia: [ixx, ixy, ixz, iyy, iyz, izz],
    } = *inertial;

    if !mass.is_finite() {
        return Err(err(".mass", format!("mass {} is not finite", num(mass))));
    }
    if mass < 0.0 {
        return Err(err(".mass", format!("negative mass {}", num(mass))));
    }
    let warn = |diags: &mut Diagnostics, field: &str, msg: String| {
        diags
            .warnings
            .push(map.diagnostic(&format!("{path}{field}"), Some(&label), &msg));
    };
    if mass > MAX_PLAUSIBLE_MASS {
        let msg = format!(
            "mass {} kg is more than {} kg: is it in grams?",
            num(mass),
            num(MAX_PLAUSIBLE_MASS)
        );
        warn(diags, ".mass", msg);
    }
    if let Some(msg) = far(&xyz, "centre of mass") {
        warn(diags, ".origin", msg);
    }
    for (what, v) in [("xyz", &xyz), ("rpy", &rpy)] {
        if !finite(v) {
            return Err(err(
                ".origin",
                format!("inertial origin {what} {} is not finite", vec3(v)),
            ));
        }
    }
    if let Some(msg) = too_large(&[mass], "mass") {
        return Err(err(".mass", msg));
    }
    if let Some(msg) = too_large(&xyz, "inertial origin xyz") {
        return Err(err(".origin", msg));
    }
    if let Some(msg) = too_large(&[ixx, ixy, ixz, iyy, iyz, izz], "inertia") {
        return Err(err(".inertia", msg));
    }
    let tensor = Matrix3::new(ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz);
    if tensor.iter().any(|v| !v.is_finite()) {
        let msg = format!(
            "inertia (ixx {}, ixy {}, ixz {}, iyy {}, iyz {}, izz {}) has a number that is not finite",
            num(ixx),
            num(ixy),
            num(ixz),
            num(iyy),
            num(iyz),
            num(izz)
        );
        return Err(err(".inertia", msg));
    }
    let (tensor, non_physical) =
        non_physical::examine(i, name, mass, &tensor, choice).map_err(|m| err(".inertia", m))?;
    let moments = principal_moments(&tensor);
    let is_zero = tensor.iter().all(|v| *v == 0.0);
    if mass > 0.0 && is_zero {
        let msg = format!("mass {} with zero inertia: treated as a point mass", num(mass));
        diags
            .warnings
            .push(map.diagnostic(&format!("{path}.inertia"), Some(&label), &msg));
    } else if mass == 0.0 && !is_zero {
        let msg = "zero mass but a non-zero inertia";
        diags
            .warnings
            .push(map.diagnostic(&format!("{path}.inertia"), Some(&label), msg));
    } else if mass > 0.0 && moments[2] > 0.0 {
        // The radius of gyration about the principal axis of largest moment: how far from the
        // centre of mass the mass would sit. Outside a millimetre-to-metres band, the mass and
        // the inertia are almost surely in different units (g vs kg, mm² vs m²).
        let radius = (moments[2] / mass).sqrt();
        if !(MIN_GYRATION_RADIUS..=MAX_GYRATION_RADIUS).contains(&radius) {
            let msg = format!(
                "inertia does not fit the mass: radius of gyration √(I/m) = {} m, expected {} to \
                 {} m; check the units (kg, m, kg·m²)",
                num(radius),
                num(MIN_GYRATION_RADIUS),
                num(MAX_GYRATION_RADIUS)
            );
            warn(diags, ".inertia", msg);
        }
    }

    // The tensor is given in the inertial frame; the model wants link-frame axes.
    let (rpy, near) = snap.rpy("inertial origin", rpy);
    report(near, map, &path, &label, diags);
    let rotation = from_xyz_rpy(xyz, rpy).rotation;
    let link = Inertia {
        mass,
        com: Vector3::from(xyz),
        inertia_com: rotation * tensor * rotation.transpose(),
    };
    Ok((link, non_physical))
}

/// Above this mass (kg) a link gets a warning (a heavy industrial arm's links weigh tens to
/// hundreds of kilograms; ten tonnes is a unit mistake).
pub(crate) const MAX_PLAUSIBLE_MASS: f64 = 1e4;
/// Above this distance (m) an origin gets a warning (millimetres written as metres).
pub(crate) const MAX_PLAUSIBLE_LENGTH: f64 = 100.0;
/// The band of plausible radii of gyration (m): 0.1 mm to 10 m.
pub(crate) const MIN_GYRATION_RADIUS: f64 = 1e-4;
pub(crate) const MAX_GYRATION_RADIUS: f64 = 10.0;

/// Numbers beyond this magnitude are errors: no robot has them, and the products the
/// dynamics form of them would overflow `f64` (or lose every digit) in generated code.
pub(crate) const MAX_MAGNITUDE: f64 = 1e12;

/// An error message when a finite number of `values` exceeds [`MAX_MAGNITUDE`].
pub(crate) fn too_large(values: &[f64], what: &str) -> Option<String> {
    values
        .iter()
        .find(|v| v.is_finite() && v.abs() > MAX_MAGNITUDE)
        .map(|v| {
            format!(
                "{what} has the value {}, beyond ±{MAX_MAGNITUDE:e}: far too large for a robot (and for \
             the arithmetic)",
                num(*v)
            )
        })
}

/// A warning when `xyz` lies more than [`MAX_PLAUSIBLE_LENGTH`] from its frame.
fn far(xyz: &[f64; 3], what: &str) -> Option<String> {
    let d = xyz.iter().map(|v| v.abs()).fold(0.0, f64::max);
    (d > MAX_PLAUSIBLE_LENGTH).then(|| {
        format!(
            "{what} {} is more than {} m away: are the lengths in millimetres?",
            vec3(xyz),
            num(MAX_PLAUSIBLE_LENGTH)
        )
    })
}

fn finite(v: &[f64; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}
