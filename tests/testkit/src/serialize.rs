//! A model written back as dyngen YAML (inline form) and as URDF text, for round-trip tests:
//! every joint becomes a joint to a link of its own, every body that link's inertial.

use dyngen_codegen::model::{JointKind, Model, Pose};
use nalgebra::Matrix3;

/// Roll, pitch, yaw of a rotation `R = Rz(yaw) Ry(pitch) Rx(roll)` (URDF convention).
pub fn rpy(r: &Matrix3<f64>) -> [f64; 3] {
    let pitch = (-r[(2, 0)]).clamp(-1.0, 1.0).asin();
    if r[(2, 0)].abs() < 1.0 - 1e-12 {
        [r[(2, 1)].atan2(r[(2, 2)]), pitch, r[(1, 0)].atan2(r[(0, 0)])]
    } else {
        // Gimbal lock: only roll ± yaw is defined; put it all in yaw.
        [0.0, pitch, (-r[(0, 1)]).atan2(r[(1, 1)])]
    }
}

fn link_of(model: &Model, joint: Option<usize>) -> String {
    match joint {
        None => "base".into(),
        Some(j) => model.bodies()[j].name.clone(),
    }
}

fn kind(model: &Model, j: usize) -> &'static str {
    match (model.joints()[j].kind, &model.joints()[j].limits) {
        (JointKind::Prismatic, _) => "prismatic",
        (JointKind::Revolute, Some(_)) => "revolute",
        (JointKind::Revolute, None) => "continuous",
    }
}

fn list(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(", ")
}

fn spaced(v: &[f64]) -> String {
    v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(" ")
}

fn pose_parts(p: &Pose) -> ([f64; 3], [f64; 3]) {
    (p.translation.into(), rpy(&p.rotation))
}

/// The model as inline dyngen YAML.
pub fn to_yaml(model: &Model) -> String {
    let mut s = format!(
        "name: {}\ngravity: [{}]\n",
        model.name(),
        list(model.gravity().as_slice())
    );
    let ee = &model.end_effector();
    let (xyz, r) = pose_parts(&ee.placement);
    s += &format!(
        "end_effector: {{ name: {}, link: {}, xyz: [{}], rpy: [{}] }}\nlinks:\n  - name: base\n",
        ee.name,
        model.bodies()[model.end_effector_body()].name,
        list(&xyz),
        list(&r)
    );
    for b in model.bodies() {
        let i = &b.inertia;
        let m = &i.inertia_com;
        s += &format!(
            "  - name: {}\n    inertial:\n      mass: {:?}\n      origin: {{ xyz: [{}], rpy: [0, 0, 0] }}\n      \
             inertia: {{ ixx: {:?}, ixy: {:?}, ixz: {:?}, iyy: {:?}, iyz: {:?}, izz: {:?} }}\n",
            b.name,
            i.mass,
            list(i.com.as_slice()),
            m[(0, 0)],
            m[(0, 1)],
            m[(0, 2)],
            m[(1, 1)],
            m[(1, 2)],
            m[(2, 2)]
        );
    }
    s += "joints:\n";
    for (j, joint) in model.joints().iter().enumerate() {
        let (xyz, r) = pose_parts(&joint.origin);
        s += &format!(
            "  - name: {}\n    type: {}\n    parent: {}\n    child: {}\n    origin: {{ xyz: [{}], rpy: [{}] }}\n    axis: [{}]\n",
            joint.name,
            kind(model, j),
            link_of(model, joint.parent),
            model.bodies()[j].name,
            list(&xyz),
            list(&r),
            list(joint.axis.as_slice())
        );
        if let Some(l) = &joint.limits {
            s += &format!(
                "    limit: {{ lower: {:?}, upper: {:?}, velocity: {:?}, effort: {:?} }}\n",
                l.lower, l.upper, l.velocity, l.effort
            );
        }
    }
    s
}

/// The model as URDF. The end-effector frame is a fixed joint to a massless link `tool_link`
/// named after the frame; load it with `end_effector = <frame name>`.
pub fn to_urdf(model: &Model) -> String {
    let mut s = format!(
        "<?xml version=\"1.0\"?>\n<robot name=\"{}\">\n  <link name=\"base\"/>\n",
        model.name()
    );
    for b in model.bodies() {
        let i = &b.inertia;
        let m = &i.inertia_com;
        s += &format!(
            "  <link name=\"{}\">\n    <inertial>\n      <origin xyz=\"{}\" rpy=\"0 0 0\"/>\n      \
             <mass value=\"{:?}\"/>\n      <inertia ixx=\"{:?}\" ixy=\"{:?}\" ixz=\"{:?}\" iyy=\"{:?}\" \
             iyz=\"{:?}\" izz=\"{:?}\"/>\n    </inertial>\n  </link>\n",
            b.name,
            spaced(i.com.as_slice()),
            i.mass,
            m[(0, 0)],
            m[(0, 1)],
            m[(0, 2)],
            m[(1, 1)],
            m[(1, 2)],
            m[(2, 2)]
        );
    }
    for (j, joint) in model.joints().iter().enumerate() {
        let (xyz, r) = pose_parts(&joint.origin);
        s += &format!(
            "  <joint name=\"{}\" type=\"{}\">\n    <parent link=\"{}\"/>\n    <child link=\"{}\"/>\n    \
             <origin xyz=\"{}\" rpy=\"{}\"/>\n    <axis xyz=\"{}\"/>\n",
            joint.name,
            kind(model, j),
            link_of(model, joint.parent),
            model.bodies()[j].name,
            spaced(&xyz),
            spaced(&r),
            spaced(joint.axis.as_slice())
        );
        if let Some(l) = &joint.limits {
            s += &format!(
                "    <limit lower=\"{:?}\" upper=\"{:?}\" velocity=\"{:?}\" effort=\"{:?}\"/>\n",
                l.lower, l.upper, l.velocity, l.effort
            );
        }
        s += "  </joint>\n";
    }
    let ee = &model.end_effector();
    let (xyz, r) = pose_parts(&ee.placement);
    s += &format!(
        "  <link name=\"{0}\"/>\n  <joint name=\"{0}_fixed\" type=\"fixed\">\n    <parent link=\"{1}\"/>\n    \
         <child link=\"{0}\"/>\n    <origin xyz=\"{2}\" rpy=\"{3}\"/>\n  </joint>\n</robot>\n",
        ee.name,
        model.bodies()[model.end_effector_body()].name,
        spaced(&xyz),
        spaced(&r)
    );
    s
}
