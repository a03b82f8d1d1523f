//! A robot's C library (`docs/c-library.md`, ABI version 1), loaded with `libloading`: its
//! sizes and names, its function table, and `P_evaluate` on numpy batches without the GIL.
//! No per-robot Python code is compiled: the table says what each function takes and returns.

use crate::arrays::{batch, Argument, Results};
use crate::errors::CompileError;
use libloading::Library as Shared;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::ffi::{c_char, CStr};
use std::path::PathBuf;

/// The ABI version this package reads (`DYNGEN_ABI_VERSION`).
const ABI_VERSION: u32 = 1;

/// `dyngen_array` of `dyngen.h`.
#[repr(C)]
struct ArrayInfo {
    name: *const c_char,
    rows: usize,
    cols: usize,
}

/// `dyngen_function_info` of `dyngen.h`.
#[repr(C)]
struct FunctionInfo {
    name: *const c_char,
    quantity: *const c_char,
    input_count: usize,
    inputs: *const ArrayInfo,
    output_count: usize,
    outputs: *const ArrayInfo,
    lanes: usize,
    takes_frame: i32,
    reference_frame: i32,
}

type Evaluate = unsafe extern "C" fn(usize, usize, usize, *const *const f64, *const *mut f64) -> i32;
type StatusMessage = unsafe extern "C" fn(i32) -> *const c_char;

/// One entry of the function table, copied out of the library.
struct Function {
    name: String,
    inputs: Vec<(String, usize)>,
    outputs: Vec<(String, usize, usize)>,
    takes_frame: bool,
}

/// A loaded robot library.
#[pyclass(module = "dyngen", frozen)]
pub struct Library {
    /// Keeps the code `evaluate` and `status_message` point into loaded.
    _shared: Shared,
    evaluate: Evaluate,
    status_message: StatusMessage,
    functions: Vec<Function>,
    #[pyo3(get)]
    name: String,
    #[pyo3(get)]
    floating_base: bool,
    #[pyo3(get)]
    dof: usize,
    #[pyo3(get)]
    nq: usize,
    #[pyo3(get)]
    nv: usize,
    #[pyo3(get)]
    joint_names: Vec<String>,
    #[pyo3(get)]
    frame_names: Vec<String>,
    #[pyo3(get)]
    parameter_names: Vec<String>,
    #[pyo3(get)]
    base_parameter_names: Vec<String>,
    #[pyo3(get)]
    parameters: Vec<f64>,
    /// `P_base_parameters`, when the library has the base parameters.
    base_parameters_of: Option<unsafe extern "C" fn(*const f64, *mut f64) -> i32>,
    #[pyo3(get)]
    path: PathBuf,
}

/// A string the library owns (static data), or an error naming what was read.
///
/// # Safety
/// `text` is null or points to a NUL-terminated string valid for the library's life.
unsafe fn string(text: *const c_char, what: &str) -> PyResult<String> {
    match text.is_null() {
        true => Err(CompileError::new_err(format!("the library gave no {what}"))),
        false => Ok(unsafe { CStr::from_ptr(text) }.to_string_lossy().into_owned()),
    }
}

/// The symbol `prefix_name` of `shared`, copied out (a function pointer), or an error naming it.
///
/// # Safety
/// `T` is the symbol's type as `docs/c-library.md` declares it.
unsafe fn symbol<T: Copy>(shared: &Shared, prefix: &str, name: &str) -> PyResult<T> {
    let full = format!("{prefix}_{name}");
    unsafe { shared.get::<T>(full.as_bytes()) }
        .map(|s| *s)
        .map_err(|e| CompileError::new_err(format!("the library has no '{full}': {e}")))
}

/// `count` names read by `P_<what>_name(i)`.
///
/// # Safety
/// `name` is a `P_*_name` function of the library: it returns static strings or NULL.
unsafe fn names(
    name: unsafe extern "C" fn(usize) -> *const c_char,
    count: usize,
    what: &str,
) -> PyResult<Vec<String>> {
    (0..count).map(|i| unsafe { string(name(i), what) }).collect()
}

