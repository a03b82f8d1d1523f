//! Measured data from arrays: what `dyngen identify` reads from a data file's columns, given
//! as numpy arrays (one row per sample, joints in the order of `Robot.joint_names`), checked
//! as the data file is: finite numbers, one length, time strictly increasing, positions and
//! velocities within the joint limits.

use crate::arrays::rows;
use dyngen_identify::Samples;
use dyngen_model::model::Model;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The arrays of one data set, as Python passes them.
pub struct DataArrays<'a, 'py> {
    pub t: &'a Bound<'py, PyAny>,
    pub q: &'a Bound<'py, PyAny>,
    pub qd: Option<&'a Bound<'py, PyAny>>,
    pub qdd: Option<&'a Bound<'py, PyAny>>,
    pub tau: Option<&'a Bound<'py, PyAny>>,
    pub wrench: Option<&'a Bound<'py, PyAny>>,
    pub sensor_frame: Option<String>,
}

impl DataArrays<'_, '_> {
    /// The samples for `model`, checked.
    pub fn samples(&self, model: &Model) -> PyResult<Samples> {
        let n = model.dof();
        let time: Vec<f64> = rows("t", self.t, 0)?.into_iter().map(|r| r[0]).collect();
        let joints = |name: &str, value: Option<&Bound<'_, PyAny>>| -> PyResult<Option<Vec<Vec<f64>>>> {
            value.map(|v| rows(name, v, n)).transpose()
        };
        let q = rows("q", self.q, n)?;
        let samples = Samples {
            qd: joints("qd", self.qd)?,
            qdd: joints("qdd", self.qdd)?,
            tau: joints("tau", self.tau)?,
            wrench: self.wrench.map(|w| rows("wrench", w, 6)).transpose()?.map(|w| {
                w.into_iter()
                    .map(|r| [r[0], r[1], r[2], r[3], r[4], r[5]])
                    .collect()
            }),
            sensor_frame: self.sensor_frame.clone(),
            time,
            q,
            ..Samples::default()
        };
        check(model, &samples)?;
        Ok(samples)
    }
}

/// The checks a data file's reader makes on each line, on arrays.
fn check(model: &Model, samples: &Samples) -> PyResult<()> {
    let count = samples.time.len();
    if count == 0 {
        return Err(PyValueError::new_err("no samples: 't' is empty"));
    }
    let lengths = [
        ("q", Some(samples.q.len())),
        ("qd", samples.qd.as_ref().map(Vec::len)),
        ("qdd", samples.qdd.as_ref().map(Vec::len)),
        ("tau", samples.tau.as_ref().map(Vec::len)),
        ("wrench", samples.wrench.as_ref().map(Vec::len)),
    ];
    for (name, length) in lengths {
        if let Some(length) = length.filter(|&l| l != count) {
            return Err(PyValueError::new_err(format!(
                "argument '{name}' has {length} samples, but 't' has {count}: one row per sample"
            )));
        }
    }
    if samples.wrench.is_some() != samples.sensor_frame.is_some() {
        return Err(PyValueError::new_err(
            "a force/torque sensor needs both 'wrench' (N, 6) and 'sensor_frame', the frame it measures in",
        ));
    }
    if let Some(k) = (1..count).find(|&k| samples.time[k] <= samples.time[k - 1]) {
        return Err(PyValueError::new_err(format!(
            "argument 't': time {} at sample {k} does not increase (sample {} is at {})",
            samples.time[k],
            k - 1,
            samples.time[k - 1]
        )));
    }
    for (c, &joint) in model.coordinate_joints().iter().enumerate() {
        let joint = &model.joints()[joint];
        let Some(l) = joint.limits else { continue };
        // The data file's slack: a trajectory written at a limit may land a rounding error
        // beyond it.
        let slack = 1e-9 * (l.upper - l.lower).abs().max(1.0);
        if let Some(k) = samples
            .q
            .iter()
            .position(|q| q[c] < l.lower - slack || q[c] > l.upper + slack)
        {
            return Err(PyValueError::new_err(format!(
                "argument 'q': sample {k}, joint '{}': position {} is outside the joint limits [{}, {}]",
                joint.name, samples.q[k][c], l.lower, l.upper
            )));
        }
        let Some(qd) = samples.qd.as_ref().filter(|_| l.velocity > 0.0) else {
            continue;
        };
        if let Some(k) = qd.iter().position(|v| v[c].abs() > l.velocity * (1.0 + 1e-9)) {
            return Err(PyValueError::new_err(format!(
                "argument 'qd': sample {k}, joint '{}': velocity {} exceeds the velocity limit {}",
                joint.name, qd[k][c], l.velocity
            )));
        }
    }
    Ok(())
}
