//! What `dyngen.compile` asks of Rust: what identifies a robot's generated code (for the cache),
//! and the robot written as a C library crate by the generator's `Builder`.

use crate::errors::{description_error, CompileError};
use crate::loading::functions;
use crate::robot::Robot;
use dyngen_codegen::generate::GenerateError;
use dyngen_codegen::Builder;
use dyngen_identify::to_yaml;
use dyngen_model::description::Choices;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// Where this package was built from: the checkout's `runtime/`, which a compiled robot's crate
/// depends on while it exists (the published `dyngen-runtime` otherwise).
#[pyfunction]
pub fn runtime_checkout() -> Option<PathBuf> {
    let runtime = Path::new(env!("CARGO_MANIFEST_DIR")).join("../runtime");
    runtime
        .join("Cargo.toml")
        .is_file()
        .then(|| runtime.canonicalize().unwrap_or(runtime))
}

/// What [`compile_source`] returns: the description file or the YAML of a robot in memory,
/// the files read, and the rest of what identifies the generated code.
type Source = (Option<PathBuf>, Option<String>, Vec<PathBuf>, String);

/// How the robot's description reaches the generator: `(path, None)` for a robot loaded from
/// a file, `(None, yaml)` for one made in memory (an identified robot), whose YAML the caller
/// writes and passes back; and the text that identifies the generated code besides the files'
/// contents (version, choices, functions).
#[pyfunction]
#[pyo3(signature = (robot, functions=None))]
pub fn compile_source(robot: &Robot, functions: Option<&Bound<'_, PyAny>>) -> PyResult<Source> {
    let data = &robot.data;
    if data.theta.is_some() {
        return Err(CompileError::new_err(
            "a robot made with with_parameters() has no description to generate: compile the description, \
             or the identified robot (Identification.robot)",
        ));
    }
    let functions = self::functions(functions)?;
    let (path, yaml, sources, choices) = match &data.origin {
        Some(origin) => (
            Some(origin.path.clone()),
            None,
            origin.sources.clone(),
            origin.choices.clone(),
        ),
        None => (
            None,
            Some(to_yaml(
                &data.model,
                &["Written by dyngen.compile for the robot in memory.".to_owned()],
            )),
            Vec::new(),
            Choices::default(),
        ),
    };
    let fingerprint = format!(
        "dyngen {}\nchoices {choices:?}\nfunctions {functions:?}\n",
        env!("CARGO_PKG_VERSION")
    );
    Ok((path, yaml, sources, fingerprint))
}

/// Writes `robot` (its description, or `description` for one made in memory) as a C library
/// crate into `dir` with symbols starting with `prefix`; returns the generator's warnings.
#[pyfunction]
#[pyo3(signature = (robot, dir, prefix, functions=None, description=None, runtime=None))]
pub fn write_c_library(
    py: Python<'_>,
    robot: &Robot,
    dir: PathBuf,
    prefix: &str,
    functions: Option<&Bound<'_, PyAny>>,
    description: Option<PathBuf>,
    runtime: Option<PathBuf>,
) -> PyResult<Vec<String>> {
    let functions = self::functions(functions)?;
    let (path, choices) = match (&robot.data.origin, description) {
        (Some(origin), _) => (origin.path.clone(), origin.choices.clone()),
        (None, Some(description)) => (description, Choices::default()),
        (None, None) => {
            return Err(CompileError::new_err(
                "a robot made in memory needs its description written",
            ))
        }
    };
    let choices = choices.with(Choices {
        functions,
        ..Choices::default()
    });
    let mut builder = Builder::new(&path)
        .choices(choices)
        .cargo_directives(false)
        .regenerate_command("dyngen.compile (Python)")
        .c_library(&dir)
        .c_prefix(prefix);
    if let Some(runtime) = runtime {
        builder = builder.c_runtime_path(runtime);
    }
    match py.detach(|| builder.compile_report()) {
        Ok(report) => Ok(report.robot.warnings),
        Err(GenerateError::Description(e)) => Err(description_error(py, &e)),
        Err(e) => Err(CompileError::new_err(e.to_string())),
    }
}
