//! [`Model`] → [`urdf_rs::Robot`]: any description (YAML included), after fixed and locked
//! joints were welded away, as a URDF that urdf-viz, RViz or `k` can read.
//!
//! What is written, and why it loads back as the same model, is in [`to_urdf_rs`]'s docs.
//! Exactness rests on three things: rotations are written as the rpy that [`from_xyz_rpy`]
//! turns back into the same matrix bit for bit (searched near the analytic angles), the
//! loader keeps an axis that is a unit vector to rounding as written, and welding a massless
//! link (the end-effector's) leaves a body's numbers unchanged.

use super::assemble::DEFAULT_GRAVITY;
use super::choices::{Choices, FrameSelection, FrameSpec};
use super::error::vec3;
use super::joint_parameters::{JointParameters, JointValues};
use super::load::from_urdf_rs;
use crate::model::{
    exact_sin_cos, from_xyz_rpy, Inertia, JointKind, JointTermValues, JointTerms, Model, Pose,
};
use nalgebra::{Matrix3, Vector3};
use std::collections::HashSet;

/// A model as a URDF, with what the URDF alone cannot say.
#[derive(Clone, Debug)]
pub struct UrdfExport {
    /// The robot: write it with [`urdf_rs::write_to_string`].
    pub robot: urdf_rs::Robot,
    /// What loading `robot` back needs to give the same model (gravity, the end-effector, the
    /// named frames, a floating base, joint-level parameters), as a YAML wrapper would write
    /// them; [`Choices::default`] when the URDF alone suffices.
    pub choices: Choices,
    /// What differs when the URDF is read without [`UrdfExport::choices`], or by tools other
    /// than dyngen (gravity, the order of the joints), one line each.
    pub warnings: Vec<String>,
    /// The model's joint-level parameters: viscous and Coulomb friction are in the URDF
    /// (`<dynamics damping friction>`); the chosen columns, the Coulomb smoothing, armature and
    /// offset have no URDF element and go into the YAML wrapper's `joint_parameters`.
    pub joint_terms: JointTerms,
}

impl UrdfExport {
    /// A dyngen YAML wrapper that loads the URDF written to `urdf_path` (relative to the
    /// wrapper) as the exported model, gravity and end-effector included.
    pub fn yaml_wrapper(&self, urdf_path: &str) -> String {
        let mut s = format!(
            "urdf: {}\nname: {}\n",
            yaml_str(urdf_path),
            yaml_str(&self.robot.name)
        );
        if let Some(ee) = &self.choices.end_effector {
            s.push_str(&format!("end_effector: {}\n", frame_yaml(ee)));
        }
        if let FrameSelection::Listed(frames) = &self.choices.frames {
            s.push_str("frames:\n");
            for frame in frames {
                s.push_str(&format!("  - {}\n", frame_yaml(frame)));
            }
        }
        if let Some(g) = &self.choices.gravity {
            s.push_str(&format!("gravity: {}\n", yaml_vec(g)));
        }
        if self.choices.floating_base {
            s.push_str("floating_base: true\n");
        }
        s.push_str(&self.joint_parameters_yaml());
        s
    }

    /// Whether loading the URDF alone gives a different model: a YAML wrapper is needed.
    pub fn needs_wrapper(&self) -> bool {
        self.choices != Choices::default()
    }

    /// `joint_parameters:` with what URDF cannot say (empty without joint-level columns).
    fn joint_parameters_yaml(&self) -> String {
        let terms = &self.joint_terms;
        if terms.kinds.is_empty() {
            return String::new();
        }
        let kinds: Vec<&str> = terms.kinds.iter().map(|k| k.keyword()).collect();
        let mut s = format!("joint_parameters:\n  columns: [{}]\n", kinds.join(", "));
        if let Some(eps) = terms.coulomb_smoothing {
            s.push_str(&format!("  coulomb_smoothing: {eps:?}\n"));
        }
        let names = self
            .robot
            .joints
            .iter()
            .filter(|j| j.joint_type != urdf_rs::JointType::Fixed);
        let rows: Vec<String> = names
            .zip(0..terms.values.len())
            .filter_map(|(joint, j)| {
                let v = terms.value(j);
                let mut fields = Vec::new();
                if v.armature != 0.0 {
                    fields.push(format!("armature: {:?}", v.armature));
                }
                if v.offset != 0.0 {
                    fields.push(format!("offset: {:?}", v.offset));
                }
                (!fields.is_empty())
                    .then(|| format!("    {}: {{ {} }}\n", yaml_str(&joint.name), fields.join(", ")))
            })
            .collect();
        if !rows.is_empty() {
            s.push_str("  joints:\n");
            s.extend(rows);
        }
        s
    }
}

