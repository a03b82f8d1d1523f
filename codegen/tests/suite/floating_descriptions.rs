//! Floating bases in descriptions: the key in YAML and the URDF option give the same model, the
//! root link and what is welded to it become the base body, a fixed base is what it always was,
//! frames ride on the base body too, joint-level parameters and mimic joints mean what they mean
//! on a fixed base (and are refused together at the same key), and the model written as URDF
//! loads back as itself.

use dyngen_codegen::description::{self, to_urdf_rs, Choices, FrameSelection, FrameSpec};
use dyngen_codegen::dynamics::FloatingDynamics;
use dyngen_codegen::model::Inertia;
use dyngen_runtime::ReferenceFrame;
use dyngen_testkit::workspace_root;
use std::path::Path;

const ROBOT: &str = r#"
name: hopper
floating_base: true
end_effector: foot
links:
  - { name: trunk, inertial: { mass: 4.0, origin: { xyz: [0.02, 0, 0] }, inertia: { ixx: 0.05, ixy: 0, ixz: 0, iyy: 0.08, iyz: 0, izz: 0.07 } } }
  - { name: imu, inertial: { mass: 0.1, origin: { xyz: [0, 0.01, 0] }, inertia: { ixx: 1e-5, ixy: 0, ixz: 0, iyy: 1e-5, iyz: 0, izz: 1e-5 } } }
  - { name: thigh, inertial: { mass: 1.0, origin: { xyz: [0, 0, -0.1] }, inertia: { ixx: 0.01, ixy: 0, ixz: 0, iyy: 0.01, iyz: 0, izz: 0.001 } } }
  - { name: shank, inertial: { mass: 0.5, origin: { xyz: [0, 0, -0.1] }, inertia: { ixx: 0.004, ixy: 0, ixz: 0, iyy: 0.004, iyz: 0, izz: 0.0005 } } }
  - { name: foot }
joints:
  - { name: imu_mount, type: fixed, parent: trunk, child: imu, origin: { xyz: [0.1, 0, 0.05] } }
  - name: hip
    type: revolute
    parent: trunk
    child: thigh
    origin: { xyz: [0, 0, -0.05] }
    axis: [0, 1, 0]
    limit: { lower: -1.5, upper: 1.5, effort: 20, velocity: 10 }
  - name: knee
    type: revolute
    parent: thigh
    child: shank
    origin: { xyz: [0, 0, -0.2] }
    axis: [0, 1, 0]
    limit: { lower: -2.5, upper: 0, effort: 20, velocity: 10 }
  - { name: ankle, type: fixed, parent: shank, child: foot, origin: { xyz: [0, 0, -0.2] } }
"#;

