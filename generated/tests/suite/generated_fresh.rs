//! The committed generated code is what the generator writes today, and the generator writes
//! the same bytes every time: across runs, processes (each with its own hash seed) and order.

use dyngen_codegen::generate::{descriptions_in, generate_into_crate, generate_robot, Mode};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
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

/// The order in which a `HashMap` with the default hasher visits `0..64`: it follows the
/// process's random hash keys, so two processes almost surely differ.
fn hash_order() -> String {
    let map: std::collections::HashMap<u32, ()> = (0..64).map(|k| (k, ())).collect();
    let order: Vec<String> = map.keys().map(u32::to_string).collect();
    format!("hash order: {}\n", order.join(","))
}

/// In the child process: print the hash order and the generated code of the robot named by
/// the environment.
#[test]
fn determinism_child() {
    if let Ok(robot) = std::env::var(CHILD) {
        print!("{}{}", hash_order(), generate(Path::new(&robot)));
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
                "generated_fresh::determinism_child",
                "--exact",
                "--nocapture",
                "--quiet",
                "--test-threads=1",
            ])
            .env(CHILD, robot)
            .output()
            .expect("child test process runs");
        let stdout = String::from_utf8_lossy(&out.stdout);
        // The child hashed with other keys than this process (else this proves less).
        let order = stdout
            .lines()
            .find(|l| l.starts_with("hash order:"))
            .expect("child output");
        assert_ne!(
            format!("{order}\n"),
            hash_order(),
            "the child process had the same hash keys"
        );
        assert!(
            stdout.contains(code.as_str()),
            "{}: the generation in a separate process differs",
            robot.display()
        );
    }
}

/// `cargo xtask gen a b` and `cargo xtask gen b a` write the same bytes (the xtask passes its
/// arguments in order to `generate_into_crate`).
#[test]
fn generation_does_not_depend_on_argument_order() {
    let robots: Vec<PathBuf> = ["arm7.yaml", "ur5.yaml"]
        .iter()
        .map(|r| root().join("robots").join(r))
        .collect();
    let reversed: Vec<PathBuf> = robots.iter().rev().cloned().collect();
    let scratch = dyngen_testkit::scratch::scratch_dir("order");
    let base = scratch.path();
    let mut trees = Vec::new();
    for (name, list) in [("forward", &robots), ("reversed", &reversed)] {
        let src = base.join(name);
        std::fs::create_dir_all(&src).expect("scratch dir");
        generate_into_crate(root(), &src, list, Mode::Write).unwrap_or_else(|e| panic!("{e}"));
        let mut files: Vec<(String, Vec<u8>)> = std::fs::read_dir(&src)
            .expect("readable")
            .map(|e| {
                let p = e.expect("entry").path();
                let name = p.file_name().expect("name").to_string_lossy().into_owned();
                (name, std::fs::read(&p).expect("readable"))
            })
            .collect();
        files.sort();
        trees.push(files);
    }
    let names: Vec<&str> = trees[0].iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["arm7.rs", "lib.rs", "ur5.rs"]);
    for ((name, a), (_, b)) in trees[0].iter().zip(&trees[1]) {
        assert!(a == b, "{name} depends on the argument order");
    }
    // And each is what is committed.
    for name in ["arm7.rs", "ur5.rs"] {
        let committed = std::fs::read(root().join("generated/src").join(name)).expect("committed");
        let generated = &trees[0].iter().find(|(n, _)| n == name).expect("generated").1;
        assert!(&committed == generated, "{name} differs from the committed file");
    }
}