impl Library {
    /// Loads the library at `path` whose symbols start with `prefix`.
    fn load(path: PathBuf, prefix: &str) -> PyResult<Library> {
        // SAFETY: loading runs the library's initialisers; a dyngen robot library has none
        // beyond what the Rust standard library sets up.
        let shared = unsafe { Shared::new(&path) }.map_err(|e| {
            CompileError::new_err(format!("{}: cannot load the library: {e}", path.display()))
        })?;
        // SAFETY (every call below): the symbols are those of `dyngen.h` with their declared
        // types; the size and name functions take no pointer and return static data.
        unsafe {
            let abi: unsafe extern "C" fn() -> u32 = symbol(&shared, prefix, "abi_version")?;
            let abi = abi();
            if abi != ABI_VERSION {
                return Err(CompileError::new_err(format!(
                    "{}: the library's ABI version is {abi}, this package reads version {ABI_VERSION}: compile it again",
                    path.display()
                )));
            }
            let size = |name: &str| -> PyResult<usize> {
                let f: unsafe extern "C" fn() -> usize = symbol(&shared, prefix, name)?;
                Ok(f())
            };
            let name_of = |name: &str| -> PyResult<unsafe extern "C" fn(usize) -> *const c_char> {
                symbol(&shared, prefix, name)
            };
            let (dof, nq, nv) = (size("dof")?, size("nq")?, size("nv")?);
            let parameter_count = size("parameter_count")?;
            let base_count = size("base_parameter_count")?;
            let robot_name: unsafe extern "C" fn() -> *const c_char = symbol(&shared, prefix, "robot_name")?;
            let is_floating: unsafe extern "C" fn() -> i32 = symbol(&shared, prefix, "is_floating_base")?;
            let parameters_of: unsafe extern "C" fn(*mut f64) -> i32 = symbol(&shared, prefix, "parameters")?;
            let mut parameters = vec![0.0; parameter_count];
            if parameters_of(parameters.as_mut_ptr()) != 0 {
                return Err(CompileError::new_err(
                    "the library's parameters could not be read",
                ));
            }
            let base_parameters_of: unsafe extern "C" fn(*const f64, *mut f64) -> i32 =
                symbol(&shared, prefix, "base_parameters")?;
            let mut probe = vec![0.0; base_count];
            let has_base = base_parameters_of(parameters.as_ptr(), probe.as_mut_ptr()) == 0;
            let info: unsafe extern "C" fn(usize) -> *const FunctionInfo =
                symbol(&shared, prefix, "function_info")?;
            let functions = (0..size("function_count")?)
                .map(|i| function(info(i)))
                .collect::<PyResult<Vec<_>>>()?;
            Ok(Library {
                evaluate: symbol(&shared, prefix, "evaluate")?,
                status_message: symbol(&shared, prefix, "status_message")?,
                functions,
                name: string(robot_name(), "robot name")?,
                floating_base: is_floating() == 1,
                dof,
                nq,
                nv,
                joint_names: names(name_of("joint_name")?, dof, "joint name")?,
                frame_names: names(name_of("frame_name")?, size("frame_count")?, "frame name")?,
                parameter_names: names(name_of("parameter_name")?, parameter_count, "parameter name")?,
                base_parameter_names: names(
                    name_of("base_parameter_name")?,
                    base_count,
                    "base parameter name",
                )?,
                parameters,
                base_parameters_of: has_base.then_some(base_parameters_of),
                path,
                _shared: shared,
            })
        }
    }

    fn status(&self, status: i32) -> String {
        // SAFETY: `P_status_message` returns a static sentence for any status.
        unsafe { string((self.status_message)(status), "status message") }
            .unwrap_or_else(|_| format!("status {status}"))
    }
}

/// One table entry, copied.
///
/// # Safety
/// `info` is what `P_function_info` returned: NULL or static data as `dyngen.h` declares it.
unsafe fn function(info: *const FunctionInfo) -> PyResult<Function> {
    let Some(info) = (unsafe { info.as_ref() }) else {
        return Err(CompileError::new_err("the library's function table has a hole"));
    };
    let arrays = |pointer: *const ArrayInfo, count: usize| -> PyResult<Vec<(String, usize, usize)>> {
        (0..count)
            .map(|k| {
                // SAFETY: `pointer` has `count` entries (the table's contract).
                let a = unsafe { &*pointer.add(k) };
                Ok((unsafe { string(a.name, "array name") }?, a.rows, a.cols))
            })
            .collect()
    };
    Ok(Function {
        name: unsafe { string(info.name, "function name") }?,
        inputs: arrays(info.inputs, info.input_count)?
            .into_iter()
            .map(|(name, rows, _)| (name, rows))
            .collect(),
        outputs: arrays(info.outputs, info.output_count)?,
        takes_frame: info.takes_frame == 1,
    })
}

#[pymethods]
impl Library {
    /// Loads the robot library at `path`, whose symbols start with `prefix`.
    #[new]
    fn new(path: PathBuf, prefix: &str) -> PyResult<Library> {
        Library::load(path, prefix)
    }

    /// The names of the functions in the table, e.g. "mass_matrix", "frame_jacobian_local".
    #[getter]
    fn functions(&self) -> Vec<String> {
        self.functions.iter().map(|f| f.name.clone()).collect()
    }

    /// The names of function `name`'s inputs, in call order.
    fn inputs(&self, name: &str) -> PyResult<Vec<String>> {
        Ok(self
            .entry(name)?
            .1
            .inputs
            .iter()
            .map(|(n, _)| n.clone())
            .collect())
    }

