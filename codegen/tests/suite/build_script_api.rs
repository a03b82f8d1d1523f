//! The build-script API keeps the promises a build script relies on: it writes the module into
//! the output directory, rewrites it only when its content changes (so downstream crates do not
//! rebuild), never overwrites a file it did not write, reports every input it read (for
//! `cargo:rerun-if-changed`) and turns a bad description into an error a person can act on.

use dyngen_codegen::generate::{generate_robot, GenerateError, GENERATED_MARKER};
use dyngen_codegen::Builder;
use std::path::{Path, PathBuf};

fn repo(rel: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join(rel)
}

/// A fresh, empty scratch directory for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("build_script_api")
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

fn builder(description: &str, out: &Path) -> Builder {
    Builder::new(repo(description))
        .out_dir(out)
        .cargo_directives(false)
}

#[test]
fn writes_the_module_named_after_the_description_and_rewrites_only_on_change() {
    let out = scratch("rewrite");
    let file = builder("robots/ur5.yaml", &out)
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(file, out.join("ur5.rs"));
    let code = std::fs::read_to_string(&file).expect("written");
    assert!(code.starts_with(GENERATED_MARKER));
    assert!(code.contains("pub struct Ur5;"), "type named after the file");

    let stamp = std::fs::metadata(&file)
        .and_then(|m| m.modified())
        .expect("mtime");
    std::thread::sleep(std::time::Duration::from_millis(20));
    builder("robots/ur5.yaml", &out)
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    let again = std::fs::metadata(&file)
        .and_then(|m| m.modified())
        .expect("mtime");
    assert_eq!(stamp, again, "unchanged content must not touch the file");

    let renamed = builder("robots/ur5.yaml", &out)
        .module_name("arm")
        .type_name("MyArm")
        .compile()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(renamed, out.join("arm.rs"));
    assert!(std::fs::read_to_string(&renamed)
        .expect("written")
        .contains("pub struct MyArm;"));
}

#[test]
fn refuses_to_overwrite_a_file_it_did_not_write() {
    let out = scratch("foreign");
    let mine = "// my own hand-written module\npub fn keep_me() {}\n";
    std::fs::write(out.join("ur5.rs"), mine).expect("write");
    let err = builder("robots/ur5.yaml", &out)
        .compile()
        .expect_err("must refuse");
    assert!(matches!(err, GenerateError::NotGenerated { .. }), "{err:?}");
    assert!(err.to_string().contains("ur5.rs"), "{err}");
    assert_eq!(std::fs::read_to_string(out.join("ur5.rs")).expect("kept"), mine);
}

#[test]
fn bad_description_is_an_error_with_file_and_line_and_writes_nothing() {
    let out = scratch("bad");
    let description = out.join("broken.yaml");
    std::fs::write(
        &description,
        "name: broken\nlinks:\n  - name: base\n  - name: l1\n    inertial: { mass: -2.0 }\njoints: []\n",
    )
    .expect("write");
    let err = Builder::new(&description)
        .out_dir(&out)
        .cargo_directives(false)
        .compile()
        .expect_err("must fail");
    let message = err.to_string();
    assert!(message.contains("broken.yaml"), "names the file: {message}");
    assert!(
        message.contains(":5:"),
        "names the line of the bad mass: {message}"
    );
    assert!(!out.join("broken.rs").exists(), "nothing written");
}

#[test]
fn every_file_read_is_reported_for_rerun_if_changed() {
    // The Panda wrapper points at a URDF: editing either must re-run the build script.
    let robot = generate_robot(&repo("robots/panda.yaml"), "robots/panda.yaml", "Panda", "test")
        .unwrap_or_else(|e| panic!("{e}"));
    let names: Vec<String> = robot
        .sources
        .iter()
        .filter_map(|s| s.file_name().map(|n| n.to_string_lossy().into_owned()))
        .collect();
    assert!(names.contains(&"panda.yaml".to_owned()), "{names:?}");
    assert!(names.contains(&"panda.urdf".to_owned()), "{names:?}");
}

/// Each choice setter sets one field of the builder's `Choices`, so the setters give the same
/// choices in any order; `.choices(..)` sets the fields its value chooses and keeps the others,
/// before or after the setters, so no choice made earlier is dropped without a word.
#[test]
fn the_choice_setters_compose_in_any_order() {
    use dyngen_codegen::description::{
        Choices, CodeShape, ContactSpec, FrameReferences, FrameSelection, FrameSpec, NonPhysicalInertia,
    };
    use dyngen_codegen::{FunctionGroup, Functions};
    use dyngen_runtime::ContactKind;
    let foot = || ContactSpec::new("tool0", ContactKind::Point);
    let new = || Builder::new("robot.urdf");
    let one = new()
        .contact(foot())
        .floating_base()
        .frames(FrameSelection::AllLinks)
        .end_effector("tool0")
        .locked_joint("finger", 0.01)
        .gravity([0.0, 0.0, -1.62])
        .snap_angles(1e-4)
        .inertia(NonPhysicalInertia::Repair)
        .functions(&[FunctionGroup::Frames])
        .frame_references(FrameReferences::Aligned)
        .code_shape(CodeShape::Composed);
    let other = new()
        .code_shape(CodeShape::Composed)
        .frame_references(FrameReferences::Aligned)
        .functions(&[FunctionGroup::Frames])
        .inertia(NonPhysicalInertia::Repair)
        .snap_angles(1e-4)
        .gravity([0.0, 0.0, -1.62])
        .locked_joint("finger", 0.01)
        .end_effector(FrameSpec::link("tool0"))
        .frames(FrameSelection::AllLinks)
        .floating_base()
        .contact(foot());
    assert_eq!(one.chosen(), other.chosen());
    let expected = Choices {
        end_effector: Some(FrameSpec::link("tool0")),
        frames: FrameSelection::AllLinks,
        locked_joints: vec![("finger".into(), 0.01)],
        gravity: Some([0.0, 0.0, -1.62]),
        snap_angles: Some(1e-4),
        inertia: NonPhysicalInertia::Repair,
        floating_base: true,
        joint_parameters: None,
        functions: Some(Functions::with(&[FunctionGroup::Frames]).unwrap()),
        contacts: vec![foot()],
        frame_references: FrameReferences::Aligned,
        code_shape: CodeShape::Composed,
    };
    assert_eq!(one.chosen(), &expected);

    // A whole value, before or after field setters, keeps what it does not choose.
    let whole = Choices {
        gravity: Some([0.0, 0.0, -1.62]),
        snap_angles: Some(1e-4),
        ..Choices::default()
    };
    let before = new()
        .choices(whole.clone())
        .floating_base()
        .frames(FrameSelection::AllLinks);
    let after = new()
        .floating_base()
        .frames(FrameSelection::AllLinks)
        .choices(whole);
    assert_eq!(before.chosen(), after.chosen());
    assert_eq!(
        after.chosen().chosen_keys(),
        ["frames", "gravity", "snap_angles", "floating_base"]
    );
}
