//! `dyngen check`, `dyngen info` and `dyngen urdf`: loading, reporting and exporting without
//! generating a file.

use crate::common;

use common::{arg, broken_arm7, dyngen, repository_file};
use dyngen_codegen::description::load;

#[test]
fn check_exit_codes() {
    let arm7 = repository_file("robots/arm7.yaml");
    let ok = dyngen(&["check", arg(&arm7)]);
    assert_eq!(ok.code, Some(0), "{}", ok.output());
    assert!(ok.stderr.contains("7 DOF"), "{}", ok.output());
    // arm7 loads without warnings, so denying them changes nothing.
    let strict = dyngen(&["check", arg(&arm7), "--deny-warnings"]);
    assert_eq!(strict.code, Some(0), "{}", strict.output());

    let dir = tempfile::tempdir().expect("temp dir");
    let broken = broken_arm7(dir.path());
    let bad = dyngen(&["check", arg(&broken)]);
    assert_eq!(bad.code, Some(1), "{}", bad.output());
    assert!(
        bad.stderr.starts_with(&format!("error: {}:", broken.display())),
        "{}",
        bad.output()
    );

    // Vendor URDF files write 1.5708 for a quarter turn: a warning, which --deny-warnings
    // turns into a failure.
    let xarm = repository_file("codegen/tests/data/example-robot-data/xarm_description/xarm7.urdf");
    let warned = dyngen(&["check", arg(&xarm)]);
    assert_eq!(warned.code, Some(0), "{}", warned.output());
    assert!(
        warned.stderr.contains("warning:"),
        "xarm7 has near-quarter turns: {}",
        warned.output()
    );
    let denied = dyngen(&["check", arg(&xarm), "--deny-warnings"]);
    assert_eq!(denied.code, Some(1), "{}", denied.output());
    // Snapping them away leaves nothing to deny... except what snapping itself reports.
    let snapped = dyngen(&["check", arg(&xarm), "--snap-angles=1e-4"]);
    assert_eq!(snapped.code, Some(0), "{}", snapped.output());
    // A choice a YAML description makes itself, made again on the command line, is an error
    // naming the key, never ignored; one it leaves open is the flag's.
    let rounded = repository_file("robots/panda_rounded.yaml");
    let mixed = dyngen(&["check", arg(&rounded), "--snap-angles", "1e-4"]);
    assert_eq!(mixed.code, Some(1), "{}", mixed.output());
    assert!(
        mixed.stderr.contains("`snap_angles` was chosen twice"),
        "{}",
        mixed.output()
    );
    let open = dyngen(&["check", arg(&arm7), "--snap-angles", "1e-4"]);
    assert_eq!(open.code, Some(0), "{}", open.output());
}

