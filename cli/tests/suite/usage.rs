//! The command line itself: help and version succeed, a command line clap refuses exits 2
//! (a usage error), a failure of the work exits 1.

use crate::common;

use common::{dyngen, repository_file};

#[test]
fn help_and_version_succeed() {
    for args in [&["--help"][..], &["-h"], &["--version"], &["-V"], &["help"]] {
        let run = dyngen(args);
        assert_eq!(run.code, Some(0), "{args:?}: {}", run.output());
    }
    let help = dyngen(&["--help"]);
    for command in ["gen", "check", "info", "urdf", "excite", "identify", "payload"] {
        assert!(
            help.stdout.contains(command),
            "--help lists {command}: {}",
            help.stdout
        );
    }
    let version = dyngen(&["--version"]);
    assert_eq!(
        version.stdout.trim(),
        format!("dyngen {}", env!("CARGO_PKG_VERSION"))
    );
}

#[test]
fn every_command_has_help() {
    for command in ["gen", "check", "info", "urdf", "excite", "identify", "payload"] {
        let run = dyngen(&[command, "--help"]);
        assert_eq!(run.code, Some(0), "{command} --help: {}", run.output());
        assert!(run.stdout.contains("Usage: dyngen"), "{}", run.output());
    }
    let excite = dyngen(&["excite", "--help"]);
    for option in [
        "--output",
        "--duration",
        "--rate",
        "--frequency",
        "--harmonics",
        "--iterations",
        "--seed",
    ] {
        assert!(
            excite.stdout.contains(option),
            "excite --help names {option}: {}",
            excite.stdout
        );
    }
}

#[test]
fn usage_errors_exit_2() {
    let arm7 = repository_file("robots/arm7.yaml");
    let arm7 = arm7.to_str().expect("UTF-8");
    let cases: [&[&str]; 5] = [
        &[],
        &["gen", arm7, "-o", "x.rs", "--no-such-flag"],
        &["gen", arm7],
        &["identify", arm7, "-o", "x.yaml"],
        &["no-such-command"],
    ];
    for args in cases {
        let run = dyngen(args);
        assert_eq!(run.code, Some(2), "{args:?}: {}", run.output());
        // Without a command clap prints the help; otherwise it says what is wrong.
        let said = if args.is_empty() {
            "Usage: dyngen"
        } else {
            "error:"
        };
        assert!(run.stderr.contains(said), "{args:?}: {}", run.output());
    }
    let not_a_number = dyngen(&["excite", arm7, "-o", "x.csv", "--duration", "long"]);
    assert_eq!(not_a_number.code, Some(2), "{}", not_a_number.output());
}

#[test]
fn failures_of_the_work_exit_1() {
    let missing = dyngen(&["check", "no/such/robot.yaml"]);
    assert_eq!(missing.code, Some(1), "{}", missing.output());
    assert!(
        missing.stderr.starts_with("error: no/such/robot.yaml"),
        "{}",
        missing.output()
    );
    let negative = dyngen(&[
        "excite",
        repository_file("robots/arm7.yaml").to_str().expect("UTF-8"),
        "-o",
        "x.csv",
        "--duration=-1",
    ]);
    assert_eq!(negative.code, Some(1), "{}", negative.output());
}
