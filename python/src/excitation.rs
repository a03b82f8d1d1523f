//! `dyngen.excite`: an excitation trajectory for identification (`optimise_within`: a periodic
//! Fourier series within the joint limits, optimised for a well-conditioned base regressor,
//! optionally keeping frames inside boxes and above planes), sampled into arrays.

use crate::arrays::rows;
use crate::identification::{identifiable, positive};
use crate::robot::Robot;
use dyngen_identify::{
    optimise_within, BaseModel, Excitation as Optimised, ExcitationOptions, Region, TrajectoryLimits,
    Workspace, WorkspaceConstraint, DEFAULT_ACCELERATION_PER_VELOCITY,
};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A workspace region as Python gives it: `(frame or None, min (3,), max (3,))` for a box,
/// `(frame or None, normal (3,), offset)` for the side of a plane.
type BoxArgument = (Option<String>, [f64; 3], [f64; 3]);
type PlaneArgument = (Option<String>, [f64; 3], f64);

/// Optimises an excitation trajectory for `robot`: `harmonics` harmonics of `base_frequency`
/// Hz (the period is its inverse), within the joint position and velocity limits and
/// accelerations of `acceleration_per_velocity` × the velocity limit; `boxes` keep a frame's
/// origin inside `(frame, min, max)`, `above` on the side of `(frame, normal, offset)` the
/// normal points to (`frame` None: the end-effector). The search: `starts` random starts,
/// then `iterations` steps of an evolution strategy from `seed`, each candidate evaluated on
/// `samples` states.
#[pyfunction]
#[pyo3(signature = (robot, *, base_frequency=None, harmonics=None, iterations=None, starts=None,
    samples=None, seed=None, acceleration_per_velocity=DEFAULT_ACCELERATION_PER_VELOCITY,
    boxes=Vec::new(), above=Vec::new()))]
#[allow(clippy::too_many_arguments)]
pub fn excite(
    py: Python<'_>,
    robot: &Robot,
    base_frequency: Option<f64>,
    harmonics: Option<usize>,
    iterations: Option<usize>,
    starts: Option<usize>,
    samples: Option<usize>,
    seed: Option<u64>,
    acceleration_per_velocity: f64,
    boxes: Vec<BoxArgument>,
    above: Vec<PlaneArgument>,
) -> PyResult<Excitation> {
    let model = identifiable(&robot.data)?;
    let defaults = ExcitationOptions::default();
    let options = ExcitationOptions {
        base_frequency: positive(
            "base_frequency",
            base_frequency.unwrap_or(defaults.base_frequency),
        )?,
        harmonics: harmonics.unwrap_or(defaults.harmonics),
        iterations: iterations.unwrap_or(defaults.iterations),
        starts: starts.unwrap_or(defaults.starts),
        samples: samples.unwrap_or(defaults.samples),
        seed: seed.unwrap_or(defaults.seed),
    };
    if options.harmonics == 0 || options.samples == 0 {
        return Err(PyValueError::new_err("harmonics and samples must be at least 1"));
    }
    positive("acceleration_per_velocity", acceleration_per_velocity)?;
    let frame = |f: Option<String>| f.unwrap_or_else(|| model.end_effector().name.clone());
    let finite = |what: &str, values: &[f64]| match values.iter().all(|v| v.is_finite()) {
        true => Ok(()),
        false => Err(PyValueError::new_err(format!(
            "{what}: every number must be finite, found {values:?}"
        ))),
    };
    let mut constraints = Vec::new();
    for (f, min, max) in boxes {
        finite("boxes", &[min, max].concat())?;
        constraints.push(WorkspaceConstraint {
            frame: frame(f),
            region: Region::between(min, max),
        });
    }
    for (f, normal, offset) in above {
        finite("above", &[normal[0], normal[1], normal[2], offset])?;
        constraints.push(WorkspaceConstraint {
            frame: frame(f),
            region: Region::above(normal, offset),
        });
    }
    let workspace = Workspace::new(model, &constraints).map_err(|e| PyValueError::new_err(e.to_string()))?;
    let limits = TrajectoryLimits::from_model(model, acceleration_per_velocity);
    let optimised = py
        .detach(|| optimise_within(&BaseModel::new(model), &limits, &workspace, &options))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(Excitation { optimised })
}

/// An optimised excitation trajectory: `sample(t)` gives positions, velocities and
/// accelerations along it.
#[pyclass(module = "dyngen", frozen)]
pub struct Excitation {
    optimised: Optimised,
}

#[pymethods]
impl Excitation {
    /// `(q, qd, qdd)` at the times `t` (N,): three (N, dof) arrays.
    fn sample<'py>(
        &self,
        py: Python<'py>,
        t: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, pyo3::types::PyTuple>> {
        let times: Vec<f64> = rows("t", t, 0)?.into_iter().map(|r| r[0]).collect();
        let trajectory = &self.optimised.trajectory;
        let n = trajectory.dof();
        let (q, qd, qdd) = py.detach(|| {
            let mut out = [Vec::new(), Vec::new(), Vec::new()];
            for &time in &times {
                let s = trajectory.at(time);
                out[0].extend(s.q);
                out[1].extend(s.qd);
                out[2].extend(s.qdd);
            }
            let [q, qd, qdd] = out;
            (q, qd, qdd)
        });
        let array = |values: Vec<f64>| -> PyResult<Bound<'py, PyArray2<f64>>> {
            Array2::from_shape_vec((times.len(), n), values)
                .map(|a| a.into_pyarray(py))
                .map_err(|e| PyValueError::new_err(format!("internal error: {e}")))
        };
        pyo3::types::PyTuple::new(py, [array(q)?, array(qd)?, array(qdd)?])
    }

    /// The period (s): the trajectory repeats after it.
    #[getter]
    fn period(&self) -> f64 {
        self.optimised.trajectory.period()
    }

    /// Condition number of the column-scaled base regressor stacked along the trajectory.
    #[getter]
    fn condition_number(&self) -> f64 {
        self.optimised.condition_number
    }

    /// The median condition number of random trajectories within the same limits.
    #[getter]
    fn random_condition_number(&self) -> f64 {
        self.optimised.random_condition_number
    }

    /// The smallest distance (m) of a constrained frame inside its region over the whole
    /// period, proven; None without workspace constraints.
    #[getter]
    fn workspace_margin(&self) -> Option<f64> {
        self.optimised.workspace.as_ref().map(|w| w.guaranteed_margin)
    }

    /// The Fourier coefficients: offsets `q0` (dof,) and the velocity amplitudes `a`, `b`
    /// (dof, harmonics) of `q̇_j(t) = Σ_l a_jl cos(ω l t) + b_jl sin(ω l t)`, `ω = 2π f`.
    #[getter]
    fn coefficients(&self) -> (Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let t = &self.optimised.trajectory;
        (t.offsets.clone(), t.a.clone(), t.b.clone())
    }

    fn __repr__(&self) -> String {
        format!(
            "<dyngen.Excitation: period {} s, condition number {:.1} (random: {:.1})>",
            self.period(),
            self.optimised.condition_number,
            self.optimised.random_condition_number
        )
    }
}