/// `<dynamics damping friction>`: viscous and Coulomb friction, as URDF readers (Gazebo) take
/// them; `None` when both are 0.
fn urdf_dynamics(v: &JointTermValues) -> Option<urdf_rs::Dynamics> {
    (v.viscous != 0.0 || v.coulomb != 0.0).then_some(urdf_rs::Dynamics {
        damping: v.viscous,
        friction: v.coulomb,
    })
}

/// A model that cannot be written as a URDF that loads back as the same model.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("cannot write model '{model}' as URDF: {message}")]
pub struct ExportError {
    /// The model's name.
    pub model: String,
    /// What URDF cannot say, as a sentence fragment.
    pub message: String,
}

/// Writes `model` as a URDF: after fixed and locked joints were welded away, for urdf-viz,
/// RViz, `k` or any URDF reader.
///
/// What is written:
/// - a base link (`base_link`, the ROS name, or `base_link_1`, ... if a body has that name),
///   massless: what was welded to the base does not move and is not in the model;
/// - per moving joint, the joint (revolute, continuous when it has no limits, or prismatic)
///   hanging from its parent joint's body link (or the base link), with its origin, axis and
///   limits, and its body as the child link: the body's inertia about the centre of mass in
///   body axes (`<inertial>` origin at the centre of mass, rpy zero);
/// - the end-effector frame as a massless link of the frame's name on a fixed joint
///   (`<frame>_joint`), unless a body already has that name (then the frame needs an
///   `end_effector` choice naming the body and the offset);
/// - visuals for viewers (dyngen's readers skip them): a sphere at every joint and at the
///   end-effector, and a rod from every link's frame to each frame it carries.
///
/// Returns the robot with the choices that load it back as `model` and warnings about what
/// the URDF alone does not say. The choices are the default when the URDF alone suffices:
/// default gravity, no named frames or joint-level columns, and an end-effector that the
/// loader's default rule picks (the leaf at the end of the longest chain). Loaded back with
/// them, the model is the same, with the same parameters
/// and byte-identical generated code, whenever every rotation in it is one URDF rpy rotation
/// (true of every model loaded from a description whose moving joints hang from moving links
/// or the base), and equal to rounding otherwise; the inertia tensor's lower triangle is
/// rebuilt from the upper one (the parameters use only the upper). Joints not in depth-first
/// order come back in depth-first order (a warning lists it), as every URDF reader orders
/// them. URDF has no gravity: a model whose gravity is not
/// `[0, 0, -9.81]` is still written (a robot on a wall should be viewable), with a warning, and
/// the gravity in [`UrdfExport::choices`]. Fails when no URDF loads back as the model: two bodies of one
/// name, a prismatic joint without limits (URDF requires them).
///
/// ```
/// use dyngen_model::description::{from_urdf_rs, load, to_urdf_rs};
/// let arm7 = load(std::path::Path::new("../robots/arm7.yaml")).unwrap().model;
/// let export = to_urdf_rs(&arm7).unwrap();
/// let text = dyngen_model::urdf_rs::write_to_string(&export.robot).unwrap();
/// assert!(text.contains(r#"<joint name="flange_joint" type="fixed">"#));
/// let back = from_urdf_rs(&export.robot, &export.choices).unwrap().model;
/// assert_eq!(back, arm7);
/// ```
pub fn to_urdf_rs(model: &Model) -> Result<UrdfExport, ExportError> {
    let fail = |message: String| ExportError {
        model: model.name().to_owned(),
        message,
    };
    let mut link_names = HashSet::new();
    for body in model.bodies() {
        if !link_names.insert(body.name.as_str()) {
            return Err(fail(format!("two bodies are named '{}'", body.name)));
        }
    }
    for joint in model.joints() {
        if joint.kind == JointKind::Prismatic && joint.limits.is_none() {
            let msg = format!(
                "joint '{}' is prismatic without limits, which URDF cannot express",
                joint.name
            );
            return Err(fail(msg));
        }
    }

    let ee = model.end_effector();
    let ee_body = &model.bodies()[model.end_effector_body()].name;
    let ee_link = !link_names.contains(ee.name.as_str());
    // A floating base is a link of its own with its inertia; a fixed one, a massless link.
    let floating = model.floating_base();
    let base = match floating {
        Some(body) if !link_names.contains(body.name.as_str()) && body.name != ee.name => body.name.clone(),
        Some(body) => {
            return Err(fail(format!(
                "the base body and another link are both named '{}'",
                body.name
            )))
        }
        None => unique("base_link", |n| link_names.contains(n) || n == ee.name),
    };
    let parent_link = |parent: Option<usize>| parent.map_or(base.clone(), |p| model.bodies()[p].name.clone());

    let mut links = vec![link(&base, floating.map(|b| &b.inertia))];
    let mut joints = Vec::new();
    for (j, (joint, body)) in model.joints().iter().zip(model.bodies()).enumerate() {
        links.push(link(&body.name, Some(&body.inertia)));
        let joint_type = match (joint.kind, joint.limits) {
            (JointKind::Revolute, Some(_)) => urdf_rs::JointType::Revolute,
            (JointKind::Revolute, None) => urdf_rs::JointType::Continuous,
            (JointKind::Prismatic, _) => urdf_rs::JointType::Prismatic,
        };
        let limit = joint
            .limits
            .map_or_else(urdf_rs::JointLimit::default, |l| urdf_rs::JointLimit {
                lower: l.lower,
                upper: l.upper,
                effort: l.effort,
                velocity: l.velocity,
                ..urdf_rs::JointLimit::default()
            });
        joints.push(urdf_rs::Joint {
            name: joint.name.clone(),
            joint_type,
            origin: pose(&joint.origin),
            parent: urdf_rs::LinkName {
                link: parent_link(joint.parent),
            },
            child: urdf_rs::LinkName {
                link: body.name.clone(),
            },
            axis: urdf_rs::Axis {
                xyz: urdf_rs::Vec3([joint.axis.x, joint.axis.y, joint.axis.z]),
            },
            limit,
            calibration: None,
            dynamics: urdf_dynamics(&model.joint_terms().value(j)),
            // Mimic joints stay mimic joints (their master is never one: chains are resolved).
            mimic: model.mimics()[j].map(|m| urdf_rs::Mimic {
                joint: model.joints()[m.master].name.clone(),
                multiplier: Some(m.multiplier),
                offset: Some(m.offset),
            }),
            safety_controller: None,
        });
    }
    let spec = if ee_link {
        links.push(link(&ee.name, None));
        let joint_names: HashSet<&str> = model.joints().iter().map(|j| j.name.as_str()).collect();
        let name = unique(&format!("{}_joint", ee.name), |n| joint_names.contains(n));
        joints.push(urdf_rs::Joint {
            name,
            joint_type: urdf_rs::JointType::Fixed,
            origin: pose(&ee.placement),
            parent: urdf_rs::LinkName {
                link: ee_body.clone(),
            },
            child: urdf_rs::LinkName {
                link: ee.name.clone(),
            },
            axis: urdf_rs::Axis::default(),
            limit: urdf_rs::JointLimit::default(),
            calibration: None,
            dynamics: None,
            mimic: None,
            safety_controller: None,
        });
        FrameSpec::link(ee.name.clone())
    } else {
        body_frame_spec(model, ee, &base)
    };
    stick_figure(model, &mut links);
    let robot = urdf_rs::Robot {
        name: model.name().to_owned(),
        version: None,
        links,
        joints,
        materials: Vec::new(),
    };

    let gravity: [f64; 3] = model.gravity().into();
    let named: Vec<FrameSpec> = model.frames()[1..]
        .iter()
        .map(|f| body_frame_spec(model, f, &base))
        .collect();
    let mut choices = Choices {
        gravity: (gravity != DEFAULT_GRAVITY).then_some(gravity),
        frames: match named.is_empty() {
            true => FrameSelection::EndEffector,
            false => FrameSelection::Listed(named),
        },
        ..Choices::default()
    };
    let mut warnings = Vec::new();
    if floating.is_some() {
        choices.floating_base = true;
        warnings.push(format!(
            "the base '{base}' floats and URDF cannot say so: load the URDF with a floating base \
             (a YAML wrapper's `floating_base: true`, `Choices::floating_base`, `--floating-base`)"
        ));
    }
    if let Some(g) = choices.gravity {
        warnings.push(format!(
            "gravity {} is not the default {} and URDF cannot say so: load the URDF with this \
             gravity (a YAML wrapper's `gravity`, or `Choices::gravity`)",
            vec3(&g),
            vec3(&DEFAULT_GRAVITY)
        ));
    }

    // The loader is the judge of what its default rule picks and of the joint order.
    let plain = from_urdf_rs(&robot, &choices)
        .map(|l| l.model)
        .map_err(|e| fail(format!("the URDF does not load back: {e}")))?;
    let same_frame = plain.end_effector().name == ee.name
        && plain.joints()[plain.end_effector_body()].name == model.joints()[model.end_effector_body()].name
        && close(&plain.end_effector().placement, &ee.placement);
    if !same_frame {
        warnings.push(format!(
            "the end-effector '{}' is not the frame dyngen picks from the URDF alone (leaf link \
             '{}'): load it with the `end_effector` option ({})",
            ee.name,
            plain.end_effector().name,
            describe(&spec)
        ));
        choices.end_effector = Some(spec);
    }
    let order: Vec<&str> = plain.joints().iter().map(|j| j.name.as_str()).collect();
    if order.iter().zip(model.joints()).any(|(a, j)| *a != j.name) {
        warnings.push(format!(
            "the joints are not in depth-first order, which URDF readers use: read back, q is \
             ordered [{}]",
            order.join(", ")
        ));
    }
    choices.joint_parameters = joint_parameters(model);
    Ok(UrdfExport {
        robot,
        choices,
        warnings,
        joint_terms: model.joint_terms().clone(),
    })
}

