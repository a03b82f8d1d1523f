//! dyngen for Python: robot descriptions, their generic dynamics on numpy batches,
//! identification from arrays, and robots compiled to their C library (`docs/python.md`).
//! The Python package around this module is `python/dyngen/`.

mod arrays;
mod errors;
mod generic;
mod loading;
mod reference;
mod robot;

use pyo3::prelude::*;

#[pymodule]
fn _dyngen(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    errors::register(m)?;
    m.add_class::<robot::Robot>()?;
    Ok(())
}
