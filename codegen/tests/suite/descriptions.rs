//! Robot descriptions load to the right models.
//!
//! Panda and UR5 are compared with the model Pinocchio 4.1 built from the same URDFs
//! (`tests/fixtures/*.json`, made by `tools/fixtures.py`): joint order, placements,
//! axes, the merged inertial parameters (fixed joints and locked fingers) and the end-effector
//! frame. The rest checks the rules that those two robots do not exercise: branching trees,
//! YAML and URDF giving the same model, composed fixed placements, defaults.

use dyngen_codegen::description::{self, Choices, FrameSpec, Loaded};
use dyngen_codegen::model::{from_xyz_rpy, JointKind, Model, Pose};
use nalgebra::{Matrix3, Vector3};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn repo(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(rel)
}

fn load(rel: &str) -> Loaded {
    description::load(&repo(rel)).unwrap_or_else(|e| panic!("{e}"))
}

fn fixture(robot: &str) -> Value {
    let text =
        std::fs::read_to_string(repo(&format!("codegen/tests/fixtures/{robot}.json"))).expect("fixture file");
    serde_json::from_str(&text).expect("fixture json")
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

/// dyngen's robots have exact quarter turns (the Panda's URDF writes π/2 to the last bit, which
/// `from_xyz_rpy` takes as exact; `robots/ur5.yaml` snaps the UR5's 1.57079632679); Pinocchio
/// computes `cos(π/2)` as 6e-17 (Panda) or 4.9e-12 (UR5). Snap the reference the same way,
/// then compare tightly.
fn snap(x: f64) -> f64 {
    for exact in [-1.0, 0.0, 1.0] {
        if (x - exact).abs() < 1e-9 {
            return exact;
        }
    }
    x
}

fn pose(v: &Value) -> Pose {
    let rows: Vec<Vec<f64>> = v["rotation"]
        .as_array()
        .expect("rows")
        .iter()
        .map(numbers)
        .collect();
    let t = numbers(&v["translation"]);
    Pose {
        rotation: Matrix3::from_fn(|i, j| snap(rows[i][j])),
        translation: Vector3::new(t[0], t[1], t[2]),
    }
}

fn assert_pose(what: &str, actual: &Pose, expected: &Pose) {
    let dr = (actual.rotation - expected.rotation).abs().max();
    let dt = (actual.translation - expected.translation).abs().max();
    assert!(
        dr <= 1e-12 && dt <= 1e-12,
        "{what}: rotation off by {dr:e}, translation by {dt:e}\n{actual:?}\n{expected:?}"
    );
}

/// Relative agreement to 1e-9 (with a floor far below any parameter of a real robot).
fn assert_params(robot: &str, model: &Model, expected: &[f64]) {
    let actual = model.parameters();
    assert_eq!(actual.len(), expected.len(), "{robot}: number of parameters");
    let names = model.parameter_names();
    for ((a, e), name) in actual.iter().zip(expected).zip(&names) {
        let tol = 1e-9 * a.abs().max(e.abs()) + 1e-15;
        assert!((a - e).abs() <= tol, "{robot}: {name} = {a:e}, reference {e:e}");
    }
}

/// Everything the fixture says about the model, except the states.
fn check_against_fixture(robot: &str, loaded: &Loaded) {
    let fx = fixture(robot);
    let model = &loaded.model;
    let names: Vec<&str> = fx["joint_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap())
        .collect();
    let ours: Vec<&str> = model.joints().iter().map(|j| j.name.as_str()).collect();
    assert_eq!(ours, names, "{robot}: joint order");
    let index = |name: &str| names.iter().position(|n| *n == name);

    for (joint, fj) in model.joints().iter().zip(fx["joints"].as_array().unwrap()) {
        let what = format!("{robot} joint '{}'", joint.name);
        assert_eq!(
            joint.parent,
            index(fj["parent"].as_str().unwrap()),
            "{what}: parent"
        );
        assert_pose(
            &format!("{what} placement"),
            &joint.origin,
            &pose(&fj["placement"]),
        );
        let axis = numbers(&fj["axis"]);
        assert!(
            (joint.axis - Vector3::new(axis[0], axis[1], axis[2])).abs().max() <= 1e-12,
            "{what}: axis"
        );
        assert_eq!(joint.kind, JointKind::Revolute, "{what}: kind");
        assert_eq!(
            joint.limits.is_none(),
            fj["continuous"].as_bool().unwrap(),
            "{what}: continuous"
        );
    }
    assert_params(robot, model, &numbers(&fx["pi"]));

    let ee = &model.end_effector();
    assert_eq!(ee.name, fx["ee_frame"].as_str().unwrap(), "{robot}: ee frame");
    assert_eq!(
        ee.parent,
        index(fx["ee_parent_joint"].as_str().unwrap()),
        "{robot}: ee parent"
    );
    assert_pose(
        &format!("{robot} ee placement"),
        &ee.placement,
        &pose(&fx["ee_placement_in_parent_joint"]),
    );
    assert_eq!(
        model.gravity(),
        Vector3::from_vec(numbers(&fx["gravity"])),
        "{robot}: gravity"
    );
    assert!(
        loaded.warnings.is_empty(),
        "{robot}: unexpected warnings {:?}",
        loaded.warnings
    );
}

#[test]
fn panda_matches_pinocchio() {
    let loaded = load("robots/panda.yaml");
    assert_eq!(loaded.model.name(), "panda");
    assert_eq!(loaded.model.dof(), 7);
    check_against_fixture("panda", &loaded);
    assert_eq!(
        loaded.sources,
        vec![repo("robots/panda.yaml"), repo("robots/urdf/panda.urdf")]
    );
}

/// The Panda with its `rpy` rounded to 4 decimals, loaded with `snap_angles: 1e-4`, against
/// Pinocchio's model of the same file with the same angles snapped (`panda_rounded.json`): the
/// quarter turns are exact again (notes, no warnings), the hand's yaw stays `-0.7854`.
#[test]
fn panda_rounded_snapped_matches_pinocchio() {
    let loaded = load("robots/panda_rounded.yaml");
    assert_eq!(loaded.model.name(), "panda_rounded");
    assert_eq!(loaded.model.dof(), 7);
    check_against_fixture("panda_rounded", &loaded);
    let snapped = loaded.notes.iter().filter(|n| n.contains("snapped to")).count();
    assert_eq!(snapped, 6, "{:#?}", loaded.notes);
    assert_eq!(
        loaded.sources,
        vec![
            repo("robots/panda_rounded.yaml"),
            repo("robots/urdf/panda_rounded.urdf")
        ]
    );
    // Same joint frames as the Panda (bit for bit), another end-effector placement.
    let panda = load("robots/panda.yaml").model;
    for (a, b) in loaded.model.joints().iter().zip(panda.joints()) {
        assert_eq!(a.origin.rotation, b.origin.rotation, "joint '{}'", a.name);
    }
    assert_ne!(
        loaded.model.end_effector().placement.rotation,
        panda.end_effector().placement.rotation
    );
}

#[test]
fn ur5_matches_pinocchio() {
    let loaded = load("robots/ur5.yaml");
    assert_eq!(loaded.model.name(), "ur5");
    assert_eq!(loaded.model.dof(), 6);
    check_against_fixture("ur5", &loaded);
    assert_eq!(
        loaded.sources,
        vec![repo("robots/ur5.yaml"), repo("robots/urdf/ur5_robot.urdf")]
    );
}

#[test]
fn panda_with_fingers_free_has_the_second_finger_mimic_the_first() {
    let text = std::fs::read_to_string(repo("robots/urdf/panda.urdf")).unwrap();
    let file = Path::new("robots/urdf/panda.urdf");
    let free = description::load_urdf_str(&text, file, &Choices::default()).unwrap();
    let m = &free.model;
    assert_eq!((m.dof(), m.joints().len(), m.parameter_count()), (8, 9, 90));
    let coordinates: Vec<&str> = (m.coordinate_joints().into_iter())
        .map(|k| m.joints()[k].name.as_str())
        .collect();
    assert_eq!(coordinates.last(), Some(&"panda_finger_joint1"));
    let finger2 = m
        .joints()
        .iter()
        .position(|j| j.name == "panda_finger_joint2")
        .unwrap();
    let mimic = m.mimics()[finger2].expect("finger 2 mimics finger 1");
    assert_eq!(m.joints()[mimic.master].name, "panda_finger_joint1");
    assert_eq!((mimic.multiplier, mimic.offset), (1.0, 0.0));
    // Locking only the mimic joint is accepted (finger 1 stays a ninth... eighth joint).
    let options = Choices {
        locked_joints: vec![("panda_finger_joint2".into(), 0.0)],
        ..Default::default()
    };
    let loaded = description::load_urdf_str(&text, file, &options).unwrap();
    assert_eq!(loaded.model.dof(), 8);
    assert!(
        loaded.warnings.iter().any(|w| w.contains("will not follow")),
        "{:?}",
        loaded.warnings
    );
}

#[test]
fn bare_urdf_picks_the_end_of_the_longest_chain_and_says_so() {
    let loaded = load("robots/urdf/ur5_robot.urdf");
    assert_eq!(loaded.model.dof(), 6);
    // ee_link and tool0 both end the 6-joint chain; ee_link comes first in the file.
    assert_eq!(loaded.model.end_effector().name, "ee_link");
    assert_eq!(loaded.model.end_effector_body(), 5);
    assert!(
        loaded
            .notes
            .iter()
            .any(|n| n.contains("no end-effector given") && n.contains("'ee_link'")),
        "{:?}",
        loaded.notes
    );
    assert_eq!(loaded.sources, vec![repo("robots/urdf/ur5_robot.urdf")]);
}

#[test]
fn arm7_is_a_realistic_seven_axis_arm() {
    let loaded = load("robots/arm7.yaml");
    let m = &loaded.model;
    assert!(loaded.warnings.is_empty(), "{:?}", loaded.warnings);
    assert_eq!(m.dof(), 7);
    assert!(m
        .joints()
        .iter()
        .all(|j| j.kind == JointKind::Revolute && j.limits.is_some()));
    let chain: Vec<Option<usize>> = m.joints().iter().map(|j| j.parent).collect();
    assert_eq!(
        chain,
        vec![None, Some(0), Some(1), Some(2), Some(3), Some(4), Some(5)]
    );
    let z_axes = m.joints().iter().filter(|j| j.axis == Vector3::z()).count();
    assert!(z_axes < 7, "not every axis may be z");
    assert!(
        m.joints().iter().any(|j| j.axis == -Vector3::y()),
        "iiwa axis 4 turns about -y"
    );
    // full inertia tensors: some products of inertia about the COM are non-zero
    let products = m
        .bodies()
        .iter()
        .filter(|b| {
            let i = b.inertia.inertia_com;
            i[(0, 1)] != 0.0 || i[(0, 2)] != 0.0 || i[(1, 2)] != 0.0
        })
        .count();
    assert!(products >= 3, "only {products} bodies have products of inertia");
    // non-zero offsets off the axis line (the iiwa links are not DH-shaped)
    assert!(m.joints().iter().any(|j| j.origin.translation.y != 0.0));
    let moving_mass: f64 = m.bodies().iter().map(|b| b.inertia.mass).sum();
    assert!(
        (15.0..30.0).contains(&moving_mass),
        "moving mass {moving_mass} kg"
    );
    assert_eq!(m.end_effector_body(), 6);
    assert!(m.end_effector().placement.translation.z > 0.0);
}

/// A two-armed robot on a turning torso, with a fixed sensor and a fixed-mounted second arm.
const TREE_URDF: &str = r#"<?xml version="1.0"?>
<robot name="twins">
  <link name="base"/>
  <link name="torso">
    <inertial><origin xyz="0 0 0.2"/><mass value="5"/>
      <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.05"/></inertial>
  </link>
  <link name="mount"/>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="l2"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="r1"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="r2"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="sensor"><inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <joint name="waist" type="continuous">
    <parent link="base"/><child link="torso"/><origin xyz="0 0 0.5"/><axis xyz="0 0 1"/>
  </joint>
  <joint name="left1" type="revolute">
    <parent link="torso"/><child link="l1"/><origin xyz="0 0.2 0.4" rpy="1.5707963267948966 0 0"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="10" velocity="1"/>
  </joint>
  <joint name="sensor_mount" type="fixed">
    <parent link="torso"/><child link="sensor"/><origin xyz="0.1 0 0.3"/>
  </joint>
  <joint name="right_mount" type="fixed">
    <parent link="torso"/><child link="mount"/><origin xyz="0 -0.2 0.4" rpy="0 0 3.141592653589793"/>
  </joint>
  <joint name="right1" type="revolute">
    <parent link="mount"/><child link="r1"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/>
  </joint>
  <joint name="left2" type="prismatic">
    <parent link="l1"/><child link="l2"/><origin xyz="0.3 0 0"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.2" effort="50" velocity="0.5"/>
  </joint>
  <joint name="right2" type="revolute">
    <parent link="r1"/><child link="r2"/><origin xyz="0.3 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="10" velocity="1"/>
  </joint>
</robot>
"#;

#[test]
fn branching_tree_gets_depth_first_order_and_right_parents() {
    let loaded = description::load_urdf_str(TREE_URDF, Path::new("twins.urdf"), &Choices::default())
        .unwrap_or_else(|e| panic!("{e}"));
    let m = &loaded.model;
    let names: Vec<&str> = m.joints().iter().map(|j| j.name.as_str()).collect();
    // depth-first, children in file order: waist's children are left1, (sensor), (mount → right1)
    assert_eq!(names, ["waist", "left1", "left2", "right1", "right2"]);
    let parents: Vec<Option<usize>> = m.joints().iter().map(|j| j.parent).collect();
    assert_eq!(parents, [None, Some(0), Some(1), Some(0), Some(3)]);
    assert_eq!(m.joints()[0].limits, None, "continuous joints have no limits");
    assert_eq!(m.joints()[2].kind, JointKind::Prismatic);

    // right1 hangs from torso through the fixed, turned mount: its origin is composed.
    let expected = from_xyz_rpy([0.0, -0.2, 0.4], [0.0, 0.0, std::f64::consts::PI])
        .compose(&from_xyz_rpy([0.0, 0.0, 0.1], [0.0, 0.0, 0.0]));
    assert_eq!(m.joints()[3].origin, expected);

    // The sensor is welded to the torso body: 5 kg at z 0.2 plus 0.5 kg at (0.1, 0, 0.3).
    let torso = &m.bodies()[0].inertia;
    assert!((torso.mass - 5.5).abs() < 1e-12);
    assert!((torso.com - Vector3::new(0.05 / 5.5, 0.0, (1.0 + 0.15) / 5.5)).norm() < 1e-12);

    // Two leaves end 2-joint chains (l2, r2): the first in depth-first order wins.
    assert_eq!(m.end_effector().name, "l2");
    assert!(
        loaded.notes.iter().any(|n| n.contains("'l2'")),
        "{:?}",
        loaded.notes
    );
}

#[test]
fn end_effector_with_offset_and_gravity_from_options() {
    let options = Choices {
        end_effector: Some(FrameSpec {
            name: Some("probe".into()),
            link: "sensor".into(),
            xyz: [0.0, 0.0, 0.05],
            rpy: [0.0, 0.0, 0.0],
        }),
        locked_joints: vec![],
        gravity: Some([0.0, -9.81, 0.0]),
        snap_angles: None,
        inertia: Default::default(),
        frames: Default::default(),
        floating_base: false,
        joint_parameters: None,
        functions: None,
        contacts: Vec::new(),
        frame_references: Default::default(),
        code_shape: Default::default(),
    };
    let m = description::load_urdf_str(TREE_URDF, Path::new("twins.urdf"), &options)
        .unwrap()
        .model;
    assert_eq!(m.end_effector().name, "probe");
    assert_eq!(m.end_effector_body(), 0, "the sensor rides on the waist joint");
    assert_eq!(
        m.end_effector().placement.translation,
        Vector3::new(0.1, 0.0, 0.35)
    );
    assert_eq!(m.gravity(), Vector3::new(0.0, -9.81, 0.0));
}

#[test]
fn locked_joint_welds_its_child_at_the_locked_position() {
    let options = Choices {
        locked_joints: vec![("left2".into(), 0.1)],
        ..Default::default()
    };
    let m = description::load_urdf_str(TREE_URDF, Path::new("twins.urdf"), &options)
        .unwrap()
        .model;
    assert_eq!(m.dof(), 4);
    // l2 (1 kg at the origin of its frame) now sits 0.3 + 0.1 m along l1's x axis.
    let l1 = &m.bodies()[1].inertia;
    assert!((l1.mass - 2.0).abs() < 1e-12);
    assert!(
        (l1.com - Vector3::new(0.2, 0.0, 0.0)).norm() < 1e-12,
        "{:?}",
        l1.com
    );
}

/// The same small robot in both formats: fixed joint, rotated origins, inertial frames with
/// rpy, continuous and prismatic joints, a locked joint and an end-effector offset.
const SAME_URDF: &str = r#"<robot name="same">
  <link name="base"/>
  <link name="a"><inertial><origin xyz="0.1 0.02 0.3" rpy="0.3 -0.2 0.1"/><mass value="2.5"/>
    <inertia ixx="0.03" ixy="0.001" ixz="-0.002" iyy="0.04" iyz="0.003" izz="0.02"/></inertial></link>
  <link name="b"><inertial><origin xyz="0 0.1 0"/><mass value="1.2"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.012" iyz="0" izz="0.009"/></inertial></link>
  <link name="c"><inertial><mass value="0.4"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <link name="d"><inertial><mass value="0.3"/>
    <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial></link>
  <link name="tip"/>
  <joint name="j1" type="continuous"><parent link="base"/><child link="a"/>
    <origin xyz="0 0 0.2" rpy="0 0 0.5"/><axis xyz="0 0 1"/></joint>
  <joint name="j2" type="revolute"><parent link="a"/><child link="b"/>
    <origin xyz="0.05 0 0.4" rpy="-1.5707963267948966 0 0"/><axis xyz="0 0.6 0.8"/>
    <limit lower="-1" upper="1.5" effort="30" velocity="2"/></joint>
  <joint name="weld" type="fixed"><parent link="b"/><child link="c"/>
    <origin xyz="0 0.3 0" rpy="0.1 0.2 0.3"/></joint>
  <joint name="slide" type="prismatic"><parent link="c"/><child link="d"/>
    <origin xyz="0 0 0.1"/><axis xyz="1 0 0"/><limit lower="-0.1" upper="0.1" effort="100" velocity="0.3"/></joint>
  <joint name="lock" type="revolute"><parent link="d"/><child link="tip"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>"#;

const SAME_YAML: &str = r#"
name: same
end_effector: { name: tcp, link: tip, xyz: [0, 0, 0.02], rpy: [0, 0, 1.0] }
locked_joints: { lock: 0.25 }
links:
  - name: base
  - name: a
    inertial:
      mass: 2.5
      origin: { xyz: [0.1, 0.02, 0.3], rpy: [0.3, -0.2, 0.1] }
      inertia: { ixx: 0.03, ixy: 0.001, ixz: -0.002, iyy: 0.04, iyz: 0.003, izz: 0.02 }
  - name: b
    inertial:
      mass: 1.2
      origin: { xyz: [0, 0.1, 0] }
      inertia: { ixx: 0.01, ixy: 0, ixz: 0, iyy: 0.012, iyz: 0, izz: 0.009 }
  - name: c
    inertial: { mass: 0.4, inertia: { ixx: 0.001, ixy: 0, ixz: 0, iyy: 0.001, iyz: 0, izz: 0.001 } }
  - name: d
    inertial: { mass: 0.3, inertia: { ixx: 0.001, ixy: 0, ixz: 0, iyy: 0.001, iyz: 0, izz: 0.001 } }
  - name: tip
joints:
  - { name: j1, type: continuous, parent: base, child: a, origin: { xyz: [0, 0, 0.2], rpy: [0, 0, 0.5] }, axis: [0, 0, 1] }
  - name: j2
    type: revolute
    parent: a
    child: b
    origin: { xyz: [0.05, 0, 0.4], rpy: [-1.5707963267948966, 0, 0] }
    axis: [0, 0.6, 0.8]
    limit: { lower: -1, upper: 1.5, effort: 30, velocity: 2 }
  - { name: weld, type: fixed, parent: b, child: c, origin: { xyz: [0, 0.3, 0], rpy: [0.1, 0.2, 0.3] } }
  - name: slide
    type: prismatic
    parent: c
    child: d
    origin: { xyz: [0, 0, 0.1] }
    axis: [1, 0, 0]
    limit: { lower: -0.1, upper: 0.1, effort: 100, velocity: 0.3 }
  - name: lock
    type: revolute
    parent: d
    child: tip
    origin: { xyz: [0, 0, 0.05] }
    axis: [0, 0, 1]
    limit: { lower: -3, upper: 3, effort: 1, velocity: 1 }
"#;

#[test]
fn same_robot_in_yaml_and_urdf_gives_the_same_model() {
    let options = Choices {
        end_effector: Some(FrameSpec {
            name: Some("tcp".into()),
            link: "tip".into(),
            xyz: [0.0, 0.0, 0.02],
            rpy: [0.0, 0.0, 1.0],
        }),
        locked_joints: vec![("lock".into(), 0.25)],
        gravity: None,
        snap_angles: None,
        inertia: Default::default(),
        frames: Default::default(),
        floating_base: false,
        joint_parameters: None,
        functions: None,
        contacts: Vec::new(),
        frame_references: Default::default(),
        code_shape: Default::default(),
    };
    let from_urdf = description::load_urdf_str(SAME_URDF, Path::new("same.urdf"), &options).unwrap();
    let from_yaml =
        description::load_yaml_str(SAME_YAML, Path::new("same.yaml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(from_yaml.model, from_urdf.model);
    let m = &from_yaml.model;
    assert_eq!(m.dof(), 3);
    assert_eq!(m.gravity(), Vector3::new(0.0, 0.0, -9.81));
    // the axis (0, 0.6, 0.8) is already unit; the inertial rpy rotates the tensor
    assert_eq!(m.joints()[1].axis, Vector3::new(0.0, 0.6, 0.8));
    assert!(m.bodies()[0].inertia.inertia_com[(0, 1)] != 0.001);
    // slide hangs from b through the fixed weld: origin = weld ∘ slide origin
    let weld = from_xyz_rpy([0.0, 0.3, 0.0], [0.1, 0.2, 0.3]);
    assert_eq!(
        m.joints()[2].origin,
        weld.compose(&from_xyz_rpy([0.0, 0.0, 0.1], [0.0; 3]))
    );
    assert!(from_yaml.sources.is_empty(), "nothing was read from disk");
}

#[test]
fn unit_axis_is_normalized_with_a_note() {
    let yaml = SAME_YAML.replace("axis: [1, 0, 0]", "axis: [2, 0, 0]");
    let loaded = description::load_yaml_str(&yaml, Path::new("same.yaml")).unwrap();
    assert_eq!(loaded.model.joints()[2].axis, Vector3::x());
    assert!(
        loaded
            .notes
            .iter()
            .any(|n| n.contains("joint 'slide'") && n.contains("not a unit vector")),
        "{:?}",
        loaded.notes
    );
}

/// Fuzz finding: components so small that their squares underflow (or so large that they
/// overflow) still give a unit axis, not a model that breaks an invariant.
#[test]
fn tiny_and_huge_axes_are_normalized() {
    for (written, expected) in [
        ("[3.0e-170, 0, 4.0e-170]", Vector3::new(0.6, 0.0, 0.8)),
        ("[3.0e+170, 0, 4.0e+170]", Vector3::new(0.6, 0.0, 0.8)),
        ("[0, 1.0e-310, 0]", Vector3::y()),
    ] {
        let yaml = SAME_YAML.replace("axis: [1, 0, 0]", &format!("axis: {written}"));
        let loaded = description::load_yaml_str(&yaml, Path::new("same.yaml"))
            .unwrap_or_else(|e| panic!("{written}: {e}"));
        let axis = loaded.model.joints()[2].axis;
        assert!((axis - expected).amax() < 1e-15, "{written}: {axis:?}");
    }
}

#[test]
fn inertial_frame_rotation_is_applied() {
    // The tensor diag(1, 2, 3) is given in axes turned a quarter turn about z: in the link
    // frame, x and y swap. The centre of mass is the inertial origin's xyz.
    let urdf = r#"<robot name="r"><link name="base"/>
      <link name="a"><inertial><origin xyz="0.1 0.2 0.3" rpy="0 0 1.5707963267948966"/><mass value="2"/>
        <inertia ixx="1" ixy="0" ixz="0" iyy="2" iyz="0" izz="3"/></inertial></link>
      <joint name="j" type="continuous"><parent link="base"/><child link="a"/></joint></robot>"#;
    let m = description::load_urdf_str(urdf, Path::new("r.urdf"), &Choices::default())
        .unwrap()
        .model;
    let body = &m.bodies()[0].inertia;
    assert_eq!(
        body.inertia_com,
        Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 3.0))
    );
    assert_eq!(body.com, Vector3::new(0.1, 0.2, 0.3));
    assert_eq!(m.joints()[0].axis, Vector3::x(), "URDF default axis");
}

#[test]
fn locked_revolute_joint_turns_its_child_by_the_locked_angle() {
    let yaml = r#"
name: r
locked_joints: { wrist: 1.5707963267948966 }
end_effector: l1
links:
  - name: base
  - { name: l1, inertial: { mass: 1.0, inertia: { ixx: 0.1, ixy: 0, ixz: 0, iyy: 0.1, iyz: 0, izz: 0.1 } } }
  - name: l2
    inertial:
      mass: 1.0
      origin: { xyz: [0.5, 0, 0] }
      inertia: { ixx: 0.1, ixy: 0, ixz: 0, iyy: 0.1, iyz: 0, izz: 0.1 }
joints:
  - { name: j1, type: continuous, parent: base, child: l1, axis: [0, 0, 1] }
  - { name: wrist, type: continuous, parent: l1, child: l2, origin: { xyz: [0, 0, 0.1] }, axis: [0, 0, 1] }
"#;
    let m = description::load_yaml_str(yaml, Path::new("r.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    assert_eq!(m.dof(), 1);
    // l2's centre of mass (0.5, 0, 0) turned +90° about z is (0, 0.5, 0), then lifted 0.1.
    let body = &m.bodies()[0].inertia;
    assert!(
        (body.com - Vector3::new(0.0, 0.25, 0.05)).norm() < 1e-15,
        "{:?}",
        body.com
    );
}