/// The model's joint-level columns and the values URDF cannot hold (armature, offset; friction
/// is in `<dynamics>`), as a wrapper's `joint_parameters`; `None` without columns.
fn joint_parameters(model: &Model) -> Option<JointParameters> {
    let terms = model.joint_terms();
    if terms.kinds.is_empty() {
        return None;
    }
    let nonzero = |x: f64| (x != 0.0).then_some(x);
    let joints = model
        .joints()
        .iter()
        .enumerate()
        .map(|(j, joint)| {
            let v = terms.value(j);
            let values = JointValues {
                armature: nonzero(v.armature),
                offset: nonzero(v.offset),
                ..JointValues::default()
            };
            (joint.name.clone(), values)
        })
        .filter(|(_, v)| *v != JointValues::default())
        .collect();
    Some(JointParameters {
        columns: terms.kinds.clone(),
        coulomb_smoothing: terms.coulomb_smoothing,
        joints,
    })
}

/// A frame as YAML writes it, `{ link: l, name: n, xyz: [..], rpy: [..] }`.
fn frame_yaml(spec: &FrameSpec) -> String {
    let mut s = format!("{{ link: {}", yaml_str(&spec.link));
    if let Some(name) = &spec.name {
        s.push_str(&format!(", name: {}", yaml_str(name)));
    }
    if spec.xyz != [0.0; 3] || spec.rpy != [0.0; 3] {
        s.push_str(&format!(
            ", xyz: {}, rpy: {}",
            yaml_vec(&spec.xyz),
            yaml_vec(&spec.rpy)
        ));
    }
    s + " }"
}

