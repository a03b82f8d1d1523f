//! `urdf_rs::Robot` in and out: `from_urdf_rs` runs the checks and the assembly of a URDF file,
//! `to_urdf_rs` writes any model as a URDF that loads back as the same model.
//!
//! The round trip description → model → URDF text (through urdf-rs) → model is checked both
//! through `from_urdf_rs` and by loading the text as a file: same model (names equal, numbers
//! to 1e-12), bit-identical parameters and byte-identical generated code, for the committed
//! robots and for random trees. Bad input gives the file loader's messages, without the place.

use dyngen_codegen::description::{
    self, from_urdf_rs, load_urdf_str, to_urdf_rs, Choices, DescriptionError, FrameSelection, FrameSpec,
    Loaded, UrdfExport,
};
use dyngen_codegen::internals::generate::{emit, trace, type_name, Provenance};
use dyngen_codegen::model::{Body, Frame, Joint, JointKind, Limits, Model, Pose};
use dyngen_codegen::urdf_rs;
use dyngen_testkit::random_model::{arb_model, deterministic_runner};
use dyngen_testkit::scratch::scratch_dir;
use nalgebra::{Matrix3, Vector3};
use proptest::strategy::{Strategy, ValueTree};
use std::path::{Path, PathBuf};

fn repo(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(rel)
}

fn load(path: &Path) -> Loaded {
    description::load(path).unwrap_or_else(|e| panic!("{e}"))
}

// ---------------------------------------------------------------------------------------------
// Comparing models

fn close(what: &str, a: f64, b: f64) {
    let tol = 1e-12 * a.abs().max(b.abs()).max(1.0);
    assert!((a - b).abs() <= tol, "{what}: {a:e} vs {b:e}");
}

fn close_all<'a>(what: &str, a: impl IntoIterator<Item = &'a f64>, b: impl IntoIterator<Item = &'a f64>) {
    let (a, b): (Vec<f64>, Vec<f64>) = (a.into_iter().copied().collect(), b.into_iter().copied().collect());
    assert_eq!(a.len(), b.len(), "{what}: lengths");
    for (k, (x, y)) in a.iter().zip(&b).enumerate() {
        close(&format!("{what}[{k}]"), *x, *y);
    }
}

fn close_pose(what: &str, a: &Pose, b: &Pose) {
    close_all(&format!("{what} rotation"), a.rotation.iter(), b.rotation.iter());
    close_all(
        &format!("{what} translation"),
        a.translation.iter(),
        b.translation.iter(),
    );
}

/// Same model: names, structure and limits equal, every number to 1e-12 relative.
fn assert_same_model(actual: &Model, expected: &Model) {
    assert_eq!(actual.name(), expected.name());
    assert_eq!(actual.dof(), expected.dof(), "{}: DOF", expected.name());
    assert_eq!(
        actual.mimics(),
        expected.mimics(),
        "{}: mimic joints",
        expected.name()
    );
    for (a, e) in actual.joints().iter().zip(expected.joints()) {
        let w = format!("{}: joint '{}'", expected.name(), e.name);
        assert_eq!(a.name, e.name, "{w}: name");
        assert_eq!(a.parent, e.parent, "{w}: parent");
        assert_eq!(a.kind, e.kind, "{w}: kind");
        assert_eq!(a.limits, e.limits, "{w}: limits");
        close_pose(&format!("{w} origin"), &a.origin, &e.origin);
        close_all(&format!("{w} axis"), a.axis.iter(), e.axis.iter());
    }
    for (a, e) in actual.bodies().iter().zip(expected.bodies()) {
        let w = format!("{}: body '{}'", expected.name(), e.name);
        assert_eq!(a.name, e.name, "{w}: name");
        close(&format!("{w} mass"), a.inertia.mass, e.inertia.mass);
        close_all(&format!("{w} com"), a.inertia.com.iter(), e.inertia.com.iter());
        close_all(
            &format!("{w} inertia"),
            a.inertia.inertia_com.iter(),
            e.inertia.inertia_com.iter(),
        );
    }
    close_all("gravity", actual.gravity().iter(), expected.gravity().iter());
    let (a, e) = (&actual.end_effector(), &expected.end_effector());
    assert_eq!(a.name, e.name, "end-effector name");
    assert_eq!(a.parent, e.parent, "end-effector parent");
    close_pose("end-effector placement", &a.placement, &e.placement);
}

/// The generated module, with the same provenance for every model so that only the model
/// can make two texts differ.
fn generated(model: &Model) -> String {
    let provenance = Provenance {
        source: "round trip".into(),
        source_hash: "0".into(),
        regenerate: "none".into(),
        type_name: type_name(model.name()),
    };
    emit(model, &trace(model), &provenance)
}

// ---------------------------------------------------------------------------------------------
// The round trip

