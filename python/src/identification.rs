//! `dyngen.identify`: a robot's parameters from arrays of measured motion and torques
//! (`dyngen_identify::identify`), and the `Identification` it returns. A thin layer: the
//! options are `IdentifyOptions`' fields, the results the Rust fields under the same names.

use crate::errors::{identification_error, IdentificationError};
use crate::robot::{Robot, RobotData};
use crate::samples::DataArrays;
use crate::written::{write_description, write_text, Written};
use dyngen_identify::{
    identify as identify_samples, wrapper_path, Identification as Estimate, IdentifyOptions, Observation,
    DEFAULT_MAX_RELATIVE_STD, DEFAULT_WINDOW,
};
use dyngen_model::model::Model;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// What the identified description's header says the data came from, unless told.
pub const ARRAYS: &str = "numpy arrays (dyngen.identify)";

/// The model identification works on, or why not (as the command line refuses it).
pub fn identifiable(robot: &RobotData) -> PyResult<&Model> {
    let model = &robot.model;
    if model.floating_base().is_some() {
        return Err(IdentificationError::new_err(format!(
            "'{}': identification of a floating-base robot is not supported yet (its base body's \
             parameters and base wrench are not in the identification model); identify it on a fixed base",
            model.name()
        )));
    }
    if model.has_mimics() {
        return Err(IdentificationError::new_err(format!(
            "'{}': identification of robots with mimic joints is not supported; lock them (locked_joints)",
            model.name()
        )));
    }
    Ok(model)
}

/// Identifies `robot`'s parameters from samples: time `t` (N,), positions `q` (N, dof) and
/// torques `tau` (N, dof), joints in the order of `robot.joint_names`; velocities `qd` and
/// accelerations `qdd` (N, dof) are computed when not given (a zero-phase low-pass filter of
/// `cutoff` Hz, then central differences: uniform sampling needed).
///
/// `observation`: "torque" (default), or "energy" / "momentum" over windows of `window` s,
/// which need no accelerations. `max_delay`: search a delay of the torques behind the positions
/// of up to this many samples (torque form).
///
/// Returns an `Identification`; raises `IdentificationError` when the data cannot determine a
/// parameter or is wrong, `ValueError` for arrays of the wrong shape or with NaN.
#[pyfunction]
#[pyo3(signature = (robot, t, q, tau, *, qd=None, qdd=None, cutoff=None, observation="torque",
    window=None, max_delay=None))]
#[allow(clippy::too_many_arguments)]
pub fn identify(
    py: Python<'_>,
    robot: &Robot,
    t: &Bound<'_, PyAny>,
    q: &Bound<'_, PyAny>,
    tau: &Bound<'_, PyAny>,
    qd: Option<&Bound<'_, PyAny>>,
    qdd: Option<&Bound<'_, PyAny>>,
    cutoff: Option<f64>,
    observation: &str,
    window: Option<f64>,
    max_delay: Option<usize>,
) -> PyResult<Identification> {
    let model = identifiable(&robot.data)?;
    let defaults = IdentifyOptions::default();
    let window = positive("window", window.unwrap_or(DEFAULT_WINDOW))?;
    let options = IdentifyOptions {
        cutoff: positive("cutoff", cutoff.unwrap_or(defaults.cutoff))?,
        observation: match observation {
            "torque" => Observation::Torque,
            "energy" => Observation::Energy { window },
            "momentum" => Observation::Momentum { window },
            other => {
                return Err(PyValueError::new_err(format!(
                    "observation: expected \"torque\", \"energy\" or \"momentum\", found '{other}'"
                )))
            }
        },
        max_delay,
        ..defaults
    };
    let samples = DataArrays {
        t,
        q,
        qd,
        qdd,
        tau: Some(tau),
        wrench: None,
        sensor_frame: None,
    }
    .samples(model)?;
    let estimate = py
        .detach(|| identify_samples(model, &samples, &options))
        .map_err(|e| identification_error(py, &e))?;
    Ok(Identification {
        estimate,
        description: robot.data.origin.as_ref().map(|o| o.path.clone()),
    })
}

