//! `dyngen.identify_payload`: a tool or grasped object at a frame, with the robot's own
//! parameters held, from joint torques, a force/torque sensor's wrench, or both
//! (`dyngen_identify::identify_payload`); and `Robot.with_body_at`, a robot carrying such a
//! body, to simulate measurements.

use crate::errors::identification_error;
use crate::identification::{estimated_robot_methods, identifiable, positive, ARRAYS};
use crate::robot::Robot;
use crate::samples::DataArrays;
use crate::written::{write_description, Written};
use dyngen_identify::{
    identify_payload as identify, with_body_at, PayloadData, PayloadEstimate, PayloadOptions,
};
use dyngen_model::model::Inertia;
use nalgebra::{Matrix3, Vector3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use std::path::PathBuf;

/// Identifies a payload at `frame` (default: the sensor's frame with a wrench, else the
/// end-effector) from samples: time `t` (N,), positions `q` (N, dof), and joint torques `tau`
/// (N, dof), a force/torque sensor's `wrench` (N, 6: `[f; m]` the load applies to the sensor,
/// in `sensor_frame`'s axes), or both. `data` chooses "torques", "wrench" or "both" (default:
/// what is given). `refit_joint_terms`: re-fit the description's friction, armature and offsets
/// beside the payload.
#[pyfunction]
#[pyo3(signature = (robot, t, q, *, tau=None, wrench=None, sensor_frame=None, qd=None, qdd=None,
    frame=None, data=None, refit_joint_terms=false, cutoff=None))]
#[allow(clippy::too_many_arguments)]
pub fn identify_payload(
    py: Python<'_>,
    robot: &Robot,
    t: &Bound<'_, PyAny>,
    q: &Bound<'_, PyAny>,
    tau: Option<&Bound<'_, PyAny>>,
    wrench: Option<&Bound<'_, PyAny>>,
    sensor_frame: Option<String>,
    qd: Option<&Bound<'_, PyAny>>,
    qdd: Option<&Bound<'_, PyAny>>,
    frame: Option<String>,
    data: Option<&str>,
    refit_joint_terms: bool,
    cutoff: Option<f64>,
) -> PyResult<Payload> {
    let model = identifiable(&robot.data)?;
    for name in frame.iter().chain(&sensor_frame) {
        robot.data.frame_index(name)?;
    }
    let options = PayloadOptions {
        frame,
        data: match data {
            None => None,
            Some("torques") => Some(PayloadData::Torques),
            Some("wrench") => Some(PayloadData::Wrench),
            Some("both") => Some(PayloadData::Both),
            Some(other) => {
                return Err(PyValueError::new_err(format!(
                    "data: expected \"torques\", \"wrench\" or \"both\", found '{other}'"
                )))
            }
        },
        refit_joint_terms,
        cutoff: positive("cutoff", cutoff.unwrap_or(PayloadOptions::default().cutoff))?,
    };
    let samples = DataArrays {
        t,
        q,
        qd,
        qdd,
        tau,
        wrench,
        sensor_frame,
    }
    .samples(model)?;
    let estimate = py
        .detach(|| identify(model, &samples, &options))
        .map_err(|e| identification_error(py, &e))?;
    Ok(Payload { estimate })
}

/// An identified payload: its mass, centre of mass and inertia in its frame, and the robot
/// carrying it (`robot`: the payload welded to the body that carries the frame).
#[pyclass(module = "dyngen", frozen)]
pub struct Payload {
    estimate: PayloadEstimate,
}

estimated_robot_methods!(Payload);

#[pymethods]
impl Payload {
    /// The frame the payload is given in.
    #[getter]
    fn frame(&self) -> String {
        self.estimate.frame.clone()
    }

    /// Mass (kg).
    #[getter]
    fn mass(&self) -> f64 {
        self.estimate.mass
    }

    /// Centre of mass in the frame (m).
    #[getter]
    fn com(&self) -> [f64; 3] {
        self.estimate.com.into()
    }

    /// Rotational inertia about the centre of mass, in the frame's axes (kg·m²), 3 × 3.
    #[getter]
    fn inertia_com(&self) -> [[f64; 3]; 3] {
        let m = &self.estimate.inertia_com;
        std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
    }

    /// The ten standard parameters `[m, m·c, I_O]` of the payload about the frame's origin.
    #[getter]
    fn parameters(&self) -> Vec<f64> {
        self.estimate.parameters().to_vec()
    }

    /// Names of the least squares' unknowns (the payload's ten, re-fitted joint terms, the
    /// sensor offset), their estimates and standard deviations.
    #[getter]
    fn least_squares(&self) -> (Vec<String>, Vec<f64>, Vec<f64>) {
        let ls = &self.estimate.least_squares;
        (ls.names.clone(), ls.theta_b.clone(), ls.std_dev.clone())
    }

    /// Whether the least-squares payload was not a physical body and this is the nearest that is.
    #[getter]
    fn made_consistent(&self) -> bool {
        self.estimate.made_consistent
    }

    /// The sensor's offset `[f; m]`, when a wrench was used.
    #[getter]
    fn sensor_offset(&self) -> Option<[f64; 6]> {
        self.estimate.sensor_offset
    }

    /// Samples used.
    #[getter]
    fn samples_used(&self) -> usize {
        self.estimate.samples_used
    }

    /// Writes the robot with the payload as dyngen YAML to `path`; returns the files written and
    /// the loader's warnings about it.
    #[pyo3(signature = (path, source=ARRAYS))]
    fn write(&self, py: Python<'_>, path: PathBuf, source: &str) -> PyResult<Written> {
        write_description(py, self.estimate.written(source, &path), path)
    }

    fn __repr__(&self) -> String {
        let c = self.estimate.com;
        format!(
            "<dyngen.Payload at '{}': {:.4} kg, centre of mass [{:.4}, {:.4}, {:.4}] m>",
            self.estimate.frame, self.estimate.mass, c[0], c[1], c[2]
        )
    }
}

#[pymethods]
impl Robot {
    /// This robot with a rigid body welded to the body that carries `frame`: `mass` (kg),
    /// centre of mass `com` (m) and inertia about it `inertia_com` (3 × 3, kg·m²) in the frame's
    /// coordinates. To simulate a payload.
    fn with_body_at(
        &self,
        frame: &str,
        mass: f64,
        com: [f64; 3],
        inertia_com: [[f64; 3]; 3],
    ) -> PyResult<Robot> {
        let model = identifiable(&self.data)?;
        self.data.frame_index(frame)?;
        let inertia = Matrix3::from_fn(|i, j| inertia_com[i][j]);
        let finite = mass.is_finite() && com.iter().chain(inertia.iter()).all(|x| x.is_finite());
        let symmetric = (inertia - inertia.transpose()).amax() <= 1e-12 * inertia.amax().max(1.0);
        let moments = inertia.symmetric_eigenvalues();
        if !finite || mass <= 0.0 || !symmetric || moments.min() < 0.0 {
            return Err(PyValueError::new_err(
                "with_body_at: the body needs a positive finite mass, a finite centre of mass and a \
                 symmetric positive semi-definite inertia",
            ));
        }
        let body = Inertia {
            mass,
            com: Vector3::from(com),
            inertia_com: inertia,
        };
        let carrying = with_body_at(model, frame, &body);
        Ok(Robot::in_memory(carrying))
    }
}
