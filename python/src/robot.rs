//! `dyngen.Robot`: a loaded description, its sizes and names, its parameters. The dynamics
//! are in `generic.rs` (the generic `f64` algorithms on it).

use crate::errors::description_error;
use crate::loading::LoadingOptions;
use dyngen_model::base_parameters::BaseParameterSet;
use dyngen_model::description::{load_with, Choices};
use dyngen_model::dynamics::{FloatingDynamics, NumericDynamics};
use dyngen_model::model::Model;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;
use std::sync::{Arc, OnceLock};

/// What a robot was loaded from: the file and the caller's choices, so that `compile` can
/// generate the same robot.
#[derive(Clone, Debug)]
pub struct Origin {
    pub path: PathBuf,
    pub choices: Choices,
    /// Every file read (the YAML and the URDF it names).
    pub sources: Vec<PathBuf>,
}

/// A model with its parameters: the description's, or others (`with_parameters`, an
/// identified robot).
pub struct RobotData {
    pub model: Model,
    /// The file and choices it was loaded from; `None` for a robot made in memory.
    pub origin: Option<Origin>,
    /// θ other than the model's own (the layout of `parameters`).
    pub theta: Option<Vec<f64>>,
    pub warnings: Vec<String>,
    pub notes: Vec<String>,
    base: OnceLock<BaseParameterSet>,
}

impl RobotData {
    pub fn new(model: Model, origin: Option<Origin>, warnings: Vec<String>, notes: Vec<String>) -> RobotData {
        RobotData {
            model,
            origin,
            theta: None,
            warnings,
            notes,
            base: OnceLock::new(),
        }
    }

    /// The base parameters of the model (computed once, on first use).
    pub fn base(&self) -> &BaseParameterSet {
        self.base.get_or_init(|| BaseParameterSet::compute(&self.model))
    }

    pub fn is_floating(&self) -> bool {
        self.model.floating_base().is_some()
    }

    /// Length of the configuration `q`.
    pub fn nq(&self) -> usize {
        self.model.nq()
    }

    /// Length of velocities, accelerations and generalised forces.
    pub fn nv(&self) -> usize {
        self.model.nv()
    }

    /// The standard parameters θ these dynamics use.
    pub fn parameters(&self) -> Vec<f64> {
        match (&self.theta, self.floating()) {
            (Some(theta), _) => theta.clone(),
            (None, Some(floating)) => floating.parameters(),
            (None, None) => self.model.parameters(),
        }
    }

    /// Names of the entries of θ.
    pub fn parameter_names(&self) -> Vec<String> {
        match self.is_floating() {
            true => FloatingDynamics::parameter_names(&self.model),
            false => self.model.parameter_names(),
        }
    }

    /// The fixed-base dynamics (`None` on a floating base).
    pub fn fixed(&self) -> Option<NumericDynamics<'_>> {
        match (self.is_floating(), &self.theta) {
            (true, _) => None,
            (false, Some(theta)) => Some(NumericDynamics::with_parameters(&self.model, theta)),
            (false, None) => Some(NumericDynamics::new(&self.model)),
        }
    }

    /// The floating-base dynamics (`None` on a fixed base).
    pub fn floating(&self) -> Option<FloatingDynamics<'_>> {
        match &self.theta {
            Some(theta) => FloatingDynamics::with_parameters(&self.model, theta),
            None => FloatingDynamics::new(&self.model),
        }
    }

    /// The index of frame `name` in the model's frames, or an error listing them.
    pub fn frame_index(&self, name: &str) -> PyResult<usize> {
        let frames = self.model.frames();
        frames.iter().position(|f| f.name == name).ok_or_else(|| {
            let names: Vec<&str> = frames.iter().map(|f| f.name.as_str()).collect();
            PyValueError::new_err(format!(
                "unknown frame '{name}': the robot's frames are {} (load with frames=[...] or frames=\"all\" for more)",
                names.join(", ")
            ))
        })
    }

    /// The coordinates' joint names, in the order of `q` (after the base's seven on a
    /// floating base).
    pub fn joint_names(&self) -> Vec<String> {
        self.model
            .coordinate_joints()
            .into_iter()
            .map(|j| self.model.joints()[j].name.clone())
            .collect()
    }
}

