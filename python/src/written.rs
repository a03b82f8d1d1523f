//! Files an identification writes: its text, or an `OSError` naming the file.

use crate::errors::identification_error;
use dyngen_identify::IdentifyError;
use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// What `write` returns: the files written, and the loader's warnings about them (each naming
/// its file and line).
pub type Written = (Vec<PathBuf>, Vec<String>);

/// Writes `text` to `path`.
pub fn write_text(path: &Path, text: &str) -> PyResult<()> {
    std::fs::write(path, text)
        .map_err(|e| PyOSError::new_err(format!("{}: cannot write: {e}", path.display())))
}

/// Writes an estimate's description to `path`: `written` is what its `written(source, path)`
/// gave, the YAML and the loader's warnings about it.
pub fn write_description(
    py: Python<'_>,
    written: Result<(String, Vec<String>), IdentifyError>,
    path: PathBuf,
) -> PyResult<Written> {
    let (text, warnings) = written.map_err(|e| identification_error(py, &e))?;
    write_text(&path, &text)?;
    Ok((vec![path], warnings))
}
