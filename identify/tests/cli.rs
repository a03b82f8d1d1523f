//! The `dyngen-identify` binary end to end: `excite` writes a trajectory within the limits,
//! `identify` reads data and writes a description that loads; bad data is one error line.

mod common;

use dyngen_codegen::description::load;
use dyngen_identify::data::{read_csv, to_csv};
use std::path::PathBuf;
use std::process::Command;

fn run(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_dyngen-identify"))
        .args(args)
        .output()
        .expect("runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn excite_then_identify_then_load() {
    let dir: PathBuf = std::env::temp_dir().join(format!("dyngen-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let robots = concat!(env!("CARGO_MANIFEST_DIR"), "/../robots/arm7.yaml");
    let description = dir.join("arm7_joint.yaml");
    let text = std::fs::read_to_string(robots).expect("arm7.yaml")
        + "joint_parameters:\n  columns: [armature, viscous, coulomb, offset]\n";
    std::fs::write(&description, text).expect("write");
    let nominal = load(&description).unwrap_or_else(|e| panic!("{e}")).model;
    let trajectory = dir.join("excitation.csv");
    let (ok, stdout, stderr) = run(&[
        "excite",
        description.to_str().expect("utf-8"),
        trajectory.to_str().expect("utf-8"),
        "--duration",
        "10",
        "--rate",
        "100",
        "--iterations",
        "20",
    ]);
    assert!(ok, "{stdout}{stderr}");
    assert!(stdout.contains("condition number"), "{stdout}");
    // The written trajectory passes the reader's limit checks (positions and velocities).
    let excitation = read_csv(&trajectory, &nominal, false).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(excitation.len(), 1000);
    // Measure the "real" robot along it (exact derivatives from the file, noisy torques).
    let truth = common::arm7_truth();
    let noise = common::arm7_noise(&truth);
    let dynamics = dyngen_codegen::dynamics::NumericDynamics::new(&truth);
    let mut data = excitation.clone();
    let (qd, qdd) = (
        excitation.qd.as_ref().expect("qd"),
        excitation.qdd.as_ref().expect("qdd"),
    );
    let mut rng = dyngen_runtime::SplitMix64::new(9);
    data.tau = Some(
        (0..excitation.len())
            .map(|k| {
                let tau = dynamics.inverse_dynamics(&excitation.q[k], &qd[k], &qdd[k]);
                tau.iter()
                    .zip(&noise)
                    .map(|(t, s)| t + s * dyngen_identify::excitation::normal(&mut rng))
                    .collect()
            })
            .collect(),
    );
    let data_path = dir.join("data.csv");
    std::fs::write(&data_path, to_csv(&nominal, &data)).expect("write data");
    let identified = dir.join("identified.yaml");
    let (ok, stdout, stderr) = run(&[
        "identify",
        description.to_str().expect("utf-8"),
        data_path.to_str().expect("utf-8"),
        "--out",
        identified.to_str().expect("utf-8"),
    ]);
    assert!(ok, "{stdout}{stderr}");
    assert!(
        stdout.contains("Ia[joint7]"),
        "prints the base parameters: {stdout}"
    );
    let model = load(&identified).unwrap_or_else(|e| panic!("{e}")).model;
    assert_eq!(model.parameter_count(), 98);
    // Bad data: one error line naming file, line and column, and a failure status.
    let bad = dir.join("bad.csv");
    let text = std::fs::read_to_string(&data_path).expect("data");
    std::fs::write(&bad, text.replacen("q[joint3]", "q[joint33]", 1)).expect("write");
    let (ok, _, stderr) = run(&[
        "identify",
        description.to_str().expect("utf-8"),
        bad.to_str().expect("utf-8"),
    ]);
    assert!(!ok);
    assert!(
        stderr.starts_with(&format!(
            "error: {}:1: column 4 (q[joint33]): unknown joint 'joint33'",
            bad.display()
        )),
        "{stderr}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
