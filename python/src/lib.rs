//! dyngen for Python: robot descriptions, their generic dynamics on numpy batches,
//! identification from arrays, and robots compiled to their C library (`docs/python.md`).
//! The Python package around this module is `python/dyngen/`.

mod arrays;
mod errors;
mod excitation;
mod generation;
mod generic;
mod identification;
mod library;
mod loading;
mod payload;
mod reference;
mod robot;
mod samples;
mod written;

use pyo3::prelude::*;

#[pymodule]
fn _dyngen(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    m.add_class::<robot::Robot>()?;
    m.add_class::<identification::Identification>()?;
    m.add_class::<excitation::Excitation>()?;
    m.add_class::<payload::Payload>()?;
    m.add_class::<library::Library>()?;
    m.add_function(wrap_pyfunction!(identification::identify, m)?)?;
    m.add_function(wrap_pyfunction!(excitation::excite, m)?)?;
    m.add_function(wrap_pyfunction!(payload::identify_payload, m)?)?;
    m.add_function(wrap_pyfunction!(generation::runtime_checkout, m)?)?;
    m.add_function(wrap_pyfunction!(generation::compile_source, m)?)?;
    m.add_function(wrap_pyfunction!(generation::write_c_library, m)?)?;
    Ok(())
}
