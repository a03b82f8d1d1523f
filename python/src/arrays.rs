//! numpy arrays in and out: one state (`(n,)`) or a batch (`(B, n)`, batch first), checked
//! before anything is computed, evaluated state by state without the GIL, and returned as
//! arrays of the documented shapes (a batch's results gain the leading `B`).

use nalgebra::{Dim, Matrix, RawStorage};
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{IntoPyArray, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

/// One argument of a method: its name in messages, the array given, and the length of one
/// state's entry.
pub struct Argument<'a, 'py> {
    pub name: &'a str,
    pub value: &'a Bound<'py, PyAny>,
    pub length: usize,
}

/// The arguments of one call, each copied into contiguous row-major memory and checked.
pub struct Batch {
    /// `None` for one state, `Some(B)` for a batch of `B`.
    pub states: Option<usize>,
    inputs: Vec<Vec<f64>>,
    lengths: Vec<usize>,
}

impl Batch {
    /// How many states are evaluated (1 for a single state).
    pub fn count(&self) -> usize {
        self.states.unwrap_or(1)
    }

    /// Input `i` of state `b`.
    pub fn input(&self, i: usize, b: usize) -> &[f64] {
        let n = self.lengths[i];
        &self.inputs[i][b * n..(b + 1) * n]
    }

    /// Every input of state `b`.
    pub fn state(&self, b: usize) -> Vec<&[f64]> {
        (0..self.inputs.len()).map(|i| self.input(i, b)).collect()
    }
}

/// `value` as a float64 array in C order (any array-like, any strides), or an error naming it.
fn as_float_array<'py>(name: &str, value: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let numpy = value.py().import("numpy")?;
    let array = numpy
        .call_method1("ascontiguousarray", (value, "float64"))
        .map_err(|e| PyValueError::new_err(format!("argument '{name}': not an array of numbers ({e})")))?;
    array
        .cast_into::<PyArrayDyn<f64>>()
        .map_err(|e| PyValueError::new_err(format!("argument '{name}': {e}")))
}

/// Reads and checks the arguments: each `(n,)` (one state) or `(B, n)` (a batch), all of one
/// kind and one `B`, every entry finite.
pub fn batch(arguments: &[Argument<'_, '_>]) -> PyResult<Batch> {
    let mut states: Option<Option<usize>> = None;
    let mut inputs = Vec::with_capacity(arguments.len());
    for argument in arguments {
        let array = as_float_array(argument.name, argument.value)?;
        let readonly: PyReadonlyArrayDyn<'_, f64> = array.readonly();
        let shape = readonly.shape().to_vec();
        let n = argument.length;
        let this = match shape.as_slice() {
            [m] if *m == n => None,
            [b, m] if *m == n => Some(*b),
            _ => {
                return Err(PyValueError::new_err(format!(
                "argument '{}': shape {shape:?}, expected ({n},) for one state or (B, {n}) for a batch of B",
                argument.name
            )))
            }
        };
        match states {
            None => states = Some(this),
            Some(first) if first == this => {}
            Some(first) => {
                return Err(PyValueError::new_err(format!(
                    "argument '{}': {} but '{}' is {}: every argument must be one state, or a batch of the same size",
                    argument.name,
                    describe(this),
                    arguments[0].name,
                    describe(first)
                )))
            }
        }
        let values = readonly
            .as_slice()
            .map_err(|e| PyValueError::new_err(format!("argument '{}': {e}", argument.name)))?
            .to_vec();
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            let place = match this {
                None => format!("entry {k}"),
                Some(_) => format!("state {}, entry {}", k / n.max(1), k % n.max(1)),
            };
            return Err(PyValueError::new_err(format!(
                "argument '{}': {place} is {}: every entry must be a finite number",
                argument.name, values[k]
            )));
        }
        inputs.push(values);
    }
    Ok(Batch {
        states: states.flatten(),
        inputs,
        lengths: arguments.iter().map(|a| a.length).collect(),
    })
}

