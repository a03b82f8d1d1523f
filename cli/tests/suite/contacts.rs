//! `--contact FRAME:KIND[:AXES]` (repeated): frames held to the world, for a bare URDF.

use crate::common;

use common::{arg, dyngen, repository_file};

#[test]
fn gen_holds_the_frames_asked_for() {
    let urdf = repository_file("robots/urdf/ur5_robot.urdf");
    let dir = tempfile::tempdir().expect("dir");
    let out = dir.path().join("ur5.rs");
    let run = dyngen(&[
        "gen",
        arg(&urdf),
        "--floating-base",
        "--frame",
        "forearm_link",
        "--contact",
        "ee_link:frame",
        "--contact",
        "forearm_link:point:local_world_aligned",
        "-o",
        arg(&out),
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    let code = std::fs::read_to_string(&out).expect("written");
    // Six rows for the held end-effector, three for the forearm's point.
    assert!(
        code.contains("impl ContactDynamics<12, 9> for"),
        "no ContactDynamics<12, 9>"
    );
    for needle in [
        "ContactKind::Frame",
        "ContactKind::Point",
        "ReferenceFrame::Local,",
        "ReferenceFrame::LocalWorldAligned",
    ] {
        assert!(code.contains(needle), "no {needle}");
    }
}

#[test]
fn a_bad_contact_is_one_line_naming_it() {
    let urdf = repository_file("robots/urdf/ur5_robot.urdf");
    for (flag, expected) in [
        ("ee_link:edge", "contact kind `edge`"),
        ("ee_link", "expected FRAME:KIND[:AXES]"),
        ("ee_link:point:global", "contact axes `global`"),
        ("wrist_9_link:point", "wrist_9_link"),
        ("ee_link:frame", "nothing would be left to move"),
    ] {
        let run = dyngen(&["check", arg(&urdf), "--contact", flag]);
        assert_ne!(run.code, Some(0), "{flag}: {}", run.output());
        assert!(run.stderr.contains(expected), "{flag}: {}", run.output());
        // Mistakes in the flag itself are clap's usage errors; mistakes against the robot, one line.
        if flag.starts_with("wrist") || flag == "ee_link:frame" {
            assert_eq!(run.stderr.lines().count(), 1, "{}", run.output());
        }
    }
}
