//! A failed or interrupted generation never loses the previous generated file: writes go to a
//! temporary file that is renamed over the target, and the next run removes temporaries that
//! a killed run left behind.

use dyngen_codegen::generate::{
    generate_into_crate, generate_robot, write_file, GenerateError, Mode, GENERATED_MARKER,
};
use dyngen_testkit::scratch::scratch_dir;
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant};

const ROBOT: &str = "\
name: tiny
links:
  - name: base
  - name: l1
    inertial:
      mass: 1.0
      inertia: { ixx: 0.1, ixy: 0.0, ixz: 0.0, iyy: 0.1, iyz: 0.0, izz: 0.1 }
joints:
  - { name: j1, type: continuous, parent: base, child: l1, axis: [0, 0, 1] }
";

fn old_content() -> String {
    format!("{GENERATED_MARKER}\n// the previous generation, which must survive\n")
}

fn generate(description: &Path) -> String {
    generate_robot(description, "tiny.yaml", "Tiny", "test")
        .unwrap_or_else(|e| panic!("{e}"))
        .code
}

fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .expect("readable")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

const CHILD: &str = "DYNGEN_NO_DATA_LOSS_CHILD";

/// In the child process: generate the description named by the environment into the target.
#[test]
fn writer_child() {
    if let Ok(target) = std::env::var(CHILD) {
        let description = PathBuf::from(std::env::var("DYNGEN_NO_DATA_LOSS_DESCRIPTION").expect("set"));
        write_file(Path::new(&target), &generate(&description)).expect("write");
    }
}

fn spawn_writer(target: &Path, description: &Path, pause_ms: u64) -> Child {
    Command::new(std::env::current_exe().expect("test binary"))
        .args([
            "no_data_loss::writer_child",
            "--exact",
            "--quiet",
            "--test-threads=1",
        ])
        .env(CHILD, target)
        .env("DYNGEN_NO_DATA_LOSS_DESCRIPTION", description)
        .env("DYNGEN_TEST_WRITE_PAUSE_MS", pause_ms.to_string())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("child runs")
}

/// Waits until `child` has created its temporary file (named after its process id; earlier
/// killed children may have left theirs).
fn wait_for_temporary(dir: &Path, child: &Child) {
    let own = format!(".tiny.rs.dyngen-{}.tmp", child.id());
    let start = Instant::now();
    while !temporaries(dir).contains(&own) {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "the child never wrote {own}"
        );
        std::thread::sleep(Duration::from_millis(1));
    }
}

/// SIGKILL at chosen moments while the child writes: the target is always the old or the new
/// content, never a mix or a truncation; the next complete run removes the leftovers.
#[test]
fn killed_generation_leaves_old_or_new_file() {
    let temp = scratch_dir("kill");
    let dir = temp.path();
    let description = dir.join("tiny.yaml");
    std::fs::write(&description, ROBOT).expect("write description");
    let target = dir.join("tiny.rs");
    let new = generate(&description);
    let old = old_content();
    assert_ne!(new, old);

    let pause = 150; // ms, twice: halfway through the temporary file, and before the rename
    let mut outcomes = (0, 0); // (old, new)
    let mut killed_mid_write = 0;
    // Delays after the temporary file appears (ms): inside the first pause, inside the
    // second, and around the rename; then delays from the start, which may fall anywhere.
    let after_temp = [0, 50, 100, 200, 250, 290, 310, 330];
    let from_start = [0, 20, 80, 160, 320, 640];
    for (k, delay) in after_temp
        .iter()
        .map(|d| (true, d))
        .chain(from_start.iter().map(|d| (false, d)))
    {
        std::fs::write(&target, &old).expect("reset target");
        let mut child = spawn_writer(&target, &description, pause);
        if k {
            wait_for_temporary(dir, &child);
            if *delay < pause {
                killed_mid_write += 1;
            }
        }
        std::thread::sleep(Duration::from_millis(*delay));
        let _ = child.kill(); // SIGKILL on Unix; an error means it had already finished
        let _ = child.wait();
        let content = std::fs::read_to_string(&target).expect("the target still exists");
        match content {
            c if c == old => outcomes.0 += 1,
            c if c == new => outcomes.1 += 1,
            c => panic!(
                "killed after {delay} ms: the target is neither old nor new ({} bytes)",
                c.len()
            ),
        }
    }
    assert!(
        killed_mid_write >= 2 && outcomes.0 >= 2,
        "no kill hit a write: {outcomes:?}"
    );
    // A kill mid-write leaves a temporary file; the next run removes it and writes the file.
    std::fs::write(&target, &old).expect("reset target");
    let mut child = spawn_writer(&target, &description, pause);
    wait_for_temporary(dir, &child);
    let _ = child.kill();
    let _ = child.wait();
    assert_eq!(std::fs::read_to_string(&target).expect("target"), old);
    assert_eq!(
        temporaries(dir).len(),
        1,
        "a killed write leaves its temporary file"
    );
    let mut child = spawn_writer(&target, &description, 0);
    assert!(child.wait().expect("child").success());
    assert_eq!(std::fs::read_to_string(&target).expect("target"), new);
    assert_eq!(temporaries(dir), Vec::<String>::new());
}