/// Both ways back from the exported URDF text: parsed by urdf-rs and given to `from_urdf_rs`,
/// and written to a file and loaded as one (bare, or through the YAML wrapper the export
/// suggests when it needs options).
fn reload_both_ways(export: &UrdfExport, dir: &Path) -> [Model; 2] {
    let text = urdf_rs::write_to_string(&export.robot).expect("urdf-rs writes the robot");
    let parsed =
        urdf_rs::read_from_string(&text).unwrap_or_else(|e| panic!("urdf-rs reads its text: {e}\n{text}"));
    let in_memory = from_urdf_rs(&parsed, &export.choices).unwrap_or_else(|e| panic!("{e}\n{text}"));

    let urdf_path = dir.join(format!("{}.urdf", export.robot.name));
    std::fs::write(&urdf_path, &text).expect("write URDF");
    let from_file = if !export.needs_wrapper() {
        load(&urdf_path)
    } else {
        let wrapper = dir.join(format!("{}.yaml", export.robot.name));
        let file_name = urdf_path.file_name().and_then(|f| f.to_str()).expect("file name");
        std::fs::write(&wrapper, export.yaml_wrapper(file_name)).expect("write wrapper");
        load(&wrapper)
    };
    [in_memory.model, from_file.model]
}

/// The round trip of one model: same model, same parameters (bit for bit), same code (byte for
/// byte) both ways back.
fn assert_round_trip(model: &Model, dir: &Path, compare_code: bool) -> UrdfExport {
    let export = to_urdf_rs(model).unwrap_or_else(|e| panic!("{e}"));
    let code = compare_code.then(|| generated(model));
    for (how, back) in ["from_urdf_rs", "file"]
        .into_iter()
        .zip(reload_both_ways(&export, dir))
    {
        assert_same_model(&back, model);
        assert_eq!(
            back.parameters(),
            model.parameters(),
            "{how}: parameters of {}",
            model.name()
        );
        assert_eq!(back.parameter_names(), model.parameter_names());
        if let Some(code) = &code {
            assert!(
                generated(&back) == *code,
                "{how}: generated code of {} differs",
                model.name()
            );
        }
    }
    export
}

/// Joint friction goes into `<dynamics damping friction>`; the columns, the Coulomb smoothing,
/// armature and offset (which URDF cannot say) into the YAML wrapper: through the wrapper the
/// model, its joint terms and its code come back exactly.
#[test]
fn joint_friction_and_armature_round_trip_through_dynamics_tags_and_the_wrapper() {
    let temp = scratch_dir("urdf-rs-joint_terms");
    let dir = temp.path();
    let arm7 = load(&repo("robots/arm7.yaml")).model;
    let model = dyngen_testkit::joint_terms::with_joint_terms(arm7, Some(0.02), 11);
    let export = to_urdf_rs(&model).unwrap_or_else(|e| panic!("{e}"));
    assert!(export.needs_wrapper());
    for (joint, j) in export.robot.joints.iter().zip(0..model.dof()) {
        let v = model.joint_terms().value(j);
        let dynamics = joint.dynamics.as_ref().expect("<dynamics>");
        assert_eq!(
            (dynamics.damping, dynamics.friction),
            (v.viscous, v.coulomb),
            "{}",
            joint.name
        );
    }
    // Through `from_urdf_rs` alone (no wrapper) the rigid body comes back; the wrapper's
    // `joint_parameters` choose the columns.
    let [rigid, from_file] = reload_both_ways(&export, dir);
    assert_same_model(&rigid, &model);
    assert_same_model(&from_file, &model);
    assert_eq!(from_file.joint_terms(), model.joint_terms());
    assert!(
        generated(&from_file) == generated(&model),
        "generated code differs"
    );
}

#[test]
fn committed_robots_round_trip_to_identical_code() {
    let temp = scratch_dir("urdf-rs-robots");
    let dir = temp.path();
    for robot in ["arm7", "panda", "panda_rounded", "ur5"] {
        let loaded = load(&repo(&format!("robots/{robot}.yaml")));
        let export = assert_round_trip(&loaded.model, dir, true);
        // Default gravity, and the end-effector is the loader's default pick: a bare URDF says
        // all but the named frames (Panda, UR5: every link), which go into the wrapper.
        let frames = match &export.choices.frames {
            FrameSelection::Listed(frames) => frames.len(),
            _ => 0,
        };
        assert_eq!(frames, loaded.model.frames().len() - 1, "{robot}");
        let without_frames = Choices {
            frames: FrameSelection::EndEffector,
            ..export.choices.clone()
        };
        assert_eq!(without_frames, Choices::default(), "{robot}");
        assert!(export.warnings.is_empty(), "{robot}: {:?}", export.warnings);
    }
}