/// A model frame as a frame of the exported URDF: on its body's link (`base`, the base link's
/// name, for a frame on a floating base body), at its placement there.
fn body_frame_spec(model: &Model, frame: &crate::model::Frame, base: &str) -> FrameSpec {
    let body = frame.parent.map_or(base, |p| model.bodies()[p].name.as_str());
    let p = pose(&frame.placement);
    FrameSpec {
        name: (frame.name != *body).then(|| frame.name.clone()),
        link: body.to_owned(),
        xyz: p.xyz.0,
        rpy: p.rpy.0,
    }
}

/// `link 'a1', xyz [0, 0, 0.1], rpy [0.3, 0, 0]`: an end-effector option in words.
fn describe(spec: &FrameSpec) -> String {
    let mut s = format!("link '{}'", spec.link);
    if let Some(name) = &spec.name {
        s.push_str(&format!(", name '{name}'"));
    }
    if spec.xyz != [0.0; 3] || spec.rpy != [0.0; 3] {
        s.push_str(&format!(", xyz {}, rpy {}", vec3(&spec.xyz), vec3(&spec.rpy)));
    }
    s
}

/// `base`, or `base_1`, `base_2`, ... : the first that is not `taken`.
fn unique(base: &str, taken: impl Fn(&str) -> bool) -> String {
    let mut name = base.to_owned();
    let mut k = 0;
    while taken(&name) {
        k += 1;
        name = format!("{base}_{k}");
    }
    name
}