/// `value`, checked to be a positive finite number.
pub fn positive(name: &str, value: f64) -> PyResult<f64> {
    match value.is_finite() && value > 0.0 {
        true => Ok(value),
        false => Err(PyValueError::new_err(format!(
            "{name} must be a positive number, found {value}"
        ))),
    }
}

/// The methods of a result that holds a robot made from the data (`Identification`,
/// `Payload`, each with its `estimate`): what it says about the data, the robot, and the
/// robot's description as YAML.
macro_rules! estimated_robot_methods {
    ($class:ty) => {
        #[pymethods]
        impl $class {
            /// What to know about the data and the estimate, one line each.
            #[getter]
            fn warnings(&self) -> Vec<String> {
                self.estimate.warnings.clone()
            }

            /// How the estimate was made where it differs from the usual, one line each.
            #[getter]
            fn notes(&self) -> Vec<String> {
                self.estimate.notes.clone()
            }

            /// The robot estimated (its generic dynamics; `dyngen.compile` builds it).
            #[getter]
            fn robot(&self) -> Robot {
                Robot::in_memory(self.estimate.model.clone())
            }

            /// The robot estimated as dyngen YAML; `source` is what the header says the data
            /// came from.
            #[pyo3(signature = (source=ARRAYS))]
            fn yaml(&self, source: &str) -> String {
                self.estimate.yaml(source)
            }
        }
    };
}
pub(crate) use estimated_robot_methods;

estimated_robot_methods!(Identification);

/// The result of `dyngen.identify`: the least squares on the base parameters (with each one's
/// standard deviation and each joint's noise), a physically consistent full parameter vector,
/// and the identified robot, which `write` saves as dyngen YAML or URDF.
#[pyclass(module = "dyngen", frozen)]
pub struct Identification {
    estimate: Estimate,
    /// The description identified (its wrapper must not be overwritten).
    description: Option<PathBuf>,
}

fn vector<'py>(py: Python<'py>, values: &[f64]) -> Bound<'py, PyArray1<f64>> {
    values.to_vec().into_pyarray(py)
}

fn matrix<'py>(py: Python<'py>, m: &nalgebra::DMatrix<f64>) -> Bound<'py, PyArray2<f64>> {
    let rows: Vec<Vec<f64>> = m.row_iter().map(|r| r.iter().copied().collect()).collect();
    PyArray2::from_vec2(py, &rows).expect("rows of one length")
}

#[pymethods]
impl Identification {
    /// Names of the base parameters.
    #[getter]
    fn base_parameter_names(&self) -> Vec<String> {
        self.estimate.base.names.clone()
    }