#[test]
fn the_root_link_and_what_is_welded_to_it_are_the_base_body() {
    let model = description::load_yaml_str(ROBOT, Path::new("hopper.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let base = model.floating_base().expect("a floating base");
    assert_eq!(base.name, "trunk");
    assert_eq!((model.dof(), model.nq(), model.nv()), (2, 9, 8));
    assert!(
        (base.inertia.mass - 4.1).abs() < 1e-12,
        "trunk and imu: {}",
        base.inertia.mass
    );
    let imu = Inertia {
        mass: 0.1,
        com: [0.1, 0.01, 0.05].into(),
        inertia_com: nalgebra::Matrix3::from_diagonal_element(1e-5),
    };
    let trunk = Inertia {
        mass: 4.0,
        com: [0.02, 0.0, 0.0].into(),
        inertia_com: nalgebra::Matrix3::from_diagonal(&[0.05, 0.08, 0.07].into()),
    };
    assert_eq!(base.inertia, trunk.merged(&imu));
    // The same robot on a fixed base drops the trunk and has nothing else changed.
    let fixed = description::load_yaml_str(
        &ROBOT.replace("floating_base: true\n", ""),
        Path::new("hopper.yaml"),
    )
    .unwrap()
    .model;
    assert!(fixed.floating_base().is_none());
    assert_eq!((fixed.nq(), fixed.nv()), (2, 2));
    assert_eq!(fixed.joints(), model.joints());
    assert_eq!(fixed.bodies(), model.bodies());
}

#[test]
fn the_urdf_option_and_the_yaml_key_give_the_same_model() {
    let urdf = workspace_root().join("robots/urdf/solo12.urdf");
    let options = Choices {
        floating_base: true,
        end_effector: Some(FrameSpec::link("FL_FOOT")),
        frames: FrameSelection::Listed(
            ["FR_FOOT", "HL_FOOT", "HR_FOOT", "base_link"]
                .map(FrameSpec::link)
                .to_vec(),
        ),
        ..Choices::default()
    };
    let from_urdf = description::load_with(&urdf, &options).unwrap_or_else(|e| panic!("{e}"));
    let from_yaml =
        description::load(&workspace_root().join("robots/solo12.yaml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        from_urdf.model.floating_base().map(|b| b.name.as_str()),
        Some("base_link")
    );
    let (a, b) = (&from_yaml.model, &from_urdf.model);
    assert_eq!(a.name(), "solo12", "the YAML names it; the URDF says `solo`");
    assert_eq!(
        (a.joints(), a.bodies(), a.frames()),
        (b.joints(), b.bodies(), b.frames())
    );
    assert_eq!(a.floating_base(), b.floating_base());
}

#[test]
fn joint_parameters_and_mimic_joints_mean_on_a_floating_base_what_they_mean_on_a_fixed_one() {
    let with_friction = ROBOT.replace(
        "floating_base: true\n",
        "floating_base: true\njoint_parameters: { columns: [viscous], joints: { knee: { viscous: 0.4 } } }\n",
    );
    let load = |text: &str| description::load_yaml_str(text, Path::new("hopper.yaml"));
    let floating = load(&with_friction).unwrap_or_else(|e| panic!("{e}")).model;
    let fixed = load(&with_friction.replace("floating_base: true\n", ""))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    assert_eq!(floating.joint_terms(), fixed.joint_terms());
    let names = FloatingDynamics::parameter_names(&floating);
    assert_eq!(names.len(), 10 + fixed.parameter_count());
    assert_eq!(
        names[10..],
        fixed.parameter_names()[..],
        "the base body's ten, then the fixed base's"
    );
    assert_eq!(names.last().map(String::as_str), Some("fv[knee]"));
    // A mimic joint with joint-level parameters: refused at the same key on either base.
    let knee = "    limit: { lower: -2.5, upper: 0, effort: 20, velocity: 10 }\n  - { name: ankle";
    let mimic = with_friction.replace(
        knee,
        &knee.replace(
            "\n  - { name: ankle",
            "\n    mimic: { joint: hip, multiplier: -1.0 }\n  - { name: ankle",
        ),
    );
    assert_ne!(mimic, with_friction);
    for text in [mimic.clone(), mimic.replace("floating_base: true\n", "")] {
        let err = load(&text).unwrap_err().to_string();
        assert!(
            err.contains("joint_parameters") || err.contains("joint-level"),
            "{err}"
        );
        assert!(err.contains("mimic"), "{err}");
    }
}

#[test]
fn a_floating_model_written_as_urdf_loads_back_as_itself() {
    let with_imu = ROBOT.replace("end_effector: foot\n", "end_effector: foot\nframes: [imu]\n");
    let model = description::load_yaml_str(&with_imu, Path::new("hopper.yaml"))
        .unwrap()
        .model;
    let export = to_urdf_rs(&model).unwrap_or_else(|e| panic!("{e}"));
    assert!(export.choices.floating_base);
    assert!(export.needs_wrapper());
    assert!(export
        .yaml_wrapper("hopper.urdf")
        .contains("floating_base: true\n"));
    assert!(
        export.warnings.iter().any(|w| w.contains("floats")),
        "{:?}",
        export.warnings
    );
    let back = description::from_urdf_rs(&export.robot, &export.choices).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        back.model.floating_base().map(|b| &b.name),
        model.floating_base().map(|b| &b.name)
    );
    let (a, b) = (
        &back.model.floating_base().unwrap().inertia,
        &model.floating_base().unwrap().inertia,
    );
    assert!((a.mass - b.mass).abs() < 1e-12 && (a.com - b.com).amax() < 1e-12);
    assert!((a.inertia_com - b.inertia_com).amax() < 1e-12);
    assert_eq!(back.model.joints().len(), model.joints().len());
    // The IMU stays on the base body, at its place.
    let imu = &back.model.frames()[1];
    assert_eq!((imu.name.as_str(), imu.parent), ("imu", None));
    assert!((imu.placement.translation - model.frames()[1].placement.translation).amax() < 1e-12);
}

#[test]
fn a_frame_on_the_floating_base_body_rides_with_the_base() {
    let on_base = ROBOT.replace(
        "end_effector: foot\n",
        "end_effector: foot\nframes: [imu, { name: gps, link: trunk, xyz: [0, 0, 0.2] }]\n",
    );
    let model = description::load_yaml_str(&on_base, Path::new("hopper.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model;
    let (imu, gps) = (&model.frames()[1], &model.frames()[2]);
    assert_eq!((imu.parent, gps.parent), (None, None));
    assert_eq!(imu.placement.translation, nalgebra::Vector3::new(0.1, 0.0, 0.05));
    assert_eq!(gps.placement.translation, nalgebra::Vector3::new(0.0, 0.0, 0.2));
    // On the base body a frame's pose is the base pose composed with its placement, and its
    // Jacobian has the base's columns only.
    let dynamics = FloatingDynamics::new(&model).unwrap();
    let q = [0.3, -0.2, 1.0, 0.0, 0.0, 0.6, 0.8, 0.4, -0.9];
    let s = dynamics.state(&q).unwrap();
    let (rotation, translation) = dynamics.frame_pose(&s, 1);
    let base = s.base();
    assert!((rotation - base.rotation).amax() < 1e-15);
    let expected = base.position + base.rotation * nalgebra::Vector3::new(0.1, 0.0, 0.05);
    assert!((translation - expected).amax() < 1e-15);
    let local = dynamics.frame_jacobian(&s, 1, ReferenceFrame::Local);
    assert!(local.columns(6, 2).iter().all(|&x| x == 0.0));
    // In its own axes: the base's linear columns, and the base's rotation moving it at r × ω.
    let expected = nalgebra::DMatrix::from_row_slice(
        6,
        6,
        &[
            1.0, 0.0, 0.0, 0.0, 0.05, 0.0, //
            0.0, 1.0, 0.0, -0.05, 0.0, 0.1, //
            0.0, 0.0, 1.0, 0.0, -0.1, 0.0, //
            0.0, 0.0, 0.0, 1.0, 0.0, 0.0, //
            0.0, 0.0, 0.0, 0.0, 1.0, 0.0, //
            0.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ],
    );
    assert!((local.columns(0, 6) - expected).amax() < 1e-15, "{local}");
}

#[test]
fn the_end_effector_on_the_floating_base_body_is_refused_with_what_it_is() {
    let on_base = ROBOT.replace("end_effector: foot\n", "end_effector: imu\n");
    let err = description::load_yaml_str(&on_base, Path::new("hopper.yaml"))
        .unwrap_err()
        .to_string();
    assert!(err.starts_with("hopper.yaml:4:"), "{err}");
    assert!(
        err.contains("link 'imu' is part of the floating base body: the end-effector must ride"),
        "{err}"
    );
}

/// A floating robot with mimic joints, and one with joint-level parameters, written as URDF
/// (with the wrapper's choices) load back with the same couplings and terms.
#[test]
fn floating_models_with_mimic_joints_or_joint_parameters_written_as_urdf_load_back() {
    for description in ["mimic/floating_gripper.yaml", "floating/hopper_friction.yaml"] {
        let path = workspace_root().join("codegen/tests/data").join(description);
        let model = description::load(&path).unwrap_or_else(|e| panic!("{e}")).model;
        let export = to_urdf_rs(&model).unwrap_or_else(|e| panic!("{description}: {e}"));
        let back = description::from_urdf_rs(&export.robot, &export.choices)
            .unwrap_or_else(|e| panic!("{description}: {e}"))
            .model;
        assert!(back.floating_base().is_some(), "{description}");
        assert_eq!(back.mimics(), model.mimics(), "{description}");
        assert_eq!(back.joint_terms(), model.joint_terms(), "{description}");
        assert_eq!(
            FloatingDynamics::parameter_names(&back),
            FloatingDynamics::parameter_names(&model),
            "{description}"
        );
    }
}
