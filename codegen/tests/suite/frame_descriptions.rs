//! Named frames in descriptions: what `frames:` (YAML), `Choices::frames` and an exported
//! description give, and the one-line errors (file:line:column) for frames that cannot be.

use dyngen_codegen::description::{self, load_urdf_str, load_yaml_str, Choices, FrameSelection, FrameSpec};
use dyngen_codegen::model::Model;
use std::path::Path;

/// A chain base → l1 → l2 with a fixed `flange` on l2 and a fixed `plate` on the base.
const ROBOT: &str = "\
name: r
end_effector: flange
links:
  - name: base
  - name: plate
  - name: l1
    inertial:
      mass: 1.0
      inertia: { ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1 }
  - name: l2
    inertial:
      mass: 1.0
      inertia: { ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1 }
  - name: flange
joints:
  - name: j1
    type: revolute
    parent: base
    child: l1
    axis: [0, 0, 1]
    limit: { lower: -1.0, upper: 1.0, velocity: 1.0, effort: 1.0 }
  - name: j2
    type: revolute
    parent: l1
    child: l2
    origin: { xyz: [0, 0, 0.5], rpy: [0, 0, 0] }
    axis: [0, 1, 0]
    limit: { lower: -1.0, upper: 1.0, velocity: 1.0, effort: 1.0 }
  - name: to_flange
    type: fixed
    parent: l2
    child: flange
    origin: { xyz: [0, 0, 0.3], rpy: [0, 0, 0] }
  - name: to_plate
    type: fixed
    parent: base
    child: plate
";

fn load(frames: &str) -> Result<Model, description::DescriptionError> {
    load_yaml_str(&format!("{ROBOT}{frames}"), Path::new("r.yaml")).map(|l| l.model)
}

fn names(model: &Model) -> Vec<&str> {
    model.frames().iter().map(|f| f.name.as_str()).collect()
}

fn error(frames: &str) -> String {
    let e = load(frames).expect_err("an error").to_string();
    assert!(e.starts_with("r.yaml:"), "not at a place in the file: {e}");
    assert!(!e.contains('\n'), "not one line: {e}");
    e
}

#[test]
fn listed_frames_follow_the_end_effector_with_their_offsets() {
    let model = load("frames: [l1, { name: sensor, link: flange, xyz: [0, 0, 0.05] }]\n").unwrap();
    assert_eq!(names(&model), ["flange", "l1", "sensor"]);
    let sensor = &model.frames()[2];
    assert_eq!(model.joints()[sensor.parent.unwrap()].name, "j2");
    // flange is 0.3 above l2's origin; the sensor 0.05 above the flange.
    assert!((sensor.placement.translation.z - 0.35).abs() < 1e-15);
    // Without `frames:`, the end-effector alone.
    assert_eq!(names(&load("").unwrap()), ["flange"]);
}

#[test]
fn all_means_every_link_that_moves_with_the_end_effector_once() {
    let model = load("frames: all\n").unwrap();
    assert_eq!(names(&model), ["flange", "l1", "l2"]);
    // Listing the end-effector again is the same frame, kept once.
    assert_eq!(names(&load("frames: [flange, l2]\n").unwrap()), ["flange", "l2"]);
}

#[test]
fn frames_that_cannot_be_are_errors_at_their_place() {
    let e = error("frames: [l1, tool9]\n");
    assert!(
        e.starts_with("r.yaml:38:14:") && e.contains("frame 'tool9'") && e.contains("not defined"),
        "{e}"
    );
    let e = error("frames: [plate]\n");
    assert!(
        e.contains("frame 'plate'") && e.contains("fixed to the base"),
        "{e}"
    );
    let e = error("frames: [l1, { name: l1, link: l2 }]\n");
    assert!(e.contains("'l1' is already used by an earlier frame"), "{e}");
    let e = error("frames: [{ name: flange, link: l1 }]\n");
    assert!(e.contains("already used by the end-effector"), "{e}");
    let e = error("frames: l1\n");
    assert!(e.contains("`all` or a list") && e.contains("frames: [l1]"), "{e}");
    let e = error("frames: [{ link: l1, xyz: [0, 0, .nan] }]\n");
    assert!(e.contains("not finite"), "{e}");
}