    /// The least-squares base parameters θ_b (B,).
    #[getter]
    fn base_parameters<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, &self.estimate.base.theta_b)
    }

    /// Their standard deviations σ (B,).
    #[getter]
    fn base_std_dev<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, &self.estimate.base.std_dev)
    }

    /// `σ/|θ_b|` per base parameter (B,), a fraction (0.1 is 10%).
    #[getter]
    fn base_relative_std_dev<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        let base = &self.estimate.base;
        let relative: Vec<f64> = (0..base.theta_b.len())
            .map(|k| base.relative_std_dev(k))
            .collect();
        vector(py, &relative)
    }

    /// The covariance of θ_b (B, B).
    #[getter]
    fn base_covariance<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f64>> {
        matrix(py, &self.estimate.base.covariance())
    }

    /// The torque noise σ of each joint (dof,), as estimated from the weighted residuals.
    #[getter]
    fn joint_noise<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, &self.estimate.base.joint_noise)
    }

    /// The scaled condition number of the stacked base regressor.
    #[getter]
    fn condition_number(&self) -> f64 {
        self.estimate.base.condition_number
    }

    /// Names of the full parameter vector's entries.
    #[getter]
    fn parameter_names(&self) -> Vec<String> {
        self.estimate.model.parameter_names()
    }

    /// The physically consistent full parameter vector θ (P,).
    #[getter]
    fn parameters<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, &self.estimate.consistent.theta)
    }

    /// The consistent estimate's base parameters (B,).
    #[getter]
    fn consistent_base_parameters<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, &self.estimate.consistent.theta_b)
    }

    /// Their standard deviations by linearisation at the optimum (B,).
    #[getter]
    fn consistent_std_dev<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, &self.estimate.consistent.std_dev)
    }

    /// The consistent estimate's whitened misfit (about the number of base parameters or less
    /// when it fits the data as well as the least squares).
    #[getter]
    fn consistent_misfit(&self) -> f64 {
        self.estimate.consistent.misfit
    }

    /// Whether the consistent estimate is compatible with the data.
    #[getter]
    fn consistent_compatible(&self) -> bool {
        self.estimate.consistent.compatible
    }

    /// Which estimate the identified robot holds: "consistent", "least_squares" or
    /// "description".
    #[getter]
    fn written(&self) -> &'static str {
        match self.estimate.written {
            dyngen_identify::WrittenEstimate::Consistent => "consistent",
            dyngen_identify::WrittenEstimate::LeastSquares => "least_squares",
            dyngen_identify::WrittenEstimate::Description => "description",
        }
    }

    /// Samples used (after the filter's end transients when derivatives were computed).
    #[getter]
    fn samples_used(&self) -> usize {
        self.estimate.samples_used
    }

    /// Whether velocities or accelerations were computed from the positions.
    #[getter]
    fn differentiated(&self) -> bool {
        self.estimate.differentiated
    }

    /// The torques' delay behind the positions in samples (fractional when it was refined),
    /// when it was searched, else None.
    #[getter]
    fn delay(&self) -> Option<f64> {
        self.estimate.delay.as_ref().map(|d| d.samples)
    }

    /// The base parameters whose `σ/|θ_b|` is above `max_relative_std` (a fraction), and a
    /// sentence saying why the estimate as a whole cannot be trusted (None when it can).
    #[pyo3(signature = (max_relative_std=DEFAULT_MAX_RELATIVE_STD))]
    fn trust(&self, max_relative_std: f64) -> (Vec<String>, Option<String>) {
        let trust = self.estimate.base.trust(max_relative_std);
        let names = &self.estimate.base.names;
        (
            trust.flagged.iter().map(|&k| names[k].clone()).collect(),
            trust.untrusted,
        )
    }

    /// Writes the identified robot to `path`: dyngen YAML (`.yaml`, `.yml`) or URDF (`.urdf`,
    /// with a `<stem>.dyngen.yaml` wrapper beside it for what URDF cannot say). Returns the
    /// files written and the loader's warnings about the YAML written (each naming the file
    /// and its line).
    #[pyo3(signature = (path, source=ARRAYS))]
    fn write(&self, py: Python<'_>, path: PathBuf, source: &str) -> PyResult<Written> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("yaml" | "yml") => write_description(py, self.estimate.written(source, &path), path),
            Some("urdf") => self.write_urdf(py, &path, source),
            _ => Err(PyValueError::new_err(format!(
                "{}: expected a .yaml, .yml or .urdf file name",
                path.display()
            ))),
        }
    }

    fn __repr__(&self) -> String {
        format!(
            "<dyngen.Identification of '{}': {} base parameters from {} samples, {}>",
            self.estimate.model.name(),
            self.estimate.base.theta_b.len(),
            self.estimate.samples_used,
            self.written()
        )
    }
}

impl Identification {
    fn write_urdf(&self, py: Python<'_>, path: &Path, source: &str) -> PyResult<Written> {
        let files = self
            .estimate
            .urdf(source, path)
            .map_err(|e| identification_error(py, &e))?;
        let wrapper = wrapper_path(path);
        if files.wrapper.is_some() && self.description.as_deref() == Some(wrapper.as_path()) {
            return Err(PyValueError::new_err(format!(
                "{}: the URDF's wrapper would overwrite the description identified; write the URDF elsewhere",
                wrapper.display()
            )));
        }
        write_text(path, &files.urdf)?;
        let mut written = vec![path.to_path_buf()];
        if let Some(text) = &files.wrapper {
            write_text(&wrapper, text)?;
            written.push(wrapper);
        }
        Ok((written, Vec::new()))
    }
}