/// Mimic joints are written as `<mimic>` and load back as the same coupling, the same code.
#[test]
fn robots_with_mimic_joints_round_trip_to_identical_code() {
    let temp = scratch_dir("urdf-rs-mimic");
    let dir = temp.path();
    for yaml in ["panda_mimic", "mimic_arm"] {
        let loaded = load(&repo(&format!("codegen/tests/data/mimic/{yaml}.yaml")));
        assert!(loaded.model.has_mimics());
        assert_round_trip(&loaded.model, dir, yaml == "mimic_arm");
    }
}

/// The model with its joints in depth-first order, children in index order: the order every
/// URDF reader (dyngen's, urdfdom, Pinocchio) gives a tree.
fn depth_first(model: &Model) -> Model {
    let n = model.joints().len();
    let mut order = Vec::with_capacity(n);
    let mut stack: Vec<usize> = (0..n)
        .rev()
        .filter(|&j| model.joints()[j].parent.is_none())
        .collect();
    while let Some(j) = stack.pop() {
        order.push(j);
        stack.extend((0..n).rev().filter(|&c| model.joints()[c].parent == Some(j)));
    }
    let mut new_index = vec![0; n];
    for (new, &old) in order.iter().enumerate() {
        new_index[old] = new;
    }
    Model::new(
        model.name(),
        order
            .iter()
            .map(|&old| Joint {
                parent: model.joints()[old].parent.map(|p| new_index[p]),
                ..model.joints()[old].clone()
            })
            .collect(),
        order.iter().map(|&old| model.bodies()[old].clone()).collect(),
        model.gravity(),
        Frame {
            parent: Some(new_index[model.end_effector_body()]),
            ..model.end_effector().clone()
        },
    )
    .expect("a permutation of a valid model is valid")
}

fn random_models(cases: u32, max_dof: usize) -> Vec<Model> {
    let mut runner = deterministic_runner(cases);
    let strategy = arb_model(max_dof);
    (0..cases)
        .map(|_| strategy.new_tree(&mut runner).expect("a random model").current())
        .collect()
}

#[test]
fn random_trees_round_trip_to_identical_code() {
    let temp = scratch_dir("urdf-rs-random");
    let dir = temp.path();
    let (mut with_gravity, mut with_end_effector) = (0, 0);
    for (k, model) in random_models(24, 5).iter().enumerate() {
        let model = depth_first(model);
        // Code for a third of them: tracing is the slow part, and the models are what differ.
        let export = assert_round_trip(&model, dir, k % 3 == 0);
        with_gravity += usize::from(export.choices.gravity.is_some());
        with_end_effector += usize::from(export.choices.end_effector.is_some());
        assert_eq!(
            export.choices.gravity.is_some(),
            model.gravity() != Vector3::new(0.0, 0.0, -9.81),
            "gravity is in the options exactly when it is not the default"
        );
        let warned = export.warnings.iter().any(|w| w.contains("gravity"));
        assert_eq!(warned, export.choices.gravity.is_some(), "{:?}", export.warnings);
    }
    // The sample exercises the options, not only the bare URDF.
    assert!(
        with_gravity > 0 && with_end_effector > 0,
        "{with_gravity} {with_end_effector}"
    );
}

#[test]
fn joints_not_in_depth_first_order_come_back_reordered_with_a_warning() {
    let models = random_models(64, 6);
    let model = models
        .iter()
        .find(|m| {
            depth_first(m)
                .joints()
                .iter()
                .zip(m.joints())
                .any(|(a, b)| a.name != b.name)
        })
        .expect("some random tree is not in depth-first order");
    let export = to_urdf_rs(model).unwrap();
    assert!(
        export.warnings.iter().any(|w| w.contains("depth-first")),
        "{:?}",
        export.warnings
    );
    let back = from_urdf_rs(&export.robot, &export.choices).unwrap().model;
    assert_same_model(&back, &depth_first(model));
}

// ---------------------------------------------------------------------------------------------
// What the export writes

fn find_joint<'a>(robot: &'a urdf_rs::Robot, name: &str) -> &'a urdf_rs::Joint {
    robot
        .joints
        .iter()
        .find(|j| j.name == name)
        .unwrap_or_else(|| panic!("no joint '{name}'"))
}

