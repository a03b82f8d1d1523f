//! The dynamics of a `dyngen.Robot` on dyngen's generic `f64` algorithms
//! (`NumericDynamics`, `FloatingDynamics` on a floating base), one state or a batch.
//!
//! Names and argument orders are those of `docs/dynamics.md`; on a floating base `qd`, `v`,
//! `a`, `qdd` and `tau` are of length `nv` (base twist first) and `q` of length `nq`.

use crate::arrays::{batch, evaluate, write_matrix, Argument};
use crate::reference::reference_frame;
use crate::robot::{Robot, RobotData};
use dyngen_model::dynamics::{FloatingDynamics, FloatingState, NumericDynamics};
use nalgebra::{DMatrix, Matrix3, Vector3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The dynamics of one robot, fixed or floating.
enum Dynamics<'a> {
    Fixed(NumericDynamics<'a>),
    Floating(FloatingDynamics<'a>),
}

impl RobotData {
    fn dynamics(&self) -> Dynamics<'_> {
        match (self.fixed(), self.floating()) {
            (Some(fixed), _) => Dynamics::Fixed(fixed),
            (None, Some(floating)) => Dynamics::Floating(floating),
            (None, None) => unreachable!("a model's base is fixed or floating"),
        }
    }
}

/// A floating base's configuration, checked (a unit quaternion).
fn state(dynamics: &FloatingDynamics<'_>, q: &[f64]) -> Result<FloatingState, String> {
    dynamics.state(q).map_err(|e| e.to_string())
}

fn write_pose(out: &mut [&mut [f64]], (rotation, translation): (Matrix3<f64>, Vector3<f64>)) {
    write_matrix(out[0], &rotation);
    out[1].copy_from_slice(translation.as_slice());
}

fn write_pair(out: &mut [&mut [f64]], (first, second): (DMatrix<f64>, DMatrix<f64>)) {
    write_matrix(out[0], &first);
    write_matrix(out[1], &second);
}

fn arg<'a, 'py>(name: &'a str, value: &'a Bound<'py, PyAny>, length: usize) -> Argument<'a, 'py> {
    Argument { name, value, length }
}

impl Robot {
    /// An error for a method that needs a floating base, on a fixed one.
    fn needs_floating_base(&self, method: &str) -> PyResult<FloatingDynamics<'_>> {
        self.data.floating().ok_or_else(|| {
            PyValueError::new_err(format!(
                "{method} needs a floating base: load the robot with floating_base=True"
            ))
        })
    }

    /// An error for a method of the fixed-base dynamics only, on a floating base.
    fn needs_fixed_base(&self, method: &str) -> PyResult<NumericDynamics<'_>> {
        self.data
            .fixed()
            .ok_or_else(|| PyValueError::new_err(format!("{method} is computed for a fixed base only")))
    }
}

#[pymethods]
impl Robot {
    /// End-effector pose in the base frame (the world on a floating base): `(rotation (3, 3),
    /// translation (3,))`.
    fn end_effector_pose(&self, py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        self.frame_pose(py, &self.data.model.end_effector().name.clone(), q)
    }

    /// `J(q)` of the end-effector (6 × nv, rows `[linear; angular]`, base axes at the frame's
    /// origin: Pinocchio's LOCAL_WORLD_ALIGNED).
    fn jacobian(&self, py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let frame = self.data.model.end_effector().name.clone();
        self.frame_jacobian(py, &frame, q, "local_world_aligned")
    }

    /// `J̇(q, q̇)` of the end-effector, the time derivative of `jacobian`.
    fn jacobian_dot(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let frame = self.data.model.end_effector().name.clone();
        self.frame_jacobian_time_variation(py, &frame, q, qd, "local_world_aligned")
    }

    /// The pose of frame `frame`: `(rotation (3, 3), translation (3,))`.
    fn frame_pose(&self, py: Python<'_>, frame: &str, q: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let index = data.frame_index(frame)?;
        let batch = batch(&[arg("q", q, data.nq())])?;
        let dynamics = data.dynamics();
        let zero = vec![0.0; data.nv()];
        evaluate(py, &batch, &[&[3, 3], &[3]], |x, out| {
            let pose = match &dynamics {
                Dynamics::Fixed(d) => d.frame_motion(frame, x[0], &zero).expect("a known frame").pose(),
                Dynamics::Floating(d) => d.frame_pose(&state(d, x[0])?, index),
            };
            write_pose(out, pose);
            Ok(())
        })?
        .into_python(py)
    }

