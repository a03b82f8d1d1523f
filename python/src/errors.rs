//! The exceptions dyngen raises, and how its Rust errors become them. Bad arguments (a wrong
//! shape, a NaN, a non-unit quaternion, an unknown frame) are `ValueError`s; what a description,
//! identification or a build says is one of these, its message the one the command line prints.

use dyngen_identify::IdentifyError;
use dyngen_model::description::DescriptionError as LoadError;
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    dyngen,
    DyngenError,
    PyException,
    "The base of every error dyngen raises besides ValueError for bad arguments."
);
create_exception!(
    dyngen,
    DescriptionError,
    DyngenError,
    "A robot description that cannot be loaded. `file`, `line`, `column` (None when unknown), \
     `item` (e.g. \"joint 'elbow'\", or None) and `problem` say where and what; the message is \
     `file:line:column: item: problem`."
);
create_exception!(
    dyngen,
    IdentificationError,
    DyngenError,
    "Identification failed: bad data (with `file`, `line` and `column` where the data came from \
     a file), a parameter the data cannot determine, or a robot it does not support."
);
create_exception!(
    dyngen,
    CompileError,
    DyngenError,
    "Generating or building a robot's compiled library failed, or no cargo toolchain was found."
);

/// A loader error as a `DescriptionError` carrying its place.
pub fn description_error(py: Python<'_>, e: &LoadError) -> PyErr {
    let err = DescriptionError::new_err(e.to_string());
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr("file", e.file.display().to_string())?;
        value.setattr("line", e.location.map(|l| l.line))?;
        value.setattr("column", e.location.map(|l| l.column))?;
        value.setattr("item", e.item.clone())?;
        value.setattr("problem", e.message.clone())?;
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// An identification error as an `IdentificationError`, with the data's place when it has one.
pub fn identification_error(py: Python<'_>, e: &IdentifyError) -> PyErr {
    let err = IdentificationError::new_err(e.to_string());
    let place = match e {
        IdentifyError::Data { place, .. } | IdentifyError::Csv { place, .. } => Some(place),
        _ => None,
    };
    let value = err.value(py);
    let set = || -> PyResult<()> {
        value.setattr(
            "file",
            place
                .and_then(|p| p.file.as_ref())
                .map(|f| f.display().to_string()),
        )?;
        value.setattr("line", place.and_then(|p| p.line))?;
        value.setattr(
            "column",
            place.and_then(|p| p.column.as_ref()).map(|c| c.1.clone()),
        )?;
        Ok(())
    };
    match set() {
        Ok(()) => err,
        Err(e) => e,
    }
}

/// Registers the exceptions in the module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("DyngenError", py.get_type::<DyngenError>())?;
    m.add("DescriptionError", py.get_type::<DescriptionError>())?;
    m.add("IdentificationError", py.get_type::<IdentificationError>())?;
    m.add("CompileError", py.get_type::<CompileError>())?;
    Ok(())
}
