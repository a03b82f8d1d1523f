//! Warnings reach the person building: `cargo:warning=` lines from a build script (the
//! `Builder` API), one per warning, with file, place and problem.

use std::process::Command;

const CHILD: &str = "DYNGEN_BUILD_SCRIPT_CHILD";

/// In the child process: what a build script does.
#[test]
fn build_script_child() {
    if let Ok(out) = std::env::var(CHILD) {
        dyngen_codegen::Builder::new("tests/data/warn/warnings.yaml")
            .out_dir(out)
            .compile()
            .expect("generates");
    }
}

#[test]
fn build_script_prints_each_warning() {
    let scratch = dyngen_testkit::scratch::scratch_dir("warn");
    let out = scratch.path();
    let run = Command::new(std::env::current_exe().expect("test binary"))
        .args([
            "warnings_reported::build_script_child",
            "--exact",
            "--nocapture",
            "--quiet",
            "--test-threads=1",
        ])
        .env(CHILD, out)
        .output()
        .expect("child runs");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let stdout = String::from_utf8_lossy(&run.stdout);
    let warnings: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("cargo:warning="))
        .collect();
    let file = "cargo:warning=tests/data/warn/warnings.yaml";
    for expected in [
        ":11:13: link 'lower': mass 20000 kg is more than 10000 kg",
        ":26:12: joint 'elbow': lower and upper limits are both 0",
        ":26:12: joint 'elbow': velocity limit is 0",
        ":31:13: joint 'flag_joint': origin [0, 0, 250] is more than 100 m away",
        ":8:5: link 'flag': zero mass and no children",
    ] {
        assert!(
            warnings
                .iter()
                .any(|w| w.starts_with(&format!("{file}{expected}"))),
            "no `{file}{expected}` in {warnings:#?}"
        );
    }
    assert_eq!(warnings.len(), 5, "{warnings:#?}");
    assert!(out.join("warnings.rs").is_file());
}