/// A link with its inertia about the centre of mass in link axes, or massless.
fn link(name: &str, inertia: Option<&Inertia>) -> urdf_rs::Link {
    let inertial = match inertia {
        None => urdf_rs::Inertial::default(),
        Some(b) => {
            // The upper triangle: the ten standard parameters are made of it alone.
            let i = &b.inertia_com;
            urdf_rs::Inertial {
                origin: urdf_rs::Pose {
                    xyz: urdf_rs::Vec3([b.com.x, b.com.y, b.com.z]),
                    rpy: urdf_rs::Vec3([0.0; 3]),
                },
                mass: urdf_rs::Mass { value: b.mass },
                inertia: urdf_rs::Inertia {
                    ixx: i[(0, 0)],
                    ixy: i[(0, 1)],
                    ixz: i[(0, 2)],
                    iyy: i[(1, 1)],
                    iyz: i[(1, 2)],
                    izz: i[(2, 2)],
                },
            }
        }
    };
    urdf_rs::Link {
        name: name.to_owned(),
        inertial,
        visual: Vec::new(),
        collision: Vec::new(),
    }
}

/// Something for a viewer to show (dyngen's readers skip visuals): a sphere at each joint and
/// at the end-effector, and a rod from each link's frame to each frame it carries, all of one
/// thickness scaled to the robot. `links` are the base, the bodies, then the end-effector's.
fn stick_figure(model: &Model, links: &mut [urdf_rs::Link]) {
    let ee = model.end_effector();
    // Per link, the points of the frames it carries, in its own frame.
    let mut ends: Vec<Vec<Vector3<f64>>> = vec![Vec::new(); links.len()];
    for joint in model.joints() {
        ends[joint.parent.map_or(0, |p| p + 1)].push(joint.origin.translation);
    }
    ends[model.end_effector_body() + 1].push(ee.placement.translation);
    let longest = ends.iter().flatten().map(|p| p.norm()).fold(0.0, f64::max);
    let radius = (longest / 40.0).max(0.002);
    let visual = |origin: urdf_rs::Pose, geometry: urdf_rs::Geometry| urdf_rs::Visual {
        name: None,
        origin,
        geometry,
        material: None,
    };
    let at_origin = || urdf_rs::Pose::default();
    for (k, (link, ends)) in links.iter_mut().zip(&ends).enumerate() {
        if k > 0 {
            let ball = if k <= model.joints().len() {
                2.0 * radius
            } else {
                1.5 * radius
            };
            link.visual
                .push(visual(at_origin(), urdf_rs::Geometry::Sphere { radius: ball }));
        }
        for p in ends {
            let length = p.norm();
            if length < 1e-9 {
                continue;
            }
            // A cylinder lies along z: turn z onto `p` (pitch from z, then yaw about z).
            let origin = urdf_rs::Pose {
                xyz: urdf_rs::Vec3((p / 2.0).into()),
                rpy: urdf_rs::Vec3([0.0, p.x.hypot(p.y).atan2(p.z), p.y.atan2(p.x)]),
            };
            link.visual
                .push(visual(origin, urdf_rs::Geometry::Cylinder { radius, length }));
        }
    }
}

/// A placement as URDF `xyz`/`rpy`.
fn pose(p: &Pose) -> urdf_rs::Pose {
    let t = &p.translation;
    urdf_rs::Pose {
        xyz: urdf_rs::Vec3([t.x, t.y, t.z]),
        // `+ 0.0` writes `-0` as `0`; both give the same rotation (`exact_sin_cos`).
        rpy: urdf_rs::Vec3(rpy(&p.rotation).map(|a| a + 0.0)),
    }
}

/// Roll, pitch, yaw of a rotation, chosen so that [`from_xyz_rpy`] gives back the same matrix
/// bit for bit whenever some rpy near the analytic one does (then the generated code of the
/// reloaded model is byte-identical); otherwise the analytic angles (exact to rounding).
fn rpy(r: &Matrix3<f64>) -> [f64; 3] {
    let guess = analytic_rpy(r);
    let rotation = |rpy: [f64; 3]| from_xyz_rpy([0.0; 3], rpy).rotation;
    if rotation(guess) == *r {
        return guess;
    }
    // The analytic angles are within a few ulps of any exact preimage: try their neighbours.
    const STEPS: i64 = 4;
    let near = |x: f64| (-STEPS..=STEPS).map(move |k| ulps(x, k));
    for roll in near(guess[0]) {
        for pitch in near(guess[1]) {
            for yaw in near(guess[2]) {
                if rotation([roll, pitch, yaw]) == *r {
                    return [roll, pitch, yaw];
                }
            }
        }
    }
    guess
}

