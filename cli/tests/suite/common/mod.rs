//! Running the installed-to-be `dyngen` binary and the files the tests give it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::Command;

/// What a run of `dyngen` gave.
pub struct Run {
    /// The exit code (`None`: killed by a signal, which a test treats as a failure).
    pub code: Option<i32>,
    pub stdout: String,
    pub stderr: String,
}

impl Run {
    /// Both streams, for assertion messages.
    pub fn output(&self) -> String {
        format!(
            "exit {:?}\nstdout:\n{}\nstderr:\n{}",
            self.code, self.stdout, self.stderr
        )
    }
}

/// Runs `dyngen` with `args` in `dir`.
pub fn dyngen_in(dir: &Path, args: &[&str]) -> Run {
    let out = Command::new(env!("CARGO_BIN_EXE_dyngen"))
        .current_dir(dir)
        .args(args)
        .output()
        .expect("dyngen runs");
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Runs `dyngen` with `args`, its standard input a pipe that `input` is written into.
pub fn dyngen_with_stdin(args: &[&str], input: &[u8]) -> Run {
    use std::io::Write as _;
    let mut child = Command::new(env!("CARGO_BIN_EXE_dyngen"))
        .args(args)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("dyngen runs");
    let mut stdin = child.stdin.take().expect("a pipe");
    let input = input.to_vec();
    // Written from another thread: the child reads while it writes its output. It may stop
    // reading early (an error), which closes the pipe: that write error is the child's to report.
    let writer = std::thread::spawn(move || {
        let _ = stdin.write_all(&input);
    });
    let out = child.wait_with_output().expect("dyngen finishes");
    writer.join().expect("the writer finishes");
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Runs `dyngen` with `args` in the current directory.
pub fn dyngen(args: &[&str]) -> Run {
    dyngen_in(Path::new("."), args)
}

/// A file of the repository, by its path from the workspace root.
pub fn repository_file(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(path)
}

/// `path` as an argument.
pub fn arg(path: &Path) -> &str {
    path.to_str().expect("test paths are UTF-8")
}

/// arm7 with a mass that is not a number, written into `dir`: a description that must fail
/// at a known place.
pub fn broken_arm7(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(repository_file("robots/arm7.yaml")).expect("arm7.yaml");
    assert!(
        text.contains("mass: 7.039242"),
        "the line the test breaks is still there"
    );
    let path = dir.join("broken.yaml");
    std::fs::write(&path, text.replacen("mass: 7.039242", "mass: heavy", 1)).expect("write");
    path
}

/// The rows of `dyngen identify`'s table of base parameters: the lines between its header,
/// which names `consistent θ_b`, and the line that counts the marked parameters.
pub fn table_rows(stdout: &str) -> impl Iterator<Item = &str> {
    stdout
        .lines()
        .skip_while(|l| !l.contains("consistent θ_b"))
        .skip(1)
        .take_while(|l| !l.starts_with("* ") && !l.starts_with("every base parameter"))
}

/// The θ_b and σ columns of `dyngen identify`'s table of base parameters.
pub fn table(stdout: &str) -> Vec<(f64, f64)> {
    table_rows(stdout)
        .map(|l| {
            let mut fields = l.split_whitespace().map(|f| f.parse::<f64>().expect("a number"));
            (fields.next().expect("θ_b"), fields.next().expect("σ"))
        })
        .collect()
}

/// Two tables of [`table`] the same to the digits printed.
pub fn assert_same_table(a: &[(f64, f64)], b: &[(f64, f64)], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    assert!(!a.is_empty(), "{what}");
    for ((x, sx), (y, sy)) in a.iter().zip(b) {
        assert!(
            (x - y).abs() <= 1e-6 * x.abs().max(*sx) && (sx - sy).abs() <= 1e-6 * sx,
            "{what}: {x} ± {sx} vs {y} ± {sy}"
        );
    }
}
