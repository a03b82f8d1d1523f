//! The identified robot as a dyngen YAML description (inline form), which `cargo xtask gen`
//! and `compile_robot` generate from like any other.
//!
//! The description is the model as dyngen sees it: one link per moving body (links welded by
//! fixed or locked joints are already merged, which is exactly what was identified), joint
//! frames relative to the parent moving joint, the end-effector frame, gravity, limits, and
//! the joint-level columns with their identified values. Inertias are written about the centre
//! of mass in the body frame's axes. Numbers are written in Rust's shortest round-trip form, so
//! loading the file gives back the same parameters to rounding of the inertia shift.

use dyngen_codegen::model::{Body, Inertia, JointKind, JointTerms, Model, ModelError, Pose};
use dyngen_runtime::PARAMETERS_PER_BODY;
use nalgebra::{Matrix3, Vector3};
use std::fmt::Write as _;

/// The body of ten standard parameters `[m, m·c, I_O]` (the inverse of
/// [`Inertia::parameters`]): its centre of mass, and its inertia about it (symmetrised).
pub(crate) fn inertia_of(p: &[f64]) -> Inertia {
    let m = p[0];
    let c = if m > 0.0 {
        Vector3::new(p[1], p[2], p[3]) / m
    } else {
        Vector3::zeros()
    };
    let origin = Matrix3::new(p[4], p[5], p[7], p[5], p[6], p[8], p[7], p[8], p[9]);
    let inertia_com = origin - (Matrix3::identity() * c.dot(&c) - c * c.transpose()) * m;
    Inertia {
        mass: m,
        com: c,
        inertia_com: (inertia_com + inertia_com.transpose()) * 0.5,
    }
}

/// `model` with parameters θ (as [`Model::parameters`]): bodies and joint-level values; an
/// error when θ is not a physically valid robot.
pub(crate) fn with_parameters(model: &Model, theta: &[f64]) -> Result<Model, ModelError> {
    let bodies = model
        .bodies()
        .iter()
        .enumerate()
        .map(|(b, body)| {
            let p = &theta[PARAMETERS_PER_BODY * b..PARAMETERS_PER_BODY * (b + 1)];
            Body {
                name: body.name.clone(),
                inertia: inertia_of(p),
            }
        })
        .collect();
    let terms = JointTerms {
        values: model.joint_term_values_from(theta),
        ..model.joint_terms().clone()
    };
    model.clone().with_bodies(bodies)?.with_joint_terms(terms)
}

/// Roll, pitch, yaw of a rotation `R = Rz(yaw) Ry(pitch) Rx(roll)` (URDF's convention).
pub(crate) fn rpy(r: &Matrix3<f64>) -> [f64; 3] {
    let sp = (-r[(2, 0)]).clamp(-1.0, 1.0);
    if sp.abs() < 1.0 - 1e-12 {
        [r[(2, 1)].atan2(r[(2, 2)]), sp.asin(), r[(1, 0)].atan2(r[(0, 0)])]
    } else {
        // Gimbal lock: roll and yaw share one axis; put it all in yaw.
        [0.0, sp.asin(), (-r[(0, 1)]).atan2(r[(1, 1)])]
    }
}

fn triple(v: [f64; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

fn origin(p: &Pose) -> String {
    let t = p.translation;
    format!(
        "{{ xyz: {}, rpy: {} }}",
        triple([t.x, t.y, t.z]),
        triple(rpy(&p.rotation))
    )
}

/// A name for the fixed base link that no body uses.
fn base_link_name(model: &Model) -> String {
    let mut name = "base_link".to_string();
    while model.bodies().iter().any(|b| b.name == name) {
        name.push('_');
    }
    name
}

/// The YAML text of `model`; `comment` lines go at the top (after `# `).
pub fn to_yaml(model: &Model, comment: &[String]) -> String {
    let mut y = String::new();
    for line in comment {
        let _ = writeln!(y, "# {line}");
    }
    let g = model.gravity();
    let _ = writeln!(y, "name: {}", model.name());
    let _ = writeln!(y, "gravity: {}", triple([g.x, g.y, g.z]));
    let ee = &model.end_effector();
    let _ = writeln!(
        y,
        "end_effector: {{ name: {}, link: {}, xyz: {}, rpy: {} }}",
        ee.name,
        model.bodies()[model.end_effector_body()].name,
        triple(ee.placement.translation.into()),
        triple(rpy(&ee.placement.rotation))
    );
    let terms = &model.joint_terms();
    if !terms.kinds.is_empty() {
        let kinds: Vec<&str> = terms.kinds.iter().map(|k| k.keyword()).collect();
        let _ = writeln!(y, "joint_parameters:\n  columns: [{}]", kinds.join(", "));
        if let Some(eps) = terms.coulomb_smoothing {
            let _ = writeln!(y, "  coulomb_smoothing: {eps}");
        }
    }
    let base = base_link_name(model);
    let _ = writeln!(y, "links:\n  - name: {base}");
    for body in model.bodies() {
        let i = &body.inertia;
        let t = &i.inertia_com;
        let _ = writeln!(
            y,
            "  - name: {}\n    inertial:\n      mass: {}\n      origin: {{ xyz: {} }}\n      inertia: {{ ixx: {}, ixy: {}, ixz: {}, iyy: {}, iyz: {}, izz: {} }}",
            body.name,
            i.mass,
            triple(i.com.into()),
            t[(0, 0)],
            t[(0, 1)],
            t[(0, 2)],
            t[(1, 1)],
            t[(1, 2)],
            t[(2, 2)]
        );
    }
    let _ = writeln!(y, "joints:");
    for (j, joint) in model.joints().iter().enumerate() {
        let parent = joint
            .parent
            .map_or(base.as_str(), |p| model.bodies()[p].name.as_str());
        let kind = match (joint.kind, joint.limits) {
            (JointKind::Revolute, Some(_)) => "revolute",
            (JointKind::Revolute, None) => "continuous",
            (JointKind::Prismatic, _) => "prismatic",
        };
        let _ = writeln!(
            y,
            "  - name: {}\n    type: {kind}\n    parent: {parent}\n    child: {}\n    origin: {}\n    axis: {}",
            joint.name,
            model.bodies()[j].name,
            origin(&joint.origin),
            triple(joint.axis.into())
        );
        if let Some(l) = joint.limits {
            let _ = writeln!(
                y,
                "    limit: {{ lower: {}, upper: {}, velocity: {}, effort: {} }}",
                l.lower, l.upper, l.velocity, l.effort
            );
        }
        if !terms.kinds.is_empty() {
            let v = terms.value(j);
            let fields: Vec<String> = terms
                .kinds
                .iter()
                .map(|&k| format!("{}: {}", k.keyword(), v.get(k)))
                .collect();
            let _ = writeln!(y, "    dynamics: {{ {} }}", fields.join(", "));
        }
    }
    y
}
