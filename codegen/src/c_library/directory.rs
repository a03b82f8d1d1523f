//! Whether a directory can take a C library: it is new or empty, or holds only what dyngen and
//! cargo put there. Checked before anything is written, so that a refusal leaves the directory
//! as it was.

use crate::generate::{check_file, is_generated, GenerateError};
use std::path::{Path, PathBuf};

/// What cargo writes into a crate's directory, besides dyngen's files.
const CARGO_OUTPUT: [&str; 2] = ["target", "Cargo.lock"];

/// Refuses `dir` if one of `files` (relative paths) would replace a file dyngen did not write,
/// or if it holds anything else that is not dyngen's or cargo's.
pub(super) fn check(dir: &Path, files: &[(PathBuf, String)]) -> Result<(), GenerateError> {
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| GenerateError::Io { path, source }
    };
    match std::fs::metadata(dir) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io(dir)(e)),
        Ok(meta) if !meta.is_dir() => {
            return Err(GenerateError::CLibrary {
                dir: dir.to_owned(),
                problem: "not a directory: a C library is a directory of files".into(),
            })
        }
        Ok(_) => {}
    }
    for (path, contents) in files {
        check_file(&dir.join(path), contents)?;
    }
    let ours: Vec<&Path> = files.iter().map(|(p, _)| p.as_path()).collect();
    let mut foreign = Vec::new();
    let mut pending = vec![PathBuf::new()];
    while let Some(relative) = pending.pop() {
        let here = dir.join(&relative);
        let mut entries: Vec<_> = (std::fs::read_dir(&here).map_err(io(&here))?)
            .collect::<Result<_, _>>()
            .map_err(io(&here))?;
        entries.sort_by_key(|e| e.file_name());
        for entry in entries {
            let path = relative.join(entry.file_name());
            let is_dir = entry.file_type().map_err(io(&entry.path()))?.is_dir();
            let top_level_cargo =
                relative.as_os_str().is_empty() && CARGO_OUTPUT.iter().any(|c| entry.file_name() == *c);
            if top_level_cargo || ours.contains(&path.as_path()) || is_temporary(&entry.file_name()) {
                continue;
            }
            if is_dir {
                pending.push(path);
            } else if !std::fs::read_to_string(entry.path()).is_ok_and(|text| is_generated(&text)) {
                foreign.push(path);
            }
        }
    }
    if foreign.is_empty() {
        return Ok(());
    }
    foreign.sort();
    let shown: Vec<String> = (foreign.iter().take(3))
        .map(|p| format!("`{}`", p.to_string_lossy().replace('\\', "/")))
        .collect();
    let more = match foreign.len() {
        n if n > 3 => format!(" and {} more", n - 3),
        _ => String::new(),
    };
    Err(GenerateError::CLibrary {
        dir: dir.to_owned(),
        problem: format!(
            "holds files dyngen did not write ({}{more}); refusing to write a C library among \
             them: choose a new or empty directory, or one dyngen wrote",
            shown.join(", ")
        ),
    })
}

/// A temporary file an interrupted write left (`.<name>.dyngen-<pid>.tmp`), which the next
/// write of that file removes.
fn is_temporary(name: &std::ffi::OsStr) -> bool {
    let name = name.to_string_lossy();
    name.starts_with('.') && name.contains(".dyngen-") && name.ends_with(".tmp")
}