/// An invalid description fails before anything is written: the previous files are intact.
#[test]
fn failed_generation_keeps_previous_files() {
    let temp = scratch_dir("fail");
    let dir = temp.path();
    let src = dir.join("src");
    std::fs::create_dir_all(&src).expect("src");
    let description = dir.join("tiny.yaml");
    std::fs::write(&description, ROBOT.replace("mass: 1.0", "mass: -1.0")).expect("write");
    let previous = old_content();
    std::fs::write(src.join("tiny.rs"), &previous).expect("write");
    std::fs::write(src.join("lib.rs"), &previous).expect("write");
    let e = generate_into_crate(dir, &src, &[description], Mode::Write).unwrap_err();
    assert!(e.to_string().contains("negative mass"), "{e}");
    assert_eq!(
        std::fs::read_to_string(src.join("tiny.rs")).expect("read"),
        previous
    );
    assert_eq!(
        std::fs::read_to_string(src.join("lib.rs")).expect("read"),
        previous
    );
    assert_eq!(temporaries(&src), Vec::<String>::new());
}

/// A file that dyngen did not write is never replaced.
#[test]
fn hand_written_file_is_never_overwritten() {
    let temp = scratch_dir("foreign");
    let dir = temp.path();
    let target = dir.join("tiny.rs");
    let mine = "// my own code\nfn main() {}\n";
    std::fs::write(&target, mine).expect("write");
    let e = write_file(&target, &old_content()).unwrap_err();
    assert!(matches!(e, GenerateError::NotGenerated { .. }), "{e}");
    assert_eq!(std::fs::read_to_string(&target).expect("read"), mine);
    assert_eq!(temporaries(dir), Vec::<String>::new());
}

/// A write that fails at the rename (the target is a directory) reports the path and
/// removes its temporary file.
#[test]
fn failed_rename_leaves_no_temporary() {
    let temp = scratch_dir("rename");
    let dir = temp.path();
    let target = dir.join("tiny.rs");
    std::fs::create_dir_all(target.join("inside")).expect("dir");
    let e = write_file(&target, &old_content()).unwrap_err();
    assert!(e.to_string().contains("tiny.rs"), "{e}");
    assert!(target.join("inside").is_dir());
    assert_eq!(temporaries(dir), Vec::<String>::new());
    // A missing directory: an error, nothing created.
    let e = write_file(&dir.join("missing/tiny.rs"), &old_content()).unwrap_err();
    assert!(e.to_string().contains("missing"), "{e}");
    assert!(!dir.join("missing").exists());
}