/// `R = Rz(yaw) Ry(pitch) Rx(roll)` solved for the angles, pitch in [-π/2, π/2]; at gimbal
/// lock (pitch ±π/2) roll is 0. Quarter turns come out exactly as `exact_sin_cos` takes them.
fn analytic_rpy(r: &Matrix3<f64>) -> [f64; 3] {
    let sp = (-r[(2, 0)]).clamp(-1.0, 1.0);
    let cp = r[(0, 0)].hypot(r[(1, 0)]);
    let pitch = sp.atan2(cp);
    let (_, cos_pitch) = exact_sin_cos(pitch);
    if cos_pitch == 0.0 || cp < 1e-12 {
        // Only yaw ∓ roll is defined: take roll = 0.
        let yaw = (-r[(0, 1)]).atan2(r[(1, 1)]);
        return [0.0, pitch, yaw];
    }
    [r[(2, 1)].atan2(r[(2, 2)]), pitch, r[(1, 0)].atan2(r[(0, 0)])]
}

/// `x` moved by `k` units in the last place (`k` may be negative).
fn ulps(x: f64, k: i64) -> f64 {
    if !x.is_finite() || k == 0 {
        return x;
    }
    let mut y = x;
    for _ in 0..k.unsigned_abs() {
        y = if k > 0 { y.next_up() } else { y.next_down() };
    }
    y
}

fn close(a: &Pose, b: &Pose) -> bool {
    (a.rotation - b.rotation).amax() <= 1e-12 && (a.translation - b.translation).amax() <= 1e-12
}

/// A YAML scalar that reads back as `s`: plain when safe, else double-quoted.
fn yaml_str(s: &str) -> String {
    let plain = !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | '/'))
        && s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_' || c == '.' || c == '/')
        // Words YAML 1.1 readers take for booleans or null.
        && !["true", "false", "yes", "no", "on", "off", "null", "y", "n"]
            .contains(&s.to_ascii_lowercase().as_str());
    if plain {
        s.to_owned()
    } else {
        format!("{s:?}")
    }
}

/// `[x, y, z]` with every digit (`{:?}` is the shortest form that reads back exactly).
fn yaml_vec(v: &[f64; 3]) -> String {
    let v = v.map(|x| x + 0.0); // `-0.0` → `0.0`
    format!("[{:?}, {:?}, {:?}]", v[0], v[1], v[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rotation(rpy: [f64; 3]) -> Matrix3<f64> {
        from_xyz_rpy([0.0; 3], rpy).rotation
    }

    #[test]
    fn rpy_gives_back_the_matrix_bit_for_bit() {
        let q = std::f64::consts::FRAC_PI_2;
        let mut angles = vec![[0.0; 3], [q, 0.0, 0.0], [0.0, -q, 0.0], [2.0 * q, q, -q]];
        // General angles on a grid of the canonical ranges (pitch strictly inside ±π/2): outside
        // them the analytic angles are another branch, exact to rounding only.
        for i in 0..7 {
            for j in 0..5 {
                for k in 0..7 {
                    // n of `of` steps across (-half, half), ends excluded.
                    let f =
                        |n: i32, of: i32, half: f64| half * 0.95 * (2.0 * f64::from(n) / f64::from(of) - 1.0);
                    angles.push([f(i, 6, 2.0 * q), f(j, 4, q), f(k, 6, 2.0 * q) + 0.01]);
                }
            }
        }
        for a in angles {
            let r = rotation(a);
            assert_eq!(rotation(rpy(&r)), r, "rpy {a:?}");
        }
    }

    #[test]
    fn yaml_strings_are_quoted_unless_plain_is_safe() {
        assert_eq!(yaml_str("panda_link7"), "panda_link7");
        assert_eq!(yaml_str("../urdf/arm.urdf"), "../urdf/arm.urdf");
        for quoted in ["yes", "No", "null", "7dof", "my robot", "a:b", ""] {
            assert_eq!(yaml_str(quoted), format!("{quoted:?}"));
        }
        assert_eq!(yaml_vec(&[-0.0, 1e-20, -9.81]), "[0.0, 1e-20, -9.81]");
    }

    #[test]
    fn gimbal_lock_gives_the_rotation_to_rounding() {
        // Pitch a quarter turn: only yaw - roll is defined.
        let r = rotation([0.4, std::f64::consts::FRAC_PI_2, 1.1]);
        let back = rpy(&r);
        assert_eq!(back[0], 0.0);
        assert!((rotation(back) - r).amax() < 1e-15, "{back:?}");
    }
}