    /// `J` of frame `frame` (6 × nv) in `reference`: "local", "world" or
    /// "local_world_aligned" (Pinocchio's reference frames).
    #[pyo3(signature = (frame, q, reference="local_world_aligned"))]
    fn frame_jacobian(
        &self,
        py: Python<'_>,
        frame: &str,
        q: &Bound<'_, PyAny>,
        reference: &str,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let (index, reference) = (data.frame_index(frame)?, reference_frame(reference)?);
        let batch = batch(&[arg("q", q, data.nq())])?;
        let dynamics = data.dynamics();
        let zero = vec![0.0; data.nv()];
        evaluate(py, &batch, &[&[6, data.nv()]], |x, out| {
            let j = match &dynamics {
                Dynamics::Fixed(d) => d
                    .frame_motion(frame, x[0], &zero)
                    .expect("a known frame")
                    .jacobian(reference),
                Dynamics::Floating(d) => d.frame_jacobian(&state(d, x[0])?, index, reference),
            };
            write_matrix(out[0], &j);
            Ok(())
        })?
        .into_python(py)
    }

    /// `J̇` of frame `frame` in `reference`, the time derivative of `frame_jacobian`.
    #[pyo3(signature = (frame, q, qd, reference="local_world_aligned"))]
    fn frame_jacobian_time_variation(
        &self,
        py: Python<'_>,
        frame: &str,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        reference: &str,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let (index, reference) = (data.frame_index(frame)?, reference_frame(reference)?);
        let batch = batch(&[arg("q", q, data.nq()), arg("qd", qd, data.nv())])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[6, data.nv()]], |x, out| {
            let j = match &dynamics {
                Dynamics::Fixed(d) => d
                    .frame_motion(frame, x[0], x[1])
                    .expect("a known frame")
                    .jacobian_time_variation(reference),
                Dynamics::Floating(d) => {
                    d.frame_jacobian_time_variation(&state(d, x[0])?, x[1], index, reference)
                }
            };
            write_matrix(out[0], &j);
            Ok(())
        })?
        .into_python(py)
    }

    /// The velocity `J q̇` of frame `frame` in `reference`, `[linear; angular]` (6,).
    #[pyo3(signature = (frame, q, qd, reference="local_world_aligned"))]
    fn frame_velocity(
        &self,
        py: Python<'_>,
        frame: &str,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        reference: &str,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let (index, reference) = (data.frame_index(frame)?, reference_frame(reference)?);
        let batch = batch(&[arg("q", q, data.nq()), arg("qd", qd, data.nv())])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[6]], |x, out| {
            let v = match &dynamics {
                Dynamics::Fixed(d) => d
                    .frame_motion(frame, x[0], x[1])
                    .expect("a known frame")
                    .velocity(reference),
                Dynamics::Floating(d) => d.frame_velocity(&state(d, x[0])?, x[1], index, reference),
            };
            out[0].copy_from_slice(v.as_slice());
            Ok(())
        })?
        .into_python(py)
    }

    /// The classical acceleration of frame `frame` at `q̈` in `reference` (Pinocchio's
    /// `getFrameClassicalAcceleration`), `[linear; angular]` (6,).
    #[pyo3(signature = (frame, q, qd, qdd, reference="local_world_aligned"))]
    fn frame_classical_acceleration(
        &self,
        py: Python<'_>,
        frame: &str,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        qdd: &Bound<'_, PyAny>,
        reference: &str,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let (index, reference) = (data.frame_index(frame)?, reference_frame(reference)?);
        let nv = data.nv();
        let batch = batch(&[arg("q", q, data.nq()), arg("qd", qd, nv), arg("qdd", qdd, nv)])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[6]], |x, out| {
            let a = match &dynamics {
                Dynamics::Fixed(d) => d
                    .frame_motion(frame, x[0], x[1])
                    .expect("a known frame")
                    .classical_acceleration(reference, x[2]),
                Dynamics::Floating(d) => {
                    d.frame_classical_acceleration(&state(d, x[0])?, x[1], x[2], index, reference)
                }
            };
            out[0].copy_from_slice(a.as_slice());
            Ok(())
        })?
        .into_python(py)
    }

    /// The mass matrix `D(q)` (nv × nv).
    fn mass_matrix(&self, py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let nv = data.nv();
        let batch = batch(&[arg("q", q, data.nq())])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[nv, nv]], |x, out| {
            let m = match &dynamics {
                Dynamics::Fixed(d) => d.mass_matrix(x[0]),
                Dynamics::Floating(d) => d.mass_matrix(&state(d, x[0])?),
            };
            write_matrix(out[0], &m);
            Ok(())
        })?
        .into_python(py)
    }

    /// The Christoffel-consistent Coriolis matrix `C(q, q̇)` (nv × nv), `Ḋ = C + Cᵀ`.
    fn coriolis_matrix(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let nv = data.nv();
        let batch = batch(&[arg("q", q, data.nq()), arg("qd", qd, nv)])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[nv, nv]], |x, out| {
            let m = match &dynamics {
                Dynamics::Fixed(d) => d.coriolis_matrix(x[0], x[1]),
                Dynamics::Floating(d) => d.coriolis_matrix(&state(d, x[0])?, x[1]),
            };
            write_matrix(out[0], &m);
            Ok(())
        })?
        .into_python(py)
    }

    /// Generalised gravity `g(q)` (nv,): the torques that hold the robot still.
    fn gravity(&self, py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let batch = batch(&[arg("q", q, data.nq())])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[data.nv()]], |x, out| {
            let g = match &dynamics {
                Dynamics::Fixed(d) => d.gravity_torque(x[0]),
                Dynamics::Floating(d) => d.gravity(&state(d, x[0])?),
            };
            out[0].copy_from_slice(g.as_slice());
            Ok(())
        })?
        .into_python(py)
    }

    /// Inverse dynamics `τ = D q̈ + C q̇ + g` (nv,), joint-level terms included.
    fn inverse_dynamics(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        qdd: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let nv = data.nv();
        let batch = batch(&[arg("q", q, data.nq()), arg("qd", qd, nv), arg("qdd", qdd, nv)])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[nv]], |x, out| {
            let tau = match &dynamics {
                Dynamics::Fixed(d) => d.inverse_dynamics(x[0], x[1], x[2]),
                Dynamics::Floating(d) => d.inverse_dynamics(&state(d, x[0])?, x[1], x[2]),
            };
            out[0].copy_from_slice(tau.as_slice());
            Ok(())
        })?
        .into_python(py)
    }

    /// The Slotine–Li torque `D a + C(q, q̇) v + g` (nv,).
    fn slotine_li(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        v: &Bound<'_, PyAny>,
        a: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let nv = data.nv();
        let batch = batch(&[
            arg("q", q, data.nq()),
            arg("qd", qd, nv),
            arg("v", v, nv),
            arg("a", a, nv),
        ])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[nv]], |x, out| {
            let tau = match &dynamics {
                Dynamics::Fixed(d) => d.slotine_li(x[0], x[1], x[2], x[3], true),
                Dynamics::Floating(d) => d.slotine_li(&state(d, x[0])?, x[1], x[2], x[3]),
            };
            out[0].copy_from_slice(tau.as_slice());
            Ok(())
        })?
        .into_python(py)
    }

    /// The Slotine–Li regressor `Y(q, q̇, v, a)` (nv × P), `Y θ = slotine_li(q, q̇, v, a)`.
    fn regressor(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        v: &Bound<'_, PyAny>,
        a: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        self.regressors(py, &[("q", q), ("qd", qd), ("v", v), ("a", a)], false)
    }

    /// The inverse-dynamics regressor `Y(q, q̇, q̇, q̈)` (nv × P), `Y θ = τ`.
    fn torque_regressor(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        qdd: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        self.regressors(py, &[("q", q), ("qd", qd), ("qdd", qdd)], false)
    }

    /// The base regressor `Y_b(q, q̇, v, a)` (nv × B), `Y_b θ_b = Y θ`.
    fn base_regressor(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        v: &Bound<'_, PyAny>,
        a: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        self.regressors(py, &[("q", q), ("qd", qd), ("v", v), ("a", a)], true)
    }

    /// The base torque regressor `Y_b(q, q̇, q̇, q̈)` (nv × B), `Y_b θ_b = τ`.
    fn base_torque_regressor(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        qdd: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        self.regressors(py, &[("q", q), ("qd", qd), ("qdd", qdd)], true)
    }

    /// Forward dynamics `q̈ = D⁻¹ (τ − C q̇ − g)` (nv,).
    fn forward_dynamics(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        tau: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let nv = data.nv();
        let batch = batch(&[arg("q", q, data.nq()), arg("qd", qd, nv), arg("tau", tau, nv)])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[nv]], |x, out| {
            let qdd = match &dynamics {
                Dynamics::Fixed(d) => d.forward_dynamics(x[0], x[1], x[2]),
                Dynamics::Floating(d) => d.forward_dynamics(&state(d, x[0])?, x[1], x[2]),
            };
            out[0].copy_from_slice(qdd.as_slice());
            Ok(())
        })?
        .into_python(py)
    }

    /// `D(q)⁻¹` (nv × nv).
    fn mass_matrix_inverse(&self, py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let nv = data.nv();
        let batch = batch(&[arg("q", q, data.nq())])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[nv, nv]], |x, out| {
            let m = match &dynamics {
                Dynamics::Fixed(d) => d.mass_matrix_inverse(x[0]),
                Dynamics::Floating(d) => d.mass_matrix_inverse(&state(d, x[0])?),
            };
            write_matrix(out[0], &m);
            Ok(())
        })?
        .into_python(py)
    }

    /// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics (nv × nv each; `∂τ/∂q̈ = D`). On a floating base
    /// `q` moves in the tangent space (nv columns).
    fn inverse_dynamics_derivatives(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        qdd: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let nv = data.nv();
        let batch = batch(&[arg("q", q, data.nq()), arg("qd", qd, nv), arg("qdd", qdd, nv)])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[nv, nv], &[nv, nv]], |x, out| {
            let pair = match &dynamics {
                Dynamics::Fixed(d) => d.inverse_dynamics_derivatives(x[0], x[1], x[2]),
                Dynamics::Floating(d) => d.inverse_dynamics_derivatives(&state(d, x[0])?, x[1], x[2]),
            };
            write_pair(out, pair);
            Ok(())
        })?
        .into_python(py)
    }

    /// `(∂q̈/∂q, ∂q̈/∂q̇)` of forward dynamics (nv × nv each; `∂q̈/∂τ = D⁻¹`).
    fn forward_dynamics_derivatives(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        tau: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let nv = data.nv();
        let batch = batch(&[arg("q", q, data.nq()), arg("qd", qd, nv), arg("tau", tau, nv)])?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[nv, nv], &[nv, nv]], |x, out| {
            let pair = match &dynamics {
                Dynamics::Fixed(d) => d.forward_dynamics_derivatives(x[0], x[1], x[2]),
                Dynamics::Floating(d) => d.forward_dynamics_derivatives(&state(d, x[0])?, x[1], x[2]),
            };
            write_pair(out, pair);
            Ok(())
        })?
        .into_python(py)
    }

    /// The total energy's regressor `e_H(q, q̇)` (P,): `e_H θ = T + V` (fixed base).
    fn energy_regressor(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let dynamics = self.needs_fixed_base("energy_regressor")?;
        let n = self.data.nv();
        let batch = batch(&[arg("q", q, n), arg("qd", qd, n)])?;
        let p = self.data.parameter_names().len();
        evaluate(py, &batch, &[&[p]], |x, out| {
            out[0].copy_from_slice(dynamics.energy_regressor(x[0], x[1]).as_slice());
            Ok(())
        })?
        .into_python(py)
    }

    /// Centre of mass in the world (3,) (floating base).
    fn center_of_mass(&self, py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let dynamics = self.needs_floating_base("center_of_mass")?;
        let batch = batch(&[arg("q", q, self.data.nq())])?;
        evaluate(py, &batch, &[&[3]], |x, out| {
            out[0].copy_from_slice(dynamics.center_of_mass(&state(&dynamics, x[0])?).as_slice());
            Ok(())
        })?
        .into_python(py)
    }

    /// The Jacobian of the centre of mass (3 × nv) (floating base).
    fn center_of_mass_jacobian(&self, py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let dynamics = self.needs_floating_base("center_of_mass_jacobian")?;
        let batch = batch(&[arg("q", q, self.data.nq())])?;
        evaluate(py, &batch, &[&[3, self.data.nv()]], |x, out| {
            write_matrix(
                out[0],
                &dynamics.center_of_mass_jacobian(&state(&dynamics, x[0])?),
            );
            Ok(())
        })?
        .into_python(py)
    }

    /// The centroidal momentum matrix `A_g` (6 × nv) (floating base).
    fn centroidal_momentum_matrix(&self, py: Python<'_>, q: &Bound<'_, PyAny>) -> PyResult<Py<PyAny>> {
        let dynamics = self.needs_floating_base("centroidal_momentum_matrix")?;
        let batch = batch(&[arg("q", q, self.data.nq())])?;
        evaluate(py, &batch, &[&[6, self.data.nv()]], |x, out| {
            write_matrix(
                out[0],
                &dynamics.centroidal_momentum_matrix(&state(&dynamics, x[0])?).2,
            );
            Ok(())
        })?
        .into_python(py)
    }

    /// `Ȧ_g(q, ν) ν` (6,), the centroidal momentum's rate at zero acceleration (floating base).
    fn centroidal_bias(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let dynamics = self.needs_floating_base("centroidal_bias")?;
        let batch = batch(&[arg("q", q, self.data.nq()), arg("qd", qd, self.data.nv())])?;
        evaluate(py, &batch, &[&[6]], |x, out| {
            let bias = dynamics.centroidal_bias(&state(&dynamics, x[0])?, x[1]);
            out[0].copy_from_slice(bias.as_slice());
            Ok(())
        })?
        .into_python(py)
    }

    /// `q ⊕ qd·dt` (nq,): the base moved along its twist for `dt` (the SE(3) exponential), the
    /// joints by `q̇ dt` (floating base).
    fn integrate(
        &self,
        py: Python<'_>,
        q: &Bound<'_, PyAny>,
        qd: &Bound<'_, PyAny>,
        dt: f64,
    ) -> PyResult<Py<PyAny>> {
        let dynamics = self.needs_floating_base("integrate")?;
        if !dt.is_finite() {
            return Err(PyValueError::new_err(format!("dt must be finite, found {dt}")));
        }
        let batch = batch(&[arg("q", q, self.data.nq()), arg("qd", qd, self.data.nv())])?;
        evaluate(py, &batch, &[&[self.data.nq()]], |x, out| {
            out[0].copy_from_slice(&dynamics.integrate(x[0], x[1], dt).map_err(|e| e.to_string())?);
            Ok(())
        })?
        .into_python(py)
    }

    /// The velocity (nv,) that moves `q0` to `q1` in unit time (floating base).
    fn difference(
        &self,
        py: Python<'_>,
        q0: &Bound<'_, PyAny>,
        q1: &Bound<'_, PyAny>,
    ) -> PyResult<Py<PyAny>> {
        let dynamics = self.needs_floating_base("difference")?;
        let nq = self.data.nq();
        let batch = batch(&[arg("q0", q0, nq), arg("q1", q1, nq)])?;
        evaluate(py, &batch, &[&[self.data.nv()]], |x, out| {
            out[0].copy_from_slice(&dynamics.difference(x[0], x[1]).map_err(|e| e.to_string())?);
            Ok(())
        })?
        .into_python(py)
    }
}