/// A robot description loaded into a model, with its generic `f64` dynamics.
///
/// Every dynamics method takes one state (1-D arrays) or a batch (2-D arrays, one state per
/// row) and returns numpy arrays; a batch's results have the batch first.
#[pyclass(module = "dyngen", frozen)]
pub struct Robot {
    pub data: Arc<RobotData>,
}

impl Robot {
    pub fn from_data(data: RobotData) -> Robot {
        Robot { data: Arc::new(data) }
    }

    /// A robot made in memory (identified, or carrying a payload): no file, nothing the
    /// loader said.
    pub fn in_memory(model: Model) -> Robot {
        Robot::from_data(RobotData::new(model, None, Vec::new(), Vec::new()))
    }
}

#[pymethods]
impl Robot {
    /// Loads a description (URDF, or dyngen YAML) with the choices the command line offers:
    /// `end_effector` (a link), `frames` (a list of links, or "all"), `locked_joints`
    /// ({joint: position}), `gravity` ((x, y, z) in m/s²), `snap_angles` (a tolerance in
    /// radians), `inertia` ("as_written", "repair" or "strict"), `floating_base`.
    ///
    /// Raises `DescriptionError` (with `file`, `line`, `column`, `item`, `problem`) for a
    /// description that cannot be loaded.
    #[staticmethod]
    #[pyo3(signature = (path, *, end_effector=None, frames=None, locked_joints=None, gravity=None,
        snap_angles=None, inertia=None, floating_base=false))]
    #[allow(clippy::too_many_arguments)]
    fn load(
        py: Python<'_>,
        path: PathBuf,
        end_effector: Option<String>,
        frames: Option<Bound<'_, PyAny>>,
        locked_joints: Option<Bound<'_, PyAny>>,
        gravity: Option<Vec<f64>>,
        snap_angles: Option<f64>,
        inertia: Option<String>,
        floating_base: bool,
    ) -> PyResult<Robot> {
        let options = LoadingOptions {
            end_effector,
            frames,
            locked_joints,
            gravity,
            snap_angles,
            inertia,
            floating_base,
        };
        let choices = options.choices(None)?;
        load_robot(py, path, choices)
    }

    /// The robot's name.
    #[getter]
    fn name(&self) -> String {
        self.data.model.name().to_owned()
    }

    /// Number of joint coordinates (without a floating base's six).
    #[getter]
    fn dof(&self) -> usize {
        self.data.model.dof()
    }

    /// Length of the configuration `q` (`dof`, plus 7 on a floating base: position and
    /// quaternion x, y, z, w).
    #[getter]
    fn nq(&self) -> usize {
        self.data.nq()
    }

    /// Length of velocities, accelerations and generalised forces (`dof`, plus the base
    /// twist's 6 on a floating base).
    #[getter]
    fn nv(&self) -> usize {
        self.data.nv()
    }

    /// Whether the root link flies free.
    #[getter]
    fn floating_base(&self) -> bool {
        self.data.is_floating()
    }

    /// The joints of the coordinates, in the order of `q`.
    #[getter]
    fn joint_names(&self) -> Vec<String> {
        self.data.joint_names()
    }

    /// Position limits `(lower, upper)` per coordinate (`None` for a continuous joint).
    #[getter]
    fn joint_limits(&self) -> Vec<Option<(f64, f64)>> {
        let model = &self.data.model;
        model
            .coordinate_joints()
            .into_iter()
            .map(|j| model.joints()[j].limits.map(|l| (l.lower, l.upper)))
            .collect()
    }

    /// The frames the frame functions know: the end-effector first.
    #[getter]
    fn frame_names(&self) -> Vec<String> {
        self.data.model.frames().iter().map(|f| f.name.clone()).collect()
    }

    /// The end-effector frame's name.
    #[getter]
    fn end_effector(&self) -> String {
        self.data.model.end_effector().name.clone()
    }

    /// Gravity in the base frame, m/s².
    #[getter]
    fn gravity_vector(&self) -> [f64; 3] {
        self.data.model.gravity().into()
    }

    /// The standard parameters θ: `[m, m·cx, m·cy, m·cz, Ixx, Ixy, Iyy, Ixz, Iyz, Izz]` per
    /// body about its joint origin (a floating base's body first), then the joint-level ones.
    #[getter]
    fn parameters(&self) -> Vec<f64> {
        self.data.parameters()
    }

    /// Names of the entries of `parameters`, e.g. "mcx[panda_link3]".
    #[getter]
    fn parameter_names(&self) -> Vec<String> {
        self.data.parameter_names()
    }

    /// Names of the base parameters, e.g. "Izz[link2] + Iyy[link3] + 0.0625·m[link3]".
    #[getter]
    fn base_parameter_names(&self) -> Vec<String> {
        self.data.base().names.clone()
    }

    /// The standard parameters kept as base parameters (columns of the regressor), ascending.
    #[getter]
    fn base_parameter_columns(&self) -> Vec<usize> {
        self.data.base().columns.clone()
    }

    /// The base parameters θ_b of `theta` (default: this robot's θ), with `Y_b θ_b = Y θ`.
    #[pyo3(signature = (theta=None))]
    fn base_parameters(&self, theta: Option<Vec<f64>>) -> PyResult<Vec<f64>> {
        let theta = match theta {
            Some(theta) => checked_parameters(&self.data, theta)?,
            None => self.data.parameters(),
        };
        Ok(self.data.base().base_parameters(&theta))
    }

    /// The same robot with the standard parameters `theta` (the layout of `parameters`).
    fn with_parameters(&self, theta: Vec<f64>) -> PyResult<Robot> {
        let theta = checked_parameters(&self.data, theta)?;
        let data = &self.data;
        let mut copy = RobotData::new(
            data.model.clone(),
            None,
            data.warnings.clone(),
            data.notes.clone(),
        );
        copy.theta = Some(theta);
        if let Some(base) = data.base.get() {
            let _ = copy.base.set(base.clone());
        }
        Ok(Robot::from_data(copy))
    }

    /// What the loader warned about (suspicious but legal values), one line each.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.data.warnings.clone()
    }

    /// What the loader noted (the end-effector it chose, angles it snapped), one line each.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.data.notes.clone()
    }

    /// The description file, or None for a robot made in memory (identified).
    #[getter]
    fn path(&self) -> Option<PathBuf> {
        self.data.origin.as_ref().map(|o| o.path.clone())
    }

    fn __repr__(&self) -> String {
        let model = &self.data.model;
        format!(
            "<dyngen.Robot '{}': {} DOF{}, {} parameters, {} frames>",
            model.name(),
            model.dof(),
            if self.data.is_floating() {
                " on a floating base"
            } else {
                ""
            },
            self.data.parameter_names().len(),
            model.frames().len()
        )
    }
}

/// Loads `path` with `choices` into a robot, or raises the loader's error.
pub fn load_robot(py: Python<'_>, path: PathBuf, choices: Choices) -> PyResult<Robot> {
    let loaded = py
        .detach(|| load_with(&path, &choices))
        .map_err(|e| description_error(py, &e))?;
    let origin = Origin {
        path,
        choices,
        sources: loaded.sources,
    };
    Ok(Robot::from_data(RobotData::new(
        loaded.model,
        Some(origin),
        loaded.warnings,
        loaded.notes,
    )))
}

/// `theta` checked: the robot's number of parameters, every one finite.
fn checked_parameters(data: &RobotData, theta: Vec<f64>) -> PyResult<Vec<f64>> {
    let expected = data.parameter_names().len();
    if theta.len() != expected {
        return Err(PyValueError::new_err(format!(
            "theta has {} entries, but the robot has {expected} parameters",
            theta.len()
        )));
    }
    match theta.iter().position(|x| !x.is_finite()) {
        Some(k) => Err(PyValueError::new_err(format!(
            "theta[{k}] ({}) is {}: every parameter must be finite",
            data.parameter_names()[k],
            theta[k]
        ))),
        None => Ok(theta),
    }
}
