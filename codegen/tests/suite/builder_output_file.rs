//! `Builder::output_file`, the way a command-line tool writes one module where its user asks:
//! exactly that file, the module and type named after it, the header naming the command that
//! regenerates it, and the same safe write as into `OUT_DIR` (never over a file a person wrote).

use dyngen_codegen::generate::{GenerateError, WriteOutcome, GENERATED_MARKER};
use dyngen_codegen::Builder;
use std::path::{Path, PathBuf};

fn twodof() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/example-robot-data/asr_twodof_description/TwoDofs.urdf")
}

/// A fresh, empty scratch directory for one test.
fn scratch(test: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("builder_output_file")
        .join(test);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch directory");
    dir
}

#[test]
fn writes_exactly_the_given_file_named_after_it() {
    let dir = scratch("named");
    let file = dir.join("two_arm.rs");
    let report = Builder::new(twodof())
        .output_file(&file)
        .regenerate_command("dyngen gen TwoDofs.urdf -o two_arm.rs")
        .cargo_directives(false)
        .compile_report()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(report.file, file);
    assert_eq!(report.module, "two_arm");
    assert_eq!(report.outcome, WriteOutcome::Written);
    let code = std::fs::read_to_string(&file).expect("written");
    assert!(code.starts_with(GENERATED_MARKER));
    assert!(code.contains("pub struct TwoArm;"), "type named after the file");
    assert!(
        code.contains("dyngen gen TwoDofs.urdf -o two_arm.rs"),
        "the header's command"
    );
    let entries = std::fs::read_dir(&dir).expect("dir").count();
    assert_eq!(entries, 1, "nothing else written beside it");
    // What a tool reports: names and counts agree with the module it wrote.
    let robot = &report.robot;
    assert_eq!(robot.base_parameter_names.len(), robot.base_parameter_count);
    for name in &robot.base_parameter_names {
        assert!(
            code.contains(&format!("{name:?}")),
            "BASE_PARAMETER_NAMES lists {name}"
        );
    }
    let table = robot.op_count_table("  ");
    assert_eq!(
        table.lines().count(),
        robot.op_counts.len() + 1,
        "a header and a line per function"
    );
    assert!(table.lines().all(|l| l.starts_with("  ")));

    let again = Builder::new(twodof())
        .output_file(&file)
        .regenerate_command("dyngen gen TwoDofs.urdf -o two_arm.rs")
        .cargo_directives(false)
        .compile_report()
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(again.outcome, WriteOutcome::Unchanged);
}

#[test]
fn never_replaces_a_file_a_person_wrote() {
    let dir = scratch("hand_written");
    let file = dir.join("robot.rs");
    std::fs::write(&file, "// mine\n").expect("write");
    let err = Builder::new(twodof())
        .output_file(&file)
        .cargo_directives(false)
        .compile()
        .expect_err("refused");
    assert!(matches!(err, GenerateError::NotGenerated { .. }), "{err}");
    assert_eq!(std::fs::read_to_string(&file).expect("read"), "// mine\n");
}