impl Robot {
    /// The four regressors: Slotine–Li (`q, qd, v, a`) or torque form (`q, qd, qdd`), all
    /// columns or the base ones.
    fn regressors(
        &self,
        py: Python<'_>,
        arguments: &[(&str, &Bound<'_, PyAny>)],
        base: bool,
    ) -> PyResult<Py<PyAny>> {
        let data = &self.data;
        let nv = data.nv();
        let arguments: Vec<Argument<'_, '_>> = arguments
            .iter()
            .enumerate()
            .map(|(k, &(name, value))| arg(name, value, if k == 0 { data.nq() } else { nv }))
            .collect();
        let batch = batch(&arguments)?;
        let set = base.then(|| data.base());
        let columns = match set {
            Some(set) => set.count(),
            None => data.parameter_names().len(),
        };
        let dynamics = data.dynamics();
        evaluate(py, &batch, &[&[nv, columns]], |x, out| {
            // The torque form is the Slotine–Li regressor at v = q̇, a = q̈.
            let (v, a) = match x.len() {
                3 => (x[1], x[2]),
                _ => (x[2], x[3]),
            };
            let y = match &dynamics {
                Dynamics::Fixed(d) => d.regressor(x[0], x[1], v, a),
                Dynamics::Floating(d) => d.regressor(&state(d, x[0])?, x[1], v, a),
            };
            match set {
                Some(set) => write_matrix(out[0], &set.base_regressor(&y)),
                None => write_matrix(out[0], &y),
            }
            Ok(())
        })?
        .into_python(py)
    }
}
