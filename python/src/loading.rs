//! The options of `Robot.load` and `compile`: the keys of the description's choices the
//! command line offers (`cli/src/loading.rs`), as Python spells them, into one [`Choices`].

use dyngen_model::description::{Choices, FrameSelection, FrameSpec, NonPhysicalInertia};
use dyngen_model::Functions;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

/// The loading options as Python passes them.
pub struct LoadingOptions<'py> {
    pub end_effector: Option<String>,
    pub frames: Option<Bound<'py, PyAny>>,
    pub locked_joints: Option<Bound<'py, PyAny>>,
    pub gravity: Option<Vec<f64>>,
    pub snap_angles: Option<f64>,
    pub inertia: Option<String>,
    pub floating_base: bool,
}

impl LoadingOptions<'_> {
    /// The options as one [`Choices`], with `functions` (of `compile`); a key left at `None`
    /// chooses nothing.
    pub fn choices(&self, functions: Option<Functions>) -> PyResult<Choices> {
        Ok(Choices {
            functions,
            snap_angles: self.snap_angles,
            end_effector: self.end_effector.as_deref().map(FrameSpec::link),
            frames: frames(self.frames.as_ref())?,
            locked_joints: locked_joints(self.locked_joints.as_ref())?,
            gravity: gravity(self.gravity.as_deref())?,
            inertia: inertia(self.inertia.as_deref())?,
            floating_base: self.floating_base,
            ..Choices::default()
        })
    }
}

/// `frames`: `None`, `"all"`, or a list of link names.
fn frames(value: Option<&Bound<'_, PyAny>>) -> PyResult<FrameSelection> {
    let Some(value) = value else {
        return Ok(FrameSelection::EndEffector);
    };
    if let Ok(text) = value.cast::<PyString>() {
        return match text.to_cow()?.as_ref() {
            "all" => Ok(FrameSelection::AllLinks),
            other => Err(PyValueError::new_err(format!(
                "frames: expected \"all\" or a list of link names, found '{other}' (one frame is a list: frames=['{other}'])"
            ))),
        };
    }
    let names: Vec<String> = value
        .extract()
        .map_err(|_| PyValueError::new_err("frames: expected \"all\" or a list of link names"))?;
    Ok(match names.is_empty() {
        true => FrameSelection::EndEffector,
        false => FrameSelection::Listed(names.into_iter().map(FrameSpec::link).collect()),
    })
}

/// `locked_joints`: a dict (or a list of pairs) from joint name to position, in order.
fn locked_joints(value: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<(String, f64)>> {
    let Some(value) = value else {
        return Ok(Vec::new());
    };
    let pairs: Vec<(String, f64)> = match value.cast::<PyDict>() {
        Ok(dict) => dict
            .iter()
            .map(|(k, v)| Ok((k.extract::<String>()?, v.extract::<f64>()?)))
            .collect::<PyResult<_>>(),
        Err(_) => value.extract(),
    }
    .map_err(|_| {
        PyValueError::new_err(
            "locked_joints: expected a dict from joint name to position, e.g. {'panda_finger_joint1': 0.0}",
        )
    })?;
    match pairs.iter().find(|(_, p)| !p.is_finite()) {
        Some((joint, p)) => Err(PyValueError::new_err(format!(
            "locked_joints: the position of joint '{joint}' must be finite, found {p}"
        ))),
        None => Ok(pairs),
    }
}

/// `gravity`: three finite numbers, m/s² in the base frame.
fn gravity(value: Option<&[f64]>) -> PyResult<Option<[f64; 3]>> {
    let Some(value) = value else {
        return Ok(None);
    };
    match <[f64; 3]>::try_from(value) {
        Ok(g) if g.iter().all(|x| x.is_finite()) => Ok(Some(g)),
        _ => Err(PyValueError::new_err(format!(
            "gravity: expected three finite numbers (x, y, z) in m/s², found {value:?}"
        ))),
    }
}

/// `inertia`: `"as_written"`, `"repair"` or `"strict"`.
fn inertia(value: Option<&str>) -> PyResult<NonPhysicalInertia> {
    let choices = [
        NonPhysicalInertia::AsWritten,
        NonPhysicalInertia::Repair,
        NonPhysicalInertia::Strict,
    ];
    match value {
        None => Ok(NonPhysicalInertia::default()),
        Some(text) => choices
            .into_iter()
            .find(|c| c.keyword() == text.replace('-', "_"))
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "inertia: expected \"as_written\", \"repair\" or \"strict\", found '{text}'"
                ))
            }),
    }
}

/// `functions` of `compile`: a list of group names, or `"all"`.
pub fn functions(value: Option<&Bound<'_, PyAny>>) -> PyResult<Option<Functions>> {
    let Some(value) = value else {
        return Ok(None);
    };
    let keywords: Vec<String> = match value.cast::<PyString>() {
        Ok(text) => vec![text.to_cow()?.into_owned()],
        Err(_) => value
            .extract()
            .map_err(|_| PyValueError::new_err("functions: expected a list of group names, or \"all\""))?,
    };
    Functions::from_keywords(keywords.iter().map(String::as_str))
        .map(Some)
        .map_err(|e| PyValueError::new_err(format!("functions: {e}")))
}
