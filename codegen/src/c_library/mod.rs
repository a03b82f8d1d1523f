//! A generated robot as a C library: a crate around the generated module whose `extern "C"`
//! functions take flat `double` arrays, built as a static and a shared library, with the C
//! headers, a CMake package and a pkg-config file (`docs/c-library.md`).
//!
//! Everything robot-specific is written from the table of [`table::entries`], itself derived
//! from the quantity table: the wrapper (`wrapper`), the headers (`header`) and the build
//! files (`build_files`) never list functions by hand. The files are written as every
//! generated file is ([`write_file`]), after checking that none would replace a file dyngen
//! did not write and that the directory holds nothing else.

mod build_files;
mod contacts;
mod directory;
mod header;
mod table;
mod wrapper;

use crate::frame_names::frame_identifiers;
use crate::generate::{write_file, GenerateError, GeneratedRobot, WriteOutcome};
use std::path::{Path, PathBuf};

/// Where and how to write a robot's C library ([`Builder::c_library`](crate::Builder::c_library)).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CLibrary {
    /// The directory of the library's crate.
    pub dir: PathBuf,
    /// The prefix of every symbol, `<prefix>_mass_matrix` (default: the module name).
    pub prefix: Option<String>,
    /// A checkout's `runtime/` directory for the crate to depend on `dyngen-runtime` by path
    /// (default: by version, from a registry).
    pub runtime_path: Option<PathBuf>,
}

impl CLibrary {
    /// A library in `dir`, with the default prefix and the runtime by version.
    pub fn new(dir: impl AsRef<Path>) -> CLibrary {
        CLibrary {
            dir: dir.as_ref().to_owned(),
            prefix: None,
            runtime_path: None,
        }
    }
}

/// What writing a C library did.
#[derive(Clone, Debug)]
pub struct CLibraryReport {
    pub dir: PathBuf,
    /// The prefix of its symbols.
    pub prefix: String,
    /// Every file of the library, relative to `dir`, and whether it was rewritten.
    pub files: Vec<(PathBuf, WriteOutcome)>,
}

/// What the files of one robot's library are written from.
pub(crate) struct Library {
    prefix: String,
    type_name: String,
    robot_name: String,
    /// The description as the generated module's header names it, and the command that
    /// regenerates the library.
    source: String,
    regenerate: String,
    /// `7 DOF, 70 parameters, 43 base parameters`.
    sizes_summary: String,
    sizes: table::Sizes,
    entries: Vec<table::Entry>,
    joint_names: Vec<String>,
    parameter_names: Vec<String>,
    base_parameter_names: Vec<String>,
    frame_names: Vec<String>,
    /// The frames' snake-case spellings (the generated module's), for the frame macros.
    frame_spellings: Vec<String>,
    /// The contacts the robot was generated with (`ContactDynamics`), in the order of their
    /// rows; none without the group `contacts`.
    contacts: Vec<crate::model::Contact>,
    has_base_parameters: bool,
    runtime_path: Option<PathBuf>,
}

impl Library {
    /// The crate, the library files and the CMake package: `<prefix>_dynamics`.
    fn package(&self) -> String {
        format!("{}_dynamics", self.prefix)
    }

    fn header_name(&self) -> String {
        format!("{}.h", self.package())
    }
}

/// Where the library holds the generated module, relative to its directory.
pub(crate) fn module_file() -> PathBuf {
    PathBuf::from(format!("src/{}.rs", wrapper::ROBOT_MODULE))
}

/// Whether `prefix` can start C identifiers and Rust ones.
fn is_identifier(prefix: &str) -> bool {
    let mut chars = prefix.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// How the generated robot is named: its module (the default prefix), its type, the
/// description as its header names it, and the command that regenerates it.
pub(crate) struct Naming<'a> {
    pub module: &'a str,
    pub type_name: &'a str,
    pub source: &'a str,
    pub regenerate: &'a str,
}

