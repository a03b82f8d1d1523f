//! Generating robots into a crate of committed code (the workspace's `generated/`), or checking
//! that what is committed is what the generator would write now.

use super::output::{check_file, crate_root, module_name, write_file, WriteOutcome};
use super::robot_file::{generate_robot, GenerateError, GeneratedRobot, GENERATED_MARKER};
use std::path::{Path, PathBuf};

/// Write the files, or only compare them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    Write,
    Check,
}

/// What happened to one robot.
#[derive(Debug)]
pub struct RobotReport {
    pub module: String,
    pub file: PathBuf,
    pub robot: GeneratedRobot,
    /// `Written` in check mode means stale.
    pub outcome: WriteOutcome,
    /// The C library written beside it ([`Builder::c_library`](crate::Builder::c_library)).
    pub c_library: Option<crate::CLibraryReport>,
}

/// The outcome of one run.
#[derive(Debug)]
pub struct CrateReport {
    pub robots: Vec<RobotReport>,
    /// The crate root (`lib.rs`) and what happened to it.
    pub crate_root: (PathBuf, WriteOutcome),
}

impl CrateReport {
    /// Files that were stale (check mode) or rewritten (write mode).
    pub fn changed(&self) -> Vec<&Path> {
        let mut files: Vec<&Path> = self
            .robots
            .iter()
            .filter(|r| r.outcome == WriteOutcome::Written)
            .map(|r| r.file.as_path())
            .collect();
        if self.crate_root.1 == WriteOutcome::Written {
            files.push(&self.crate_root.0);
        }
        files
    }
}

/// `path` relative to `root` with forward slashes, for headers that read the same everywhere.
fn relative(root: &Path, path: &Path) -> String {
    let abs = path.canonicalize().unwrap_or_else(|_| path.to_owned());
    let root = root.canonicalize().unwrap_or_else(|_| root.to_owned());
    abs.strip_prefix(&root)
        .unwrap_or(&abs)
        .to_string_lossy()
        .replace('\\', "/")
}

/// Modules already generated in `src` (files that carry dyngen's marker), sorted.
fn existing_modules(src: &Path) -> Result<Vec<String>, GenerateError> {
    let io = |source| GenerateError::Io {
        path: src.to_owned(),
        source,
    };
    let mut modules = Vec::new();
    for entry in std::fs::read_dir(src).map_err(io)? {
        let path = entry.map_err(io)?.path();
        let is_rs = path.extension().is_some_and(|e| e == "rs");
        if is_rs && path.file_name().is_some_and(|n| n != "lib.rs") {
            let text = std::fs::read_to_string(&path).unwrap_or_default();
            if text.starts_with(GENERATED_MARKER) {
                modules.push(module_name(&path));
            }
        }
    }
    Ok(modules)
}

/// Generates each description into `src/<module>.rs` and rewrites `src/lib.rs` to list every
/// generated module. `workspace` is the root that header paths are relative to.
pub fn generate_into_crate(
    workspace: &Path,
    src: &Path,
    descriptions: &[PathBuf],
    mode: Mode,
) -> Result<CrateReport, GenerateError> {
    let mut modules = existing_modules(src)?;
    let mut robots = Vec::new();
    for description in descriptions {
        let module = module_name(description);
        let shown = relative(workspace, description);
        let regenerate = format!("cargo xtask gen {shown}");
        let robot = generate_robot(description, &shown, &super::emit::type_name(&module), &regenerate)?;
        let file = src.join(format!("{module}.rs"));
        let outcome = match mode {
            Mode::Write => write_file(&file, &robot.code)?,
            Mode::Check => check_file(&file, &robot.code)?,
        };
        if !modules.contains(&module) {
            modules.push(module.clone());
        }
        robots.push(RobotReport {
            module,
            file,
            robot,
            outcome,
            c_library: None,
        });
    }
    modules.sort();
    let root = crate_root(&modules, "cargo xtask gen --all");
    let lib = src.join("lib.rs");
    let outcome = match mode {
        Mode::Write => write_file(&lib, &root)?,
        Mode::Check => check_file(&lib, &root)?,
    };
    Ok(CrateReport {
        robots,
        crate_root: (lib, outcome),
    })
}

/// The robot descriptions directly in `dir` (`*.yaml`, `*.yml`, `*.urdf`), sorted.
pub fn descriptions_in(dir: &Path) -> Result<Vec<PathBuf>, GenerateError> {
    let io = |source| GenerateError::Io {
        path: dir.to_owned(),
        source,
    };
    let mut found = Vec::new();
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let path = entry.map_err(io)?.path();
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if path.is_file() && matches!(ext, "yaml" | "yml" | "urdf") {
            found.push(path);
        }
    }
    found.sort();
    Ok(found)
}
