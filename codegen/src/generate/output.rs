//! Writing generated files safely: atomically (temporary file + rename, so a failed run never
//! leaves half a file), only when the content changed (so downstream crates do not rebuild), and
//! never over a file that dyngen did not generate.

use super::robot_file::{GenerateError, GENERATED_MARKER};
use std::io::Write;
use std::path::Path;

/// What writing (or checking) a generated file found.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WriteOutcome {
    /// The file already had this content.
    Unchanged,
    /// The file was written (or, when checking, would have been).
    Written,
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> GenerateError + '_ {
    move |source| GenerateError::Io {
        path: path.to_owned(),
        source,
    }
}

/// Refuses to replace an existing file that does not carry dyngen's marker (an empty file has
/// nothing to lose).
fn ensure_ours(path: &Path, existing: &str) -> Result<(), GenerateError> {
    if existing.trim().is_empty() || existing.starts_with(GENERATED_MARKER) {
        Ok(())
    } else {
        Err(GenerateError::NotGenerated {
            path: path.to_owned(),
        })
    }
}

/// Compares `path` with `contents` without writing.
pub fn check_file(path: &Path, contents: &str) -> Result<WriteOutcome, GenerateError> {
    match std::fs::read_to_string(path) {
        Ok(existing) if existing == contents => Ok(WriteOutcome::Unchanged),
        Ok(existing) => ensure_ours(path, &existing).map(|_| WriteOutcome::Written),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(WriteOutcome::Written),
        Err(e) => Err(io(path)(e)),
    }
}

/// Writes `contents` to `path` if it differs, atomically.
pub fn write_file(path: &Path, contents: &str) -> Result<WriteOutcome, GenerateError> {
    if check_file(path, contents)? == WriteOutcome::Unchanged {
        return Ok(WriteOutcome::Unchanged);
    }
    let dir = path
        .parent()
        .filter(|d| !d.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let prefix = format!(".{name}.dyngen-");
    remove_stale_temporaries(dir, &prefix);
    let tmp = dir.join(format!("{prefix}{}.tmp", std::process::id()));
    let pause = test_pause();
    let result = (|| {
        let mut f = std::fs::File::create(&tmp).map_err(io(&tmp))?;
        let (first, second) = contents.as_bytes().split_at(contents.len() / 2);
        f.write_all(first).map_err(io(&tmp))?;
        pause();
        f.write_all(second).map_err(io(&tmp))?;
        f.sync_all().map_err(io(&tmp))?;
        pause();
        std::fs::rename(&tmp, path).map_err(io(path))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.map(|_| WriteOutcome::Written)
}

/// Removes temporary files `<prefix><pid>.tmp` that an interrupted run (killed between
/// creating and renaming its temporary file) left behind. Best effort: a failure only leaves
/// a hidden file.
fn remove_stale_temporaries(dir: &Path, prefix: &str) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let is_ours = name
            .strip_prefix(prefix)
            .and_then(|rest| rest.strip_suffix(".tmp"))
            .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()));
        if is_ours {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

/// Test hook: `DYNGEN_TEST_WRITE_PAUSE_MS=n` makes [`write_file`] sleep `n` ms halfway through
/// writing the temporary file and again before renaming it, so that a test can kill the
/// process while a write is under way. Unset (always, outside that test): no pause.
fn test_pause() -> impl Fn() {
    let ms = std::env::var("DYNGEN_TEST_WRITE_PAUSE_MS")
        .ok()
        .and_then(|v| v.parse::<u64>().ok())
        .unwrap_or(0);
    move || {
        if ms > 0 {
            std::thread::sleep(std::time::Duration::from_millis(ms));
        }
    }
}

/// A Rust module name for a description file: `robots/UR5-e.yaml` → `ur5_e`.
pub fn module_name(description: &Path) -> String {
    let stem = description
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut name: String = stem
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    if name.is_empty() || name.starts_with(|c: char| c.is_ascii_digit()) {
        name.insert_str(0, "robot_");
    }
    name
}

/// The `lib.rs` of a crate of generated robots: one module per robot, with its type re-exported.
pub fn crate_root(modules: &[String], regenerate: &str) -> String {
    let mut s = format!(
        "{GENERATED_MARKER}\n// Do not edit by hand: regenerate with `{regenerate}`.\n\n\
         //! Generated rigid-body dynamics of the robots in `robots/`; each type implements\n\
         //! [`dyngen_runtime::RobotDynamics`].\n\n#![deny(warnings)]\n"
    );
    for m in modules {
        s += &format!(
            "\n{}\npub mod {m};\npub use {m}::{};\n",
            super::emit::MODULE_ATTRIBUTES,
            super::emit::type_name(m)
        );
    }
    s
}