/// The files of `robot`'s C library (paths relative to its directory, contents) and its
/// prefix.
pub(crate) fn library_files(
    robot: &GeneratedRobot,
    naming: &Naming,
    options: &CLibrary,
) -> Result<(String, Vec<(PathBuf, String)>), GenerateError> {
    let prefix = (options.prefix.clone()).unwrap_or_else(|| naming.module.to_owned());
    if !is_identifier(&prefix) {
        return Err(GenerateError::CLibrary {
            dir: options.dir.clone(),
            problem: format!(
                "the prefix `{prefix}` cannot start C names: use letters, digits and `_`, not \
                 starting with a digit"
            ),
        });
    }
    let library = library(robot, &prefix, naming, options);
    let package = library.package();
    let files = vec![
        (PathBuf::from("Cargo.toml"), build_files::manifest(&library)),
        (PathBuf::from("src/lib.rs"), wrapper::crate_root(&library)),
        (module_file(), robot.code.clone()),
        (PathBuf::from("include/dyngen.h"), header::shared_header()),
        (
            PathBuf::from(format!("include/{}", library.header_name())),
            header::robot_header(&library),
        ),
        (
            PathBuf::from(format!("{package}Config.cmake")),
            build_files::cmake_config(&library),
        ),
        (
            PathBuf::from(format!("{package}.pc")),
            build_files::pkg_config(&library),
        ),
    ];
    Ok((prefix, files))
}

fn library(robot: &GeneratedRobot, prefix: &str, naming: &Naming, options: &CLibrary) -> Library {
    let model = &robot.model;
    let floating = model.floating_base().is_some();
    let parameter_names = match floating {
        true => crate::dynamics::FloatingDynamics::parameter_names(model),
        false => model.parameter_names(),
    };
    // The contacts' rows are generated with the group `contacts` only (which a robot without
    // contacts never has).
    let contacts = match robot.functions.contains(crate::FunctionGroup::Contacts) {
        true => model.contacts().to_vec(),
        false => Vec::new(),
    };
    let sizes = table::Sizes {
        floating,
        dof: model.dof(),
        nq: model.nq(),
        nv: model.nv(),
        parameters: parameter_names.len(),
        base_parameters: robot.base_parameter_count,
        frames: model.frames().len(),
        contact_rows: contacts.iter().map(|c| c.kind.rows()).sum(),
    };
    let frame_names: Vec<String> = model.frames().iter().map(|f| f.name.clone()).collect();
    let frame_spellings = frame_identifiers(frame_names.iter().map(String::as_str))
        .into_iter()
        .map(|f| f.snake)
        .collect();
    let has_base_parameters = robot.functions.contains(crate::FunctionGroup::BaseParameters);
    Library {
        prefix: prefix.to_owned(),
        type_name: naming.type_name.to_owned(),
        robot_name: model.name().to_owned(),
        source: naming.source.to_owned(),
        regenerate: naming.regenerate.to_owned(),
        sizes_summary: robot.sizes(),
        entries: table::entries(&sizes, &robot.functions),
        sizes,
        joint_names: (model.coordinate_joints().into_iter())
            .map(|k| model.joints()[k].name.clone())
            .collect(),
        parameter_names,
        base_parameter_names: robot.base_parameter_names.clone(),
        frame_names,
        frame_spellings,
        contacts,
        has_base_parameters,
        runtime_path: options.runtime_path.clone(),
    }
}

/// Refuses `dir` if writing `files` there would replace a file dyngen did not write, or if it
/// holds anything else but dyngen's and cargo's files.
pub(crate) fn check_library(dir: &Path, files: &[(PathBuf, String)]) -> Result<(), GenerateError> {
    directory::check(dir, files)
}

/// Checks that `dir` can take `files` (nothing there that dyngen did not write), then writes
/// them; on a refusal, nothing is written.
pub(crate) fn write_library(
    dir: &Path,
    prefix: String,
    files: &[(PathBuf, String)],
) -> Result<CLibraryReport, GenerateError> {
    directory::check(dir, files)?;
    let mut written = Vec::new();
    for (path, contents) in files {
        let file = dir.join(path);
        if let Some(parent) = file.parent() {
            std::fs::create_dir_all(parent).map_err(|source| GenerateError::Io {
                path: parent.to_owned(),
                source,
            })?;
        }
        written.push((path.clone(), write_file(&file, contents)?));
    }
    Ok(CLibraryReport {
        dir: dir.to_owned(),
        prefix,
        files: written,
    })
}
