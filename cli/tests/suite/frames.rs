//! `--frame LINK` (repeated) and `--frame all`: named frames for a bare URDF.

use crate::common;

use common::{arg, dyngen, repository_file};

#[test]
fn gen_adds_the_frames_asked_for() {
    let urdf = repository_file("robots/urdf/ur5_robot.urdf");
    let dir = tempfile::tempdir().expect("dir");
    let out = dir.path().join("ur5.rs");
    let run = dyngen(&[
        "gen",
        arg(&urdf),
        "--frame",
        "forearm_link",
        "--frame",
        "ee_link",
        "-o",
        arg(&out),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    let code = std::fs::read_to_string(&out).expect("written");
    let names = code
        .lines()
        .find(|l| l.starts_with("pub const FRAME_NAMES"))
        .expect("FRAME_NAMES");
    // The end-effector of the bare URDF is its leaf `ee_link`: listed again, it is kept once.
    assert!(names.contains(r#"["ee_link", "forearm_link"]"#), "{names}");

    let all = dyngen(&["gen", arg(&urdf), "--frame", "all", "-o", arg(&out)]);
    assert_eq!(all.code, Some(0), "{}", all.output());
    let code = std::fs::read_to_string(&out).expect("written");
    for variant in ["Tool0,", "ShoulderLink,", "Wrist3Link,", "EeLink,"] {
        assert!(code.contains(variant), "no {variant} in the Frame enum");
    }
    // Links welded to the fixed base have no frame functions.
    assert!(!code.contains("BaseLink,"));
}

#[test]
fn an_unknown_frame_is_one_line_naming_it() {
    let urdf = repository_file("robots/urdf/ur5_robot.urdf");
    let run = dyngen(&["check", arg(&urdf), "--frame", "wrist_9_link"]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.output());
    assert!(
        run.stderr.contains("frame 'wrist_9_link'") && run.stderr.contains("not defined"),
        "{}",
        run.output()
    );
}

/// `--frame-references aligned` writes the frame functions in base axes only (the others are
/// converted at run time); `all` writes each reference frame; anything else is a usage error.
#[test]
fn frame_references_choose_which_reference_frames_are_written() {
    let urdf = repository_file("robots/urdf/ur5_robot.urdf");
    let dir = tempfile::tempdir().expect("dir");
    let out = dir.path().join("ur5.rs");
    let written = |choice: &str| {
        let args = [
            "gen",
            arg(&urdf),
            "--frame",
            "all",
            "--frame-references",
            choice,
            "-o",
            arg(&out),
        ];
        let run = dyngen(&args);
        assert_eq!(run.code, Some(0), "{}", run.output());
        std::fs::read_to_string(&out).expect("written")
    };
    let aligned = written("aligned");
    assert!(aligned.contains("fn frame_jacobian_forearm_link_local_world_aligned("));
    assert!(!aligned.contains("fn frame_jacobian_forearm_link_local("));
    assert!(aligned.contains("frame_references::jacobian("));
    let all = written("all");
    assert!(all.contains("fn frame_jacobian_forearm_link_local("));
    assert!(!all.contains("frame_references::"));
    let run = dyngen(&["gen", arg(&urdf), "--frame-references", "local", "-o", arg(&out)]);
    assert_eq!(run.code, Some(2), "{}", run.output());
}
