//! `dyngen excite --box/--above`: the written trajectory keeps the frames in their regions;
//! malformed regions are usage errors, unknown frames, empty boxes and unreachable regions
//! are one error line.

use crate::common;

use common::{arg, dyngen, repository_file};
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_identify::read_csv;

#[test]
fn excite_keeps_the_flange_in_a_box_and_above_a_table() {
    let dir = tempfile::tempdir().expect("temp dir");
    let description = repository_file("robots/arm7.yaml");
    let trajectory = dir.path().join("excitation.csv");
    let run = dyngen(&[
        "excite",
        arg(&description),
        "-o",
        arg(&trajectory),
        "--duration",
        "10",
        "--rate=100",
        "--iterations",
        "20",
        "--box",
        "flange:-0.8,-0.8,0.3,0.8,0.8,1.5",
        "--above",
        "0,0,1,0.45",
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert!(
        run.stdout.contains("workspace: every frame inside"),
        "{}",
        run.output()
    );
    let model = load(&description).unwrap_or_else(|e| panic!("{e}")).model;
    let samples = read_csv(&trajectory, &model, false).unwrap_or_else(|e| panic!("{e}"));
    let dynamics = NumericDynamics::new(&model);
    for q in &samples.q {
        let p = dynamics.end_effector_pose(q).1;
        assert!(p.z >= 0.45 && p.z <= 1.5, "flange at {p:?}");
        assert!(p.x.abs() <= 0.8 && p.y.abs() <= 0.8, "flange at {p:?}");
    }
}

#[test]
fn bad_regions_are_errors() {
    let arm7 = repository_file("robots/arm7.yaml");
    let excite = |region: &[&str]| {
        let mut args = vec!["excite", arg(&arm7), "-o", "never.csv", "--iterations", "2"];
        args.extend_from_slice(region);
        dyngen(&args)
    };
    for (region, said) in [
        (["--box", "1,2,3"], "expected 6 comma-separated numbers, got 3"),
        (["--above", "0,0,1,x"], "'x' is not a finite number"),
        (["--above", ":0,0,1,0"], "the frame name before ':' is empty"),
    ] {
        let run = excite(&region);
        assert_eq!(run.code, Some(2), "{region:?}: {}", run.output());
        assert!(run.stderr.contains(said), "{region:?}: {}", run.output());
    }
    for (region, said) in [
        (
            ["--above", "gripper:0,0,1,0"],
            "error: the robot has no frame 'gripper'; its frames: flange",
        ),
        (
            ["--box", "0,0,1,0.5,0.5,0.9"],
            "error: the box of frame 'flange' is empty along z",
        ),
        (
            ["--above", "0,0,1,3"],
            "error: no excitation satisfies the workspace constraints: no posture",
        ),
    ] {
        let run = excite(&region);
        assert_eq!(run.code, Some(1), "{region:?}: {}", run.output());
        assert!(run.stderr.starts_with(said), "{region:?}: {}", run.output());
    }
}