/// A table of samples: `(N, columns)` (or `(N,)` for one column, `columns` = 0), every entry
/// finite; one row per sample. `what` names the rows in messages ("sample").
pub fn rows(name: &str, value: &Bound<'_, PyAny>, columns: usize) -> PyResult<Vec<Vec<f64>>> {
    let array = as_float_array(name, value)?;
    let readonly = array.readonly();
    let shape = readonly.shape().to_vec();
    let width = match (shape.as_slice(), columns) {
        ([_], 0) => 1,
        ([_, c], _) if *c == columns && columns > 0 => columns,
        _ => {
            let expected = match columns {
                0 => "(N,)".to_owned(),
                c => format!("(N, {c})"),
            };
            return Err(PyValueError::new_err(format!(
                "argument '{name}': shape {shape:?}, expected {expected} with one row per sample"
            )));
        }
    };
    let values = readonly
        .as_slice()
        .map_err(|e| PyValueError::new_err(format!("argument '{name}': {e}")))?;
    if let Some(k) = values.iter().position(|v| !v.is_finite()) {
        return Err(PyValueError::new_err(format!(
            "argument '{name}': sample {}{} is {}: every entry must be a finite number",
            k / width,
            if columns > 0 {
                format!(", column {}", k % width)
            } else {
                String::new()
            },
            values[k]
        )));
    }
    Ok(values.chunks(width).map(<[f64]>::to_vec).collect())
}

fn describe(states: Option<usize>) -> String {
    match states {
        None => "one state".to_owned(),
        Some(b) => format!("a batch of {b}"),
    }
}

/// The results of one call: per output, the values of every state one after the other.
pub struct Results {
    shapes: Vec<Vec<usize>>,
    values: Vec<Vec<f64>>,
    states: Option<usize>,
}

impl Results {
    /// Results computed elsewhere: per output, its shape for one state and every state's
    /// values (row-major) one after the other.
    pub fn new(shapes: Vec<Vec<usize>>, values: Vec<Vec<f64>>, states: Option<usize>) -> Results {
        Results {
            shapes,
            values,
            states,
        }
    }

    /// The results as arrays: one array, or a tuple when there are several.
    pub fn into_python(self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let mut arrays = Vec::with_capacity(self.values.len());
        for (shape, values) in self.shapes.iter().zip(self.values) {
            let mut full = Vec::with_capacity(shape.len() + 1);
            full.extend(self.states);
            full.extend(shape);
            let array = ArrayD::from_shape_vec(IxDyn(&full), values)
                .map_err(|e| PyValueError::new_err(format!("internal error: result shape: {e}")))?;
            arrays.push(array.into_pyarray(py).into_any().unbind());
        }
        match arrays.len() {
            1 => Ok(arrays.pop().expect("one array")),
            _ => Ok(PyTuple::new(py, arrays)?.into_any().unbind()),
        }
    }
}

/// Evaluates `each` on every state of `batch` without the GIL, with one output buffer per
/// shape of `shapes` (the shape of one state's result). `each` returns an error message for a
/// state it cannot evaluate (a non-unit quaternion); the call then raises, naming the state.
pub fn evaluate<F>(py: Python<'_>, batch: &Batch, shapes: &[&[usize]], each: F) -> PyResult<Results>
where
    F: Fn(&[&[f64]], &mut [&mut [f64]]) -> Result<(), String> + Send + Sync,
{
    let sizes: Vec<usize> = shapes.iter().map(|s| s.iter().product()).collect();
    let count = batch.count();
    let outcome = py.detach(|| {
        let mut values: Vec<Vec<f64>> = sizes.iter().map(|&s| vec![0.0; s * count]).collect();
        for b in 0..count {
            let inputs = batch.state(b);
            let mut outputs: Vec<&mut [f64]> = values
                .iter_mut()
                .zip(&sizes)
                .map(|(v, &s)| &mut v[b * s..(b + 1) * s])
                .collect();
            each(&inputs, &mut outputs).map_err(|e| match batch.states {
                None => e,
                Some(_) => format!("state {b}: {e}"),
            })?;
        }
        Ok::<_, String>(values)
    });
    let values = outcome.map_err(PyValueError::new_err)?;
    Ok(Results {
        shapes: shapes.iter().map(|s| s.to_vec()).collect(),
        values,
        states: batch.states,
    })
}

/// Writes a matrix row by row (numpy's C order) into `out`.
pub fn write_matrix<R: Dim, C: Dim, S: RawStorage<f64, R, C>>(out: &mut [f64], m: &Matrix<f64, R, C, S>) {
    let columns = m.ncols();
    for i in 0..m.nrows() {
        for j in 0..columns {
            out[i * columns + j] = m[(i, j)];
        }
    }
}