#[test]
fn export_writes_bodies_joints_and_the_end_effector_link() {
    let model = load(&repo("robots/panda.yaml")).model;
    let export = to_urdf_rs(&model).unwrap();
    let r = &export.robot;
    assert_eq!(r.name, "panda");
    // Base, seven bodies, the end-effector frame; the welded links are gone.
    let names: Vec<&str> = r.links.iter().map(|l| l.name.as_str()).collect();
    assert_eq!(names.first(), Some(&"base_link"));
    assert_eq!(names.last(), Some(&"panda_hand_tcp"));
    assert_eq!(names.len(), 9, "{names:?}");
    assert!(!names.contains(&"panda_hand") && !names.contains(&"panda_leftfinger"));
    assert_eq!(r.joints.len(), 8);
    let j1 = find_joint(r, "panda_joint1");
    assert_eq!(j1.joint_type, urdf_rs::JointType::Revolute);
    assert_eq!(j1.parent.link, "base_link");
    assert_eq!(j1.origin.xyz.0, [0.0, 0.0, 0.333]);
    let limits = model.joints()[0].limits.unwrap();
    assert_eq!((j1.limit.lower, j1.limit.upper), (limits.lower, limits.upper));
    assert_eq!(
        (j1.limit.velocity, j1.limit.effort),
        (limits.velocity, limits.effort)
    );
    let tcp = find_joint(r, "panda_hand_tcp_joint");
    assert_eq!(tcp.joint_type, urdf_rs::JointType::Fixed);
    assert_eq!(tcp.parent.link, "panda_link7");
    // The hand is turned by -π/4 about z; link 8 and the TCP are 0.107 + 0.1034 m further.
    close("tcp yaw", tcp.origin.rpy[2], -std::f64::consts::FRAC_PI_4);
    close("tcp z", tcp.origin.xyz[2], 0.107 + 0.1034);
    // The hand and fingers are merged into link 7: its mass is the sum.
    let link7 = r.links.iter().find(|l| l.name == "panda_link7").unwrap();
    close(
        "link7 mass",
        link7.inertial.mass.value,
        model.bodies()[6].inertia.mass,
    );
    assert!(link7.inertial.mass.value > 0.9, "the hand (0.73 kg) is welded in");

    let text = urdf_rs::write_to_string(r).unwrap();
    assert!(text.contains(r#"<link name="base_link">"#), "{text}");
    assert!(
        text.contains(r#"<joint name="panda_joint1" type="revolute">"#),
        "{text}"
    );
}

#[test]
fn continuous_joints_and_massless_bodies_are_written_as_urdf_says_them() {
    let yaml = "name: wheel\nlinks:\n  - name: base\n  - name: rim\njoints:\n  - { name: spin, type: continuous, parent: base, child: rim, axis: [0, 0, 1] }\n";
    let loaded = description::load_yaml_str(yaml, Path::new("wheel.yaml")).unwrap();
    let export = to_urdf_rs(&loaded.model).unwrap();
    let spin = find_joint(&export.robot, "spin");
    assert_eq!(spin.joint_type, urdf_rs::JointType::Continuous);
    assert_eq!(spin.limit, urdf_rs::JointLimit::default());
    // The end-effector is the body itself: no extra link, and the default rule finds it.
    assert_eq!(export.robot.links.len(), 2);
    assert_eq!(export.choices, Choices::default());
    let back = from_urdf_rs(&export.robot, &Choices::default()).unwrap().model;
    assert_eq!(back, loaded.model);
}

#[test]
fn gravity_and_a_non_default_end_effector_go_in_the_options() {
    // A two-branch tree on a wall (gravity along -x), the end-effector on the shorter branch
    // with an offset, named like its body: neither survives in a bare URDF.
    let yaml = r#"
name: wall
gravity: [-9.81, 0.0, 0.0]
end_effector: { link: a1, xyz: [0.0, 0.0, 0.1], rpy: [0.3, 0.0, 0.0] }
links:
  - name: base
  - name: a1
    inertial: { mass: 1.0, inertia: { ixx: 0.01, ixy: 0, ixz: 0, iyy: 0.01, iyz: 0, izz: 0.01 } }
  - name: b1
    inertial: { mass: 1.0, inertia: { ixx: 0.01, ixy: 0, ixz: 0, iyy: 0.01, iyz: 0, izz: 0.01 } }
  - name: b2
    inertial: { mass: 1.0, inertia: { ixx: 0.01, ixy: 0, ixz: 0, iyy: 0.01, iyz: 0, izz: 0.01 } }
joints:
  - { name: ja1, type: continuous, parent: base, child: a1, axis: [0, 0, 1] }
  - { name: jb1, type: continuous, parent: base, child: b1, axis: [0, 0, 1], origin: { xyz: [0.2, 0, 0] } }
  - { name: jb2, type: continuous, parent: b1, child: b2, axis: [0, 1, 0], origin: { xyz: [0, 0, 0.3] } }
"#;
    let model = description::load_yaml_str(yaml, Path::new("wall.yaml"))
        .unwrap()
        .model;
    let temp = scratch_dir("urdf-rs-options");
    let dir = temp.path();
    let export = assert_round_trip(&model, dir, false);
    assert_eq!(export.choices.gravity, Some([-9.81, 0.0, 0.0]));
    let ee = export.choices.end_effector.as_ref().expect("end-effector option");
    assert_eq!((ee.link.as_str(), ee.name.as_deref()), ("a1", None));
    close("ee z", ee.xyz[2], 0.1);
    close("ee roll", ee.rpy[0], 0.3);
    assert_eq!(export.warnings.len(), 2, "{:?}", export.warnings);
    // Without the options the URDF gives the default gravity and the longest branch's leaf.
    let bare = from_urdf_rs(&export.robot, &Choices::default()).unwrap().model;
    assert_eq!(bare.gravity(), Vector3::new(0.0, 0.0, -9.81));
    assert_eq!(bare.end_effector().name, "b2");
    assert!(export
        .yaml_wrapper("wall.urdf")
        .contains("gravity: [-9.81, 0.0, 0.0]"));
}

fn one_joint_model(kind: JointKind, limits: Option<Limits>, body: &str) -> Model {
    Model::new(
        "one",
        vec![Joint {
            name: "j".into(),
            parent: None,
            kind,
            origin: Pose::identity(),
            axis: Vector3::z(),
            limits,
        }],
        vec![Body {
            name: body.into(),
            inertia: dyngen_codegen::model::Inertia {
                mass: 1.0,
                com: Vector3::new(0.0, 0.0, 0.1),
                inertia_com: Matrix3::identity() * 0.01,
            },
        }],
        Vector3::new(0.0, 0.0, -9.81),
        Frame {
            name: "tool".into(),
            parent: Some(0),
            placement: Pose::identity(),
        },
    )
    .expect("a valid model")
}

#[test]
fn the_base_link_name_avoids_the_bodies() {
    let model = one_joint_model(JointKind::Revolute, None, "base_link");
    let export = to_urdf_rs(&model).unwrap();
    assert_eq!(export.robot.links[0].name, "base_link_1");
    assert_eq!(find_joint(&export.robot, "j").parent.link, "base_link_1");
    assert_eq!(from_urdf_rs(&export.robot, &export.choices).unwrap().model, model);
}

#[test]
fn what_urdf_cannot_express_is_refused() {
    let model = one_joint_model(JointKind::Prismatic, None, "slider");
    let e = to_urdf_rs(&model).unwrap_err().to_string();
    assert_eq!(
        e,
        "cannot write model 'one' as URDF: joint 'j' is prismatic without limits, which URDF cannot express"
    );
}

// ---------------------------------------------------------------------------------------------
// from_urdf_rs: the same model and the same messages as a URDF file

#[test]
fn committed_urdfs_through_urdf_rs_give_the_file_loaders_models() {
    // The YAML wrappers' options, applied to the URDFs as read by urdf-rs (meshes, visuals,
    // collisions, transmissions and all).
    let panda = Choices {
        end_effector: Some(FrameSpec::link("panda_hand_tcp")),
        locked_joints: vec![
            ("panda_finger_joint1".into(), 0.0),
            ("panda_finger_joint2".into(), 0.0),
        ],
        ..Choices::default()
    };
    let ur5 = Choices {
        end_effector: Some(FrameSpec::link("tool0")),
        snap_angles: Some(1e-9),
        ..Choices::default()
    };
    for (file, yaml, options) in [
        ("panda.urdf", "panda.yaml", panda),
        ("ur5_robot.urdf", "ur5.yaml", ur5),
    ] {
        let path = repo(&format!("robots/urdf/{file}"));
        let robot = urdf_rs::read_file(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        let wrapped = load(&repo(&format!("robots/{yaml}"))).model;
        let got = from_urdf_rs(&robot, &options).unwrap_or_else(|e| panic!("{e}"));
        // The wrappers rename the robots.
        let expected = Model::new(
            got.model.name(),
            wrapped.joints().to_vec(),
            wrapped.bodies().to_vec(),
            wrapped.gravity(),
            wrapped.end_effector().clone(),
        )
        .unwrap();
        assert_eq!(got.model, expected, "{file}");
        assert!(got.sources.is_empty());
    }
}

/// One URDF through both readers with default options: same model, and the same warnings and
/// notes once the place is taken out.
fn both_readers(text: &str) -> (Loaded, Loaded) {
    let file =
        load_urdf_str(text, Path::new("t.urdf"), &Choices::default()).unwrap_or_else(|e| panic!("{e}"));
    let robot = urdf_rs::read_from_string(text).unwrap_or_else(|e| panic!("{e}"));
    let memory = from_urdf_rs(&robot, &Choices::default()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(memory.model, file.model);
    (file, memory)
}

/// `file:line:column: rest` or `file: rest` → `rest`.
fn without_place(message: &str, file: &str) -> String {
    let rest = message
        .strip_prefix(file)
        .unwrap_or_else(|| panic!("'{message}' names '{file}'"));
    let rest = rest.trim_start_matches(|c: char| c == ':' || c.is_ascii_digit());
    rest.trim_start().to_owned()
}

const INERTIA: &str = r#"<inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/>"#;

#[test]
fn urdf_defaults_map_as_in_a_file() {
    // No <inertial> (massless), no <axis> ([1, 0, 0]), no <origin>, a continuous joint without
    // <limit>, a mimic joint without multiplier and offset (locked with its leader), a
    // prismatic joint, and a zero-mass link with an inertia (a warning).
    let text = format!(
        r#"<robot name="defaults">
  <link name="base"/>
  <link name="a"><inertial><origin xyz="0 0 0.1" rpy="0.1 0.2 0.3"/><mass value="1"/>{INERTIA}</inertial></link>
  <link name="b"><inertial><mass value="0"/>{INERTIA}</inertial></link>
  <link name="c"><inertial><mass value="2"/>{INERTIA}</inertial></link>
  <link name="d"/>
  <joint name="ja" type="continuous"><parent link="base"/><child link="a"/></joint>
  <joint name="jb" type="prismatic"><parent link="a"/><child link="b"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 0 2"/><limit lower="-0.1" upper="0.1" velocity="1" effort="10"/></joint>
  <joint name="jc" type="revolute"><parent link="b"/><child link="c"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" velocity="1" effort="10"/></joint>
  <joint name="jd" type="revolute"><parent link="c"/><child link="d"/>
    <limit lower="-1" upper="1" velocity="1" effort="10"/><mimic joint="jc"/></joint>
</robot>"#
    );
    let options = Choices {
        locked_joints: vec![("jd".into(), 0.5), ("jc".into(), 0.5)],
        ..Choices::default()
    };
    let file = load_urdf_str(&text, Path::new("t.urdf"), &options).unwrap();
    let memory = from_urdf_rs(&urdf_rs::read_from_string(&text).unwrap(), &options).unwrap();
    assert_eq!(memory.model, file.model);
    let m = &memory.model;
    assert_eq!(m.joints()[0].kind, JointKind::Revolute);
    assert_eq!(m.joints()[0].axis, Vector3::x());
    assert_eq!(m.joints()[0].limits, None);
    assert_eq!(m.joints()[1].kind, JointKind::Prismatic);
    assert_eq!(m.joints()[1].axis, Vector3::z());
    assert_eq!(m.dof(), 2, "jc and jd are locked");

    let strip = |l: &Loaded, f: &str| -> Vec<String> {
        l.warnings
            .iter()
            .chain(&l.notes)
            .map(|w| without_place(w, f))
            .collect()
    };
    let from_file = strip(&file, "t.urdf");
    assert_eq!(strip(&memory, "<urdf_rs::Robot 'defaults'>"), from_file);
    assert!(
        from_file
            .iter()
            .any(|w| w.contains("zero mass but a non-zero inertia")),
        "{from_file:?}"
    );
    assert!(
        from_file.iter().any(|w| w.contains("is not a unit vector")),
        "{from_file:?}"
    );
}

#[test]
fn what_dyngen_does_not_model_is_noted() {
    let text = format!(
        r#"<robot name="r" version="1.2">
  <link name="base"/><link name="a"><inertial><mass value="1"/>{INERTIA}</inertial></link>
  <joint name="j" type="revolute"><parent link="base"/><child link="a"/>
    <limit lower="-1" upper="1" velocity="1" effort="10" acceleration="5"/>
    <dynamics damping="0.5" friction="0.1"/></joint>
</robot>"#
    );
    let loaded = from_urdf_rs(&urdf_rs::read_from_string(&text).unwrap(), &Choices::default()).unwrap();
    let notes = loaded.notes.join("\n");
    assert!(
        notes.contains(
            "<urdf_rs::Robot 'r'>: joint 'j': acceleration, deceleration limit not used: dyngen models \
             position, velocity and effort limits only"
        ),
        "{notes}"
    );
    // `<dynamics damping friction>` is read as the file reader reads it: viscous and Coulomb
    // friction values, used when the description asks for joint friction columns.
    assert!(!notes.contains("dynamics"), "{notes}");
    let from_file = load_urdf_str(&text, Path::new("r.urdf"), &Choices::default()).unwrap();
    assert_eq!(loaded.model, from_file.model);
}

fn robot_with(links: &str, joints: &str) -> String {
    format!(r#"<robot name="bad">{links}{joints}</robot>"#)
}

/// Links `base`, `a`, `b`, `c` with unit masses.
fn links() -> String {
    ["base", "a", "b", "c"]
        .iter()
        .map(|n| format!(r#"<link name="{n}"><inertial><mass value="1"/>{INERTIA}</inertial></link>"#))
        .collect()
}

fn joint(name: &str, kind: &str, parent: &str, child: &str, extra: &str) -> String {
    format!(
        r#"<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>{extra}</joint>"#
    )
}

const LIMIT: &str = r#"<limit lower="-1" upper="1" velocity="1" effort="10"/>"#;

#[test]
fn bad_input_gives_the_file_loaders_messages_without_the_place() {
    // A chain base → a → b, then a third joint j3 from b.
    let chain = |kind: &str, child: &str, extra: &str| {
        let joints = [
            joint("j1", "continuous", "base", "a", ""),
            joint("j2", "continuous", "a", "b", ""),
            joint("j3", kind, "b", child, extra),
        ];
        robot_with(&links(), &joints.concat())
    };
    let one_link = |inertial: &str| {
        let links = format!(r#"<link name="base"/><link name="a"><inertial>{inertial}</inertial></link>"#);
        robot_with(&links, &joint("j", "continuous", "base", "a", ""))
    };
    let joints = |list: &[(&str, &str, &str, &str)]| {
        let text: String = list.iter().map(|(n, k, p, c)| joint(n, k, p, c, "")).collect();
        robot_with(&links(), &text)
    };
    let mimic = format!(r#"{LIMIT}<mimic joint="j3"/>"#);
    let plain: Vec<(&str, String)> = vec![
        ("floating joint", chain("floating", "c", "")),
        ("planar joint", chain("planar", "c", "")),
        ("spherical joint", chain("spherical", "c", "")),
        ("undefined link", chain("continuous", "nowhere", "")),
        ("zero axis", chain("continuous", "c", r#"<axis xyz="0 0 0"/>"#)),
        (
            "origin not finite",
            chain("continuous", "c", r#"<origin xyz="nan 0 0"/>"#),
        ),
        (
            "limits reversed",
            chain(
                "revolute",
                "c",
                r#"<limit lower="1" upper="-1" velocity="1" effort="1"/>"#,
            ),
        ),
        ("revolute without limit", chain("revolute", "c", "")),
        ("mimic of itself", chain("revolute", "c", &mimic)),
        (
            "cycle",
            joints(&[
                ("j1", "continuous", "a", "b"),
                ("j2", "continuous", "b", "c"),
                ("j3", "continuous", "c", "a"),
            ]),
        ),
        (
            "two roots",
            joints(&[("j1", "continuous", "base", "a"), ("j2", "continuous", "b", "c")]),
        ),
        (
            "disconnected link",
            joints(&[("j1", "continuous", "base", "a"), ("j2", "continuous", "a", "b")]),
        ),
        (
            "no moving joints",
            robot_with(
                r#"<link name="base"/><link name="a"/>"#,
                &joint("j", "fixed", "base", "a", ""),
            ),
        ),
        (
            "duplicate link",
            robot_with(
                &format!("{}<link name=\"a\"/>", links()),
                &joint("j", "continuous", "base", "a", ""),
            ),
        ),
        (
            "negative mass",
            one_link(&format!(r#"<mass value="-1"/>{INERTIA}"#)),
        ),
        (
            "inertia breaks the triangle inequality",
            one_link(r#"<mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/>"#),
        ),
        (
            "no name",
            format!(
                r#"<robot><link name="a"/><link name="b"/>{}</robot>"#,
                joint("j", "continuous", "a", "b", "")
            ),
        ),
    ];
    let with_options = [
        (
            "unknown locked joint",
            Choices {
                locked_joints: vec![("nope".into(), 0.0)],
                ..Choices::default()
            },
        ),
        (
            "unknown end-effector",
            Choices {
                end_effector: Some(FrameSpec::link("nope")),
                ..Choices::default()
            },
        ),
    ];
    let cases = plain
        .into_iter()
        .map(|(what, text)| (what, text, Choices::default()))
        .chain(
            with_options
                .into_iter()
                .map(|(what, options)| (what, chain("continuous", "c", ""), options)),
        );
    for (what, text, options) in cases {
        let file: DescriptionError = load_urdf_str(&text, Path::new("bad.urdf"), &options)
            .map(|_| ())
            .expect_err(what);
        let robot = urdf_rs::read_from_string(&text).unwrap_or_else(|e| panic!("{what}: urdf-rs: {e}"));
        let memory = from_urdf_rs(&robot, &options).map(|_| ()).expect_err(what);
        let label = if robot.name.is_empty() {
            "<urdf_rs::Robot>".to_owned()
        } else {
            format!("<urdf_rs::Robot '{}'>", robot.name)
        };
        assert_eq!(memory.file, Path::new(&label), "{what}");
        assert_eq!(memory.location, None, "{what}: no place in memory");
        assert_eq!(memory.item, file.item, "{what}");
        // The duplicate's message points at the first definition, by line and column.
        let expected = match file.message.split_once(" (first defined at") {
            Some((head, _)) => head.to_owned(),
            None => file.message.clone(),
        };
        assert_eq!(memory.message, expected, "{what}");
        assert_eq!(
            memory.to_string(),
            format!(
                "{label}: {}",
                without_place(&file.to_string().replace(&file.message, &expected), "bad.urdf")
            ),
            "{what}"
        );
    }
}

#[test]
fn empty_names_in_memory_are_errors() {
    let text = robot_with(&links(), &joint("j", "continuous", "base", "a", ""));
    let mut robot = urdf_rs::read_from_string(&text).unwrap();
    robot.links[1].name.clear();
    let e = from_urdf_rs(&robot, &Choices::default()).unwrap_err().to_string();
    assert_eq!(e, "<urdf_rs::Robot 'bad'>: the link at index 1 has an empty name");
    let mut robot = urdf_rs::read_from_string(&text).unwrap();
    robot.joints[0].child.link.clear();
    let e = from_urdf_rs(&robot, &Choices::default()).unwrap_err().to_string();
    assert_eq!(
        e,
        "<urdf_rs::Robot 'bad'>: joint 'j': the child link name is empty"
    );
}

#[test]
fn same_text_same_model_for_a_branching_tree() {
    let text = robot_with(
        &links(),
        &[
            joint(
                "j1",
                "revolute",
                "base",
                "a",
                &format!(r#"<origin xyz="0 0 0.1" rpy="0 1.5707963267948966 0"/>{LIMIT}"#),
            ),
            joint(
                "j2",
                "continuous",
                "base",
                "b",
                r#"<origin xyz="0.2 0 0" rpy="0.1 0.2 0.3"/><axis xyz="0 1 0"/>"#,
            ),
            joint(
                "j3",
                "fixed",
                "a",
                "c",
                r#"<origin xyz="0 0 0.3" rpy="0 0 0.7"/>"#,
            ),
        ]
        .concat(),
    );
    let (file, memory) = both_readers(&text);
    assert_eq!(file.model.dof(), 2);
    assert_eq!(memory.notes.len(), file.notes.len());
}

/// The loader fuzzer's URDF mutants, where urdf-rs reads them, through `from_urdf_rs`: never a
/// panic, a valid model or an error that names the robot, and the file loader's model whenever
/// both accept (urdf-rs is laxer in places: `xyz="0 x 0 0"` is three numbers to it, a missing
/// `effort` is 0, so some mutants only it accepts; and stricter in others).
#[test]
fn fuzzed_urdfs_through_urdf_rs() {
    use dyngen_testkit::fuzz::{corpus, make_input, model_is_finite, Format};
    use std::panic::{catch_unwind, AssertUnwindSafe};
    let corpus = corpus(&repo(""));
    let (mut parsed, mut both) = (0, 0);
    for seed in 0..10_000u64 {
        let input = make_input(&corpus, seed.wrapping_mul(0x9E37_79B9_7F4A_7C15));
        // urdf-rs parses recursively: deep nesting overflows its stack (an abort, not a panic).
        if input.format != Format::Urdf || input.applied.contains(&"deep-nesting") {
            continue;
        }
        // urdf-rs's own failures (errors or panics) are not ours to judge.
        let Ok(Ok(robot)) = catch_unwind(|| urdf_rs::read_from_string(&input.text)) else {
            continue;
        };
        // XML turns a tab or a line break inside an attribute into a space, which the file
        // loader does; urdf-rs keeps them in names, so the two read different names.
        let names = (robot.links.iter().map(|l| &l.name)).chain(robot.joints.iter().map(|j| &j.name));
        if names.into_iter().any(|name| name.contains(['\t', '\n', '\r'])) {
            continue;
        }
        parsed += 1;
        let options = Choices::default();
        let memory = catch_unwind(AssertUnwindSafe(|| from_urdf_rs(&robot, &options)))
            .unwrap_or_else(|_| panic!("from_urdf_rs panicked on case {seed}:\n{}", input.text));
        let file = load_urdf_str(&input.text, Path::new("fuzz.urdf"), &options);
        match memory {
            Ok(loaded) => {
                assert!(model_is_finite(&loaded.model), "case {seed}");
                if let Ok(from_file) = file {
                    both += 1;
                    assert_eq!(loaded.model, from_file.model, "case {seed}:\n{}", input.text);
                }
            }
            Err(e) => {
                assert!(
                    e.file.to_string_lossy().starts_with("<urdf_rs::Robot"),
                    "case {seed}: {e}"
                );
                assert!(
                    !e.message.trim().is_empty() && e.location.is_none(),
                    "case {seed}: {e}"
                );
            }
        }
    }
    assert!(
        parsed >= 300 && both >= 100,
        "too few mutants exercised: {parsed} read, {both} accepted by both"
    );
}

/// `dyngen urdf` puts an XML declaration and a comment before the robot: both readers
/// (urdf-rs, so urdf-viz; and dyngen's) take the text as it is.
#[test]
fn a_declaration_and_a_comment_before_the_robot_are_read() {
    let model = load(&repo("robots/ur5.yaml")).model;
    let export = to_urdf_rs(&model).unwrap();
    let text = format!(
        "<?xml version=\"1.0\"?>\n<!-- Written by `dyngen urdf` from ur5.yaml -->\n{}\n",
        urdf_rs::write_to_string(&export.robot).unwrap()
    );
    let parsed = urdf_rs::read_from_string(&text).unwrap();
    assert_eq!(from_urdf_rs(&parsed, &export.choices).unwrap().model, model);
    let file = load_urdf_str(&text, Path::new("ur5.urdf"), &export.choices).unwrap();
    assert_eq!(file.model, model);
}