#[test]
fn a_bare_urdf_takes_frames_from_its_options() {
    let urdf = r#"<robot name="r">
  <link name="base"/>
  <link name="l1"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="t" type="fixed"><parent link="l1"/><child link="tip"/><origin xyz="0 0 0.2"/></joint>
</robot>
"#;
    let options = |frames| Choices {
        frames,
        ..Choices::default()
    };
    let all = load_urdf_str(urdf, Path::new("r.urdf"), &options(FrameSelection::AllLinks)).unwrap();
    assert_eq!(names(&all.model), ["tip", "l1"]);
    let e = load_urdf_str(
        urdf,
        Path::new("r.urdf"),
        &options(FrameSelection::Listed(vec![FrameSpec::link("nope")])),
    )
    .expect_err("an unknown link")
    .to_string();
    assert!(
        e.starts_with("r.urdf") && e.contains("frame 'nope'") && e.contains("not defined"),
        "{e}"
    );
}

/// An exported description (what identification writes) keeps the frames: the URDF has one
/// link per body, and the YAML wrapper places each frame on its body.
#[test]
fn exported_descriptions_keep_their_frames() {
    let model =
        load("frames: [l1, { name: sensor, link: flange, xyz: [0.01, 0, 0.05], rpy: [0.1, 0, 0] }]\n")
            .unwrap();
    let export = description::to_urdf_rs(&model).unwrap();
    let scratch = dyngen_testkit::scratch::scratch_dir("frames");
    let dir = scratch.path();
    std::fs::write(
        dir.join("r.urdf"),
        dyngen_codegen::urdf_rs::write_to_string(&export.robot).unwrap(),
    )
    .unwrap();
    std::fs::write(dir.join("r.yaml"), export.yaml_wrapper("r.urdf")).unwrap();
    let back = description::load(&dir.join("r.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    assert_eq!(names(&back), names(&model));
    for (a, b) in back.frames().iter().zip(model.frames()) {
        assert_eq!(
            back.joints()[a.parent.unwrap()].name,
            model.joints()[b.parent.unwrap()].name
        );
        assert!(
            (a.placement.translation - b.placement.translation).amax() < 1e-12,
            "{}",
            a.name
        );
        assert!(
            (a.placement.rotation - b.placement.rotation).amax() < 1e-12,
            "{}",
            a.name
        );
    }
}

/// ROS-Industrial's spelling: `link_1` and `Link1` in one URDF (both `Link1` in Rust). With
/// `frames: all` both are frames: the first keeps its spelling, the second gets the suffix
/// `_2`, with a note; the generated enum and functions use the same spellings.
const TWINS_URDF: &str = r#"<robot name="twins">
  <link name="base_link"/>
  <link name="link_1"><inertial><mass value="2"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="Link1"><inertial><origin xyz="0.2 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="tool0"/>
  <joint name="joint_a1" type="revolute"><parent link="base_link"/><child link="link_1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="100" velocity="2"/></joint>
  <joint name="joint_a2" type="revolute"><parent link="link_1"/><child link="Link1"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="100" velocity="2"/></joint>
  <joint name="joint_tool" type="fixed"><parent link="Link1"/><child link="tool0"/><origin xyz="0.4 0 0"/></joint>
</robot>
"#;

#[test]
fn names_spelled_alike_in_rust_are_told_apart_with_a_note() {
    let choices = Choices {
        frames: FrameSelection::AllLinks,
        ..Choices::default()
    };
    let loaded =
        load_urdf_str(TWINS_URDF, Path::new("twins.urdf"), &choices).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(names(&loaded.model), ["tool0", "link_1", "Link1"]);
    let notes: Vec<&String> = loaded.notes.iter().filter(|n| n.contains("'Link1'")).collect();
    assert_eq!(notes.len(), 1, "{:#?}", loaded.notes);
    assert!(
        notes[0].contains("frames 'link_1' and 'Link1' are both spelled `Frame::Link1` in generated code")
            && notes[0].contains("'Link1' is `Frame::Link1_2`, `link1_2` in function names"),
        "{}",
        notes[0]
    );

    let dir = dyngen_testkit::scratch::scratch_dir("twins");
    let urdf = dir.path().join("twins.urdf");
    std::fs::write(&urdf, TWINS_URDF).unwrap();
    let functions = dyngen_codegen::Functions::with(&[dyngen_codegen::FunctionGroup::Frames]).unwrap();
    let choices = Choices {
        functions: Some(functions),
        ..choices
    };
    let robot = dyngen_codegen::generate::generate_robot_with(&urdf, "twins.urdf", "Twins", "test", &choices)
        .unwrap_or_else(|e| panic!("{e}"));
    let code = &robot.code;
    for variant in ["Tool0,", "Link1,", "Link1_2,"] {
        assert_eq!(
            code.matches(&format!("    {variant}\n")).count(),
            1,
            "variant {variant}"
        );
    }
    for function in ["fn frame_pose_link_1(", "fn frame_pose_link1_2("] {
        assert!(code.contains(function), "{function}");
    }
    assert!(code.contains("Frame::Link1_2 =>"), "the match names the variant");
}
