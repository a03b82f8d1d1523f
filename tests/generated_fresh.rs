//! The committed generated code is what the generator writes today, and the generator writes
//! the same bytes every time: across runs, processes (each with its own hash seed) and order.

use dyngen_codegen::generate::{descriptions_in, generate_into_crate, generate_robot, Mode};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn robots() -> Vec<PathBuf> {
    descriptions_in(&root().join("robots")).expect("robots/ is readable")
}

#[test]
fn committed_generated_code_is_fresh() {
    let report = generate_into_crate(root(), &root().join("generated/src"), &robots(), Mode::Check)
        .unwrap_or_else(|e| panic!("{e}"));
    let stale = report.changed();
    assert!(
        stale.is_empty(),
        "stale generated code, run `cargo xtask gen --all`: {stale:?}"
    );
    assert_eq!(report.robots.len(), robots().len());
}

const CHILD: &str = "DYNGEN_DETERMINISM_CHILD";

fn generate(path: &Path) -> String {
    generate_robot(path, "robots/x", "Robot", "cargo xtask gen robots/x")
        .unwrap_or_else(|e| panic!("{e}"))
        .code
}

/// In the child process: print the generated code of the robot named by the environment.
#[test]
fn determinism_child() {
    if let Ok(robot) = std::env::var(CHILD) {
        print!("{}", generate(Path::new(&robot)));
    }
}

#[test]
fn generation_is_byte_identical_across_processes_and_order() {
    let robots = robots();
    // Reverse order in this process: nothing may depend on what was generated before.
    let here: Vec<String> = robots.iter().rev().map(|r| generate(r)).rev().collect();
    for (robot, code) in robots.iter().zip(&here) {
        assert_eq!(
            code,
            &generate(robot),
            "{}: two runs in one process differ",
            robot.display()
        );
        let out = Command::new(std::env::current_exe().expect("test binary"))
            .args([
                "determinism_child",
                "--exact",
                "--nocapture",
                "--quiet",
                "--test-threads=1",
            ])
            .env(CHILD, robot)
            .output()
            .expect("child test process runs");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(
            stdout.contains(code.as_str()),
            "{}: the generation in a separate process differs",
            robot.display()
        );
    }
}