    /// Evaluates function `name` (a table entry) on `inputs` (one array per input, one state or
    /// a batch) at `frame` (an index, for a frame function). Returns one array, or a tuple when
    /// the function has several outputs; a matrix is (rows, cols) in numpy's C order.
    #[pyo3(signature = (name, inputs, frame=None))]
    fn evaluate(
        &self,
        py: Python<'_>,
        name: &str,
        inputs: Vec<Bound<'_, PyAny>>,
        frame: Option<usize>,
    ) -> PyResult<Py<PyAny>> {
        let (index, function) = self.entry(name)?;
        if inputs.len() != function.inputs.len() {
            let names: Vec<&str> = function.inputs.iter().map(|(n, _)| n.as_str()).collect();
            return Err(PyValueError::new_err(format!(
                "{name} takes {} arrays ({}), {} given",
                names.len(),
                names.join(", "),
                inputs.len()
            )));
        }
        let frame = match (function.takes_frame, frame) {
            (true, Some(f)) if f < self.frame_names.len() => f,
            (true, _) => {
                return Err(PyValueError::new_err(format!(
                    "{name} needs a frame of {:?}",
                    self.frame_names
                )))
            }
            (false, _) => 0,
        };
        let arguments: Vec<Argument<'_, '_>> = function
            .inputs
            .iter()
            .zip(&inputs)
            .map(|((n, rows), value)| Argument {
                name: n,
                value,
                length: *rows,
            })
            .collect();
        let batch = batch(&arguments)?;
        let count = batch.count();
        let outcome = py.detach(|| {
            let mut columns: Vec<Vec<f64>> = function
                .outputs
                .iter()
                .map(|(_, rows, cols)| vec![0.0; rows * cols * count])
                .collect();
            let pointers: Vec<*const f64> = (0..function.inputs.len())
                .map(|i| batch.input(i, 0).as_ptr())
                .collect();
            let outputs: Vec<*mut f64> = columns.iter_mut().map(|c| c.as_mut_ptr()).collect();
            // SAFETY: `batch` holds `count` contiguous states of each input's rows, `columns`
            // room for `count` blocks of each output's rows × cols, as `P_evaluate` reads and
            // writes them; the outputs do not overlap.
            let status = match count {
                0 => 0,
                _ => unsafe { (self.evaluate)(index, frame, count, pointers.as_ptr(), outputs.as_ptr()) },
            };
            match status {
                0 => Ok(row_major(&function.outputs, columns, count)),
                status => Err(status),
            }
        });
        let values =
            outcome.map_err(|status| PyValueError::new_err(format!("{name}: {}", self.status(status))))?;
        let shapes: Vec<Vec<usize>> = function
            .outputs
            .iter()
            .map(|&(_, rows, cols)| if cols == 1 { vec![rows] } else { vec![rows, cols] })
            .collect();
        Results::new(shapes, values, batch.states).into_python(py)
    }

    /// The base parameters θ_b of `theta` (default: the description's θ), by the library's
    /// `P_base_parameters`.
    #[pyo3(signature = (theta=None))]
    fn base_parameters(&self, theta: Option<Vec<f64>>) -> PyResult<Vec<f64>> {
        let theta = theta.unwrap_or_else(|| self.parameters.clone());
        if theta.len() != self.parameters.len() {
            return Err(PyValueError::new_err(format!(
                "theta has {} entries, but the robot has {} parameters",
                theta.len(),
                self.parameters.len()
            )));
        }
        let Some(base_parameters_of) = self.base_parameters_of else {
            return Err(PyValueError::new_err(
                "the robot was compiled without its base parameters: compile with functions including \"base_parameters\"",
            ));
        };
        let mut out = vec![0.0; self.base_parameter_names.len()];
        // SAFETY: `theta` has P entries, `out` room for B, as `P_base_parameters` reads and writes.
        let status = unsafe { base_parameters_of(theta.as_ptr(), out.as_mut_ptr()) };
        match status {
            0 => Ok(out),
            status => Err(PyValueError::new_err(self.status(status))),
        }
    }
}

impl Library {
    fn entry(&self, name: &str) -> PyResult<(usize, &Function)> {
        self.functions
            .iter()
            .enumerate()
            .find(|(_, f)| f.name == name)
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "the compiled robot has no function '{name}' (it has {}): compile it with the group that holds it",
                    self.functions().join(", ")
                ))
            })
    }
}

/// Each state's column-major blocks as numpy's row-major ones.
fn row_major(outputs: &[(String, usize, usize)], columns: Vec<Vec<f64>>, count: usize) -> Vec<Vec<f64>> {
    outputs
        .iter()
        .zip(columns)
        .map(|(&(_, rows, cols), column_major)| {
            let block = rows * cols;
            let mut out = vec![0.0; block * count];
            for b in 0..count {
                for i in 0..rows {
                    for j in 0..cols {
                        out[b * block + i * cols + j] = column_major[b * block + i + rows * j];
                    }
                }
            }
            out
        })
        .collect()
}