#[test]
fn info_names_joints_parameters_and_base_parameters() {
    let twodof = repository_file("codegen/tests/data/example-robot-data/asr_twodof_description/TwoDofs.urdf");
    let run = dyngen(&["info", arg(&twodof)]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    let model = load(&twodof).expect("loads").model;
    assert!(
        run.stdout.contains(&format!("DOF: {}", model.dof())),
        "{}",
        run.stdout
    );
    for joint in model.joints() {
        assert!(
            run.stdout.contains(&joint.name),
            "names joint {}: {}",
            joint.name,
            run.stdout
        );
    }
    // The base parameters as the generated module names them.
    let base = dyngen_codegen::base_parameters::BaseParameterSet::compute(&model);
    assert!(!base.names.is_empty());
    assert!(
        run.stdout
            .contains(&format!("base parameters ({}):", base.names.len())),
        "{}",
        run.stdout
    );
    for name in &base.names {
        assert!(
            run.stdout.contains(&format!("  {name}\n")),
            "lists {name}: {}",
            run.stdout
        );
    }
    for function in ["inverse_dynamics", "mass_matrix", "base_regressor"] {
        assert!(
            run.stdout.contains(function),
            "operations of {function}: {}",
            run.stdout
        );
    }
}

#[test]
fn urdf_export_loads_back_as_the_same_model() {
    let dir = tempfile::tempdir().expect("temp dir");
    let arm7 = repository_file("robots/arm7.yaml");
    let exported = dir.path().join("arm7.urdf");
    let run = dyngen(&["urdf", arg(&arm7), "-o", arg(&exported)]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(run.stderr.contains("7 DOF"), "{}", run.output());
    let original = load(&arm7).expect("arm7").model;
    let back = load(&exported).unwrap_or_else(|e| panic!("{e}")).model;
    assert_eq!(back.dof(), original.dof());
    assert_eq!(back.end_effector().name, original.end_effector().name);
    let names =
        |m: &dyngen_codegen::model::Model| m.joints().iter().map(|j| j.name.clone()).collect::<Vec<_>>();
    assert_eq!(names(&back), names(&original));
    let (a, b) = (back.parameters(), original.parameters());
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!(
            (x - y).abs() <= 1e-9 * (1.0 + y.abs()),
            "inertial parameters survive: {x} vs {y}"
        );
    }
    // Without -o, the URDF goes to stdout.
    let stdout = dyngen(&["urdf", arg(&arm7)]);
    assert_eq!(stdout.code, Some(0), "{}", stdout.output());
    assert!(stdout.stdout.starts_with("<?xml"), "{}", stdout.output());
}

#[test]
fn a_floating_base_is_reported_and_refused_where_it_is_not_supported() {
    let solo = repository_file("robots/solo12.yaml");
    let info = dyngen(&["info", arg(&solo)]);
    assert_eq!(info.code, Some(0), "{}", info.output());
    assert!(
        info.stdout
            .contains("floating base: body 'base_link' (nq = 19, nv = 18"),
        "{}",
        info.output()
    );
    assert!(
        info.stdout
            .contains("parameters (130):\n  m[base_link], mcx[base_link]"),
        "{}",
        info.output()
    );
    assert!(
        info.stdout
            .contains("base parameters (94):\n  m[base_link] + m[FL_SHOULDER]"),
        "{}",
        info.output()
    );
    assert!(
        info.stdout.contains("centroidal_momentum_matrix"),
        "{}",
        info.output()
    );
    // A bare URDF takes the option; identification refuses the robot in one line.
    let urdf = repository_file("robots/urdf/solo12.urdf");
    let dir = tempfile::tempdir().expect("temp dir");
    let out = dir.path().join("solo.rs");
    let generated = dyngen(&["gen", arg(&urdf), "--floating-base", "-o", arg(&out)]);
    assert_eq!(generated.code, Some(0), "{}", generated.output());
    assert!(
        generated.stderr.contains(
            "12 DOF on a floating base, 130 parameters (the base body's first), 94 base parameters"
        ),
        "{}",
        generated.output()
    );
    let code = std::fs::read_to_string(&out).expect("generated file");
    assert!(
        code.contains("impl FloatingBaseDynamics<12, 18, 130> for Solo"),
        "{}",
        &code[..2000]
    );
    let excite = dyngen(&["excite", arg(&solo), "-o", arg(&dir.path().join("x.csv"))]);
    assert_eq!(excite.code, Some(1), "{}", excite.output());
    assert!(
        excite
            .stderr
            .contains("identification of a floating-base robot is not supported yet"),
        "{}",
        excite.output()
    );
}

/// `--lock` and `--gravity` choose `locked_joints` and `gravity` for a bare URDF, as the YAML
/// keys do: the locked joint leaves the model; a malformed value is a usage error (exit 2), a
/// key a YAML file writes too is refused.
#[test]
fn lock_and_gravity_flags_are_the_yaml_keys() {
    let xarm = repository_file("robots/urdf/xarm7.urdf");
    let dir = tempfile::tempdir().expect("temp dir");
    let exported = dir.path().join("locked.urdf");
    let run = dyngen(&[
        "urdf",
        arg(&xarm),
        "--lock",
        "joint7=0.25",
        "--gravity",
        "0,0,-1.62",
        "-o",
        arg(&exported),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    let model = load(&exported).unwrap_or_else(|e| panic!("{e}")).model;
    assert_eq!(model.dof(), 6, "joint7 locked");
    assert!(model.joints().iter().all(|j| j.name != "joint7"));
    let unlocked = load(&xarm).expect("xarm7").model;
    assert_eq!(unlocked.dof(), 7);

    for (flag, value) in [
        ("--lock", "joint7"),
        ("--lock", "joint7=x"),
        ("--gravity", "0,-9.81"),
    ] {
        let bad = dyngen(&["check", arg(&xarm), flag, value]);
        assert_eq!(bad.code, Some(2), "{flag} {value}: {}", bad.output());
    }
    // robots/ur5.yaml writes `gravity:`; the flag may not choose it again.
    let ur5 = repository_file("robots/ur5.yaml");
    let twice = dyngen(&["check", arg(&ur5), "--gravity", "0,0,-9.81"]);
    assert_eq!(twice.code, Some(1), "{}", twice.output());
    assert!(
        twice.stderr.contains("`gravity` was chosen twice"),
        "{}",
        twice.output()
    );
}
