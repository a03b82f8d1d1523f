//! Files an identification writes: its text, or an `OSError` naming the file.

use pyo3::exceptions::PyOSError;
use pyo3::PyResult;
use std::path::{Path, PathBuf};

/// What `write` returns: the files written, and the loader's warnings about them (each naming
/// its file and line).
pub type Written = (Vec<PathBuf>, Vec<String>);

/// Writes `text` to `path`.
pub fn write_text(path: &Path, text: &str) -> PyResult<()> {
    std::fs::write(path, text)
        .map_err(|e| PyOSError::new_err(format!("{}: cannot write: {e}", path.display())))
}
