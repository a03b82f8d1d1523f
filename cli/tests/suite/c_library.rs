//! `dyngen gen --c-library DIR`: the library's files, written only where nothing else is, and
//! a bad description or directory as one error line with nothing written. (Building and using
//! the library: `tests/downstream/tests/suite/c_library/`.)

use crate::common;

use common::{arg, broken_arm7, dyngen, repository_file};
use std::path::Path;

/// A small robot: a 2-DOF arm, generated in a fraction of a second.
fn two_dof() -> std::path::PathBuf {
    repository_file("codegen/tests/data/example-robot-data/asr_twodof_description/TwoDofs.urdf")
}

/// Every file under `dir`, relative, sorted.
fn files(dir: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut pending = vec![dir.to_owned()];
    while let Some(here) = pending.pop() {
        for entry in std::fs::read_dir(&here).expect("a directory") {
            let path = entry.expect("an entry").path();
            match path.is_dir() {
                true => pending.push(path),
                false => found.push(
                    path.strip_prefix(dir)
                        .expect("inside")
                        .to_string_lossy()
                        .replace('\\', "/"),
                ),
            }
        }
    }
    found.sort();
    found
}

#[test]
fn writes_the_library_and_rewrites_only_what_changed() {
    let dir = tempfile::tempdir().expect("temp dir");
    let library = dir.path().join("arm");
    let run = dyngen(&[
        "gen",
        arg(&two_dof()),
        "--c-library",
        arg(&library),
        "--c-prefix",
        "arm",
    ]);
    assert_eq!(run.code, Some(0), "{}", run.output());
    assert_eq!(
        files(&library),
        [
            "Cargo.toml",
            "arm_dynamics.pc",
            "arm_dynamicsConfig.cmake",
            "include/arm_dynamics.h",
            "include/dyngen.h",
            "src/lib.rs",
            "src/robot.rs",
        ]
    );
    assert!(run.stderr.contains("(7 of 7 files written)"), "{}", run.output());
    let header = std::fs::read_to_string(library.join("include/arm_dynamics.h")).expect("header");
    assert!(header.contains("int32_t arm_mass_matrix(const double *q, double *mass_matrix);"));
    let manifest = std::fs::read_to_string(library.join("Cargo.toml")).expect("manifest");
    // Without --runtime-path, the published runtime of the generator's version.
    assert!(manifest.contains("dyngen-runtime = \"=0.1.0\""), "{manifest}");

    // Again, with what cargo adds: nothing rewritten, nothing refused.
    std::fs::create_dir_all(library.join("target/debug")).expect("target");
    std::fs::write(library.join("Cargo.lock"), "# cargo's\n").expect("lock");
    let again = dyngen(&[
        "gen",
        arg(&two_dof()),
        "--c-library",
        arg(&library),
        "--c-prefix",
        "arm",
    ]);
    assert_eq!(again.code, Some(0), "{}", again.output());
    assert!(
        again.stderr.contains("(0 of 7 files written)"),
        "{}",
        again.output()
    );
}

#[test]
fn a_bad_description_is_one_error_line_and_writes_no_library() {
    let dir = tempfile::tempdir().expect("temp dir");
    let broken = broken_arm7(dir.path());
    let library = dir.path().join("broken");
    let run = dyngen(&["gen", arg(&broken), "--c-library", arg(&library)]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "exactly one line: {}", run.output());
    assert!(
        lines[0].starts_with(&format!("error: {}:", broken.display())),
        "{}",
        lines[0]
    );
    assert!(!library.exists(), "nothing written");
}

#[test]
fn a_directory_holding_other_files_is_refused_and_left_as_it_was() {
    let dir = tempfile::tempdir().expect("temp dir");
    let library = dir.path().join("project");
    std::fs::create_dir_all(library.join("src")).expect("src");
    std::fs::write(library.join("notes.txt"), "mine\n").expect("notes");
    std::fs::write(library.join("src/main.c"), "int main(void) { return 0; }\n").expect("main.c");
    let run = dyngen(&["gen", arg(&two_dof()), "--c-library", arg(&library)]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    let lines: Vec<&str> = run.stderr.lines().collect();
    assert_eq!(lines.len(), 1, "exactly one line: {}", run.output());
    let line = lines[0];
    assert!(
        line.starts_with(&format!(
            "error: {}: holds files dyngen did not write",
            library.display()
        )),
        "{line}"
    );
    assert!(
        line.contains("`notes.txt`") && line.contains("`src/main.c`"),
        "{line}"
    );
    assert_eq!(files(&library), ["notes.txt", "src/main.c"], "nothing written");
}

#[test]
fn a_file_of_the_library_written_by_hand_is_never_replaced() {
    let dir = tempfile::tempdir().expect("temp dir");
    let library = dir.path().join("arm");
    let first = dyngen(&["gen", arg(&two_dof()), "--c-library", arg(&library)]);
    assert_eq!(first.code, Some(0), "{}", first.output());
    // A person edits the header, dropping dyngen's first line.
    let header = library.join("include/twodofs_dynamics.h");
    std::fs::write(&header, "/* my header */\n").expect("edit");
    std::fs::remove_file(library.join("src/lib.rs")).expect("remove");
    let run = dyngen(&["gen", arg(&two_dof()), "--c-library", arg(&library)]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(run.stderr.contains("not generated by dyngen"), "{}", run.output());
    assert_eq!(
        std::fs::read_to_string(&header).expect("header"),
        "/* my header */\n"
    );
    assert!(
        !library.join("src/lib.rs").exists(),
        "nothing written before the refusal"
    );
}

#[test]
fn a_prefix_that_cannot_start_c_names_is_refused() {
    let dir = tempfile::tempdir().expect("temp dir");
    let library = dir.path().join("arm");
    let run = dyngen(&[
        "gen",
        arg(&two_dof()),
        "--c-library",
        arg(&library),
        "--c-prefix",
        "2arm",
    ]);
    assert_eq!(run.code, Some(1), "{}", run.output());
    assert!(
        run.stderr.contains("the prefix `2arm` cannot start C names"),
        "{}",
        run.output()
    );
    assert!(!library.exists());
    // Neither an output nor a library: a usage error.
    let usage = dyngen(&["gen", arg(&two_dof())]);
    assert_eq!(usage.code, Some(2), "{}", usage.output());
}
