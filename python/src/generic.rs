//! The dynamics of a `dyngen.Robot` on dyngen's generic `f64` algorithms
//! (`NumericDynamics`, `FloatingDynamics` on a floating base), one state or a batch.
//!
//! Names and argument orders are those of `docs/dynamics.md`; on a floating base `qd`, `v`,
//! `a`, `qdd` and `tau` are of length `nv` (base twist first) and `q` of length `nq`. Every
//! method is one call of [`Robot::each_state`]: the arrays it takes, the shapes of one state's
//! results, and what to compute on one state.

use crate::arrays::{batch, evaluate, write_matrix, Argument};
use crate::reference::reference_frame;
use crate::robot::{Robot, RobotData};
use dyngen_model::dynamics::{FloatingDynamics, FloatingState, FrameValues, NumericDynamics};
use nalgebra::{Dim, Matrix, RawStorage};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An array argument as Python passes it (any array-like).
type Array<'py> = Bound<'py, PyAny>;
/// What a dynamics method returns: one array, or a tuple of arrays.
type Arrays = PyResult<Py<PyAny>>;

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

/// What one state's evaluation gives, written into that state's output buffers in numpy's C
/// order: a vector or matrix fills one buffer, a pair two.
trait Output {
    fn write(&self, out: &mut [&mut [f64]]);
}

impl<R: Dim, C: Dim, S: RawStorage<f64, R, C>> Output for Matrix<f64, R, C, S> {
    fn write(&self, out: &mut [&mut [f64]]) {
        write_matrix(out[0], self);
    }
}

impl Output for Vec<f64> {
    fn write(&self, out: &mut [&mut [f64]]) {
        out[0].copy_from_slice(self);
    }
}

impl<A: Output, B: Output> Output for (A, B) {
    fn write(&self, out: &mut [&mut [f64]]) {
        self.0.write(&mut out[..1]);
        self.1.write(&mut out[1..]);
    }
}

/// `$call` on whichever facade `$dynamics` holds, with `$q` bound to the configuration `$x` as
/// that facade takes it: the slice on a fixed base, the checked state on a floating one (a
/// non-unit quaternion returns the error from the enclosing closure).
macro_rules! on_either_base {
    ($dynamics:expr, $x:expr, |$d:ident, $q:ident| $call:expr) => {
        match $dynamics {
            Dynamics::Fixed($d) => {
                let $q = $x;
                $call
            }
            Dynamics::Floating($d) => {
                let $q = &state($d, $x)?;
                $call
            }
        }
    };
}

/// Methods that are the facade's function of the same name on both bases, with the same
/// arguments: `fn name(q, qd, …) -> |nv| [shape], …;` takes `q` (length nq) and arrays of
/// length nv, and returns one array per shape (one state's, in terms of nv).
macro_rules! same_on_either_base {
    ($(
        $(#[$attribute:meta])*
        fn $name:ident(q $(, $argument:ident)*) -> |$nv:ident| $($shape:expr),+;
    )*) => {
        #[pymethods]
        impl Robot {
            $(
                $(#[$attribute])*
                fn $name(&self, py: Python<'_>, q: &Array $(, $argument: &Array)*) -> Arrays {
                    let $nv = self.data.nv();
                    let arrays = [("q", q) $(, (stringify!($argument), $argument))*];
                    self.each_state(py, &arrays, &[$(&$shape),+], |d, x| {
                        let [configuration, $($argument),*] = x else {
                            return Err(format!("internal error: {} arrays", x.len()));
                        };
                        Ok(on_either_base!(d, configuration, |d, q| d.$name(q $(, $argument)*)))
                    })
                }
            )*
        }
    };
}

same_on_either_base! {
    /// The mass matrix `D(q)` (nv × nv).
    fn mass_matrix(q) -> |nv| [nv, nv];

    /// The Christoffel-consistent Coriolis matrix `C(q, q̇)` (nv × nv), `Ḋ = C + Cᵀ`.
    fn coriolis_matrix(q, qd) -> |nv| [nv, nv];

    /// Inverse dynamics `τ = D q̈ + C q̇ + g` (nv,), joint-level terms included.
    fn inverse_dynamics(q, qd, qdd) -> |nv| [nv];

    /// Forward dynamics `q̈ = D⁻¹ (τ − C q̇ − g)` (nv,).
    fn forward_dynamics(q, qd, tau) -> |nv| [nv];

    /// `D(q)⁻¹` (nv × nv).
    fn mass_matrix_inverse(q) -> |nv| [nv, nv];

    /// `(∂τ/∂q, ∂τ/∂q̇)` of inverse dynamics (nv × nv each; `∂τ/∂q̈ = D`). On a floating base
    /// `q` moves in the tangent space (nv columns).
    fn inverse_dynamics_derivatives(q, qd, qdd) -> |nv| [nv, nv], [nv, nv];

    /// `(∂q̈/∂q, ∂q̈/∂q̇)` of forward dynamics (nv × nv each; `∂q̈/∂τ = D⁻¹`).
    fn forward_dynamics_derivatives(q, qd, tau) -> |nv| [nv, nv], [nv, nv];
}

impl Robot {
    /// Evaluates `each` on every state of `arrays` (the configuration first, of length nq,
    /// then arrays of length nv), with one result buffer per shape of `shapes` (one state's
    /// result): the arrays checked, the states evaluated without the GIL, the results as
    /// arrays with a batch's size first.
    fn each_state<T: Output>(
        &self,
        py: Python<'_>,
        arrays: &[(&str, &Array<'_>)],
        shapes: &[&[usize]],
        each: impl Fn(&Dynamics<'_>, &[&[f64]]) -> Result<T, String> + Send + Sync,
    ) -> Arrays {
        let data = &self.data;
        let arguments: Vec<Argument<'_, '_>> = arrays
            .iter()
            .enumerate()
            .map(|(k, &(name, value))| Argument {
                name,
                value,
                length: if k == 0 { data.nq() } else { data.nv() },
            })
            .collect();
        let batch = batch(&arguments)?;
        let dynamics = data.dynamics();
        evaluate(py, &batch, shapes, |x, out| {
            each(&dynamics, x)?.write(out);
            Ok(())
        })?
        .into_python(py)
    }

    /// [`Robot::each_state`] at frame `index`: `fixed` gets the frame's motion at `q` and `q̇`
    /// (zero when only `q` is given), `floating` the floating-base dynamics and the checked
    /// configuration; both get every state's arrays too.
    fn each_frame_state<T: Output>(
        &self,
        py: Python<'_>,
        index: usize,
        arrays: &[(&str, &Array<'_>)],
        shapes: &[&[usize]],
        fixed: impl Fn(FrameValues, &[&[f64]]) -> T + Send + Sync,
        floating: impl Fn(&FloatingDynamics<'_>, &FloatingState, &[&[f64]]) -> T + Send + Sync,
    ) -> Arrays {
        let frame = &self.data.model.frames()[index].name;
        let zero = vec![0.0; self.data.nv()];
        self.each_state(py, arrays, shapes, |d, x| match d {
            Dynamics::Fixed(d) => {
                let qd = x.get(1).copied().unwrap_or(&zero);
                let motion = d
                    .frame_motion(frame, x[0], qd)
                    .ok_or_else(|| format!("no frame '{frame}'"))?;
                Ok(fixed(motion, x))
            }
            Dynamics::Floating(d) => Ok(floating(d, &state(d, x[0])?, x)),
        })
    }

    /// [`Robot::each_state`] for a method of the floating-base dynamics only (`method` names
    /// it in the error on a fixed base) with one result of `shape`: `each` gets the dynamics
    /// and the checked configuration.
    fn each_floating_state<T: Output>(
        &self,
        py: Python<'_>,
        method: &str,
        arrays: &[(&str, &Array<'_>)],
        shape: &[usize],
        each: impl Fn(&FloatingDynamics<'_>, &FloatingState, &[&[f64]]) -> T + Send + Sync,
    ) -> Arrays {
        let floating = self.needs_floating_base(method)?;
        self.each_state(py, arrays, &[shape], |_, x| {
            Ok(each(&floating, &state(&floating, x[0])?, x))
        })
    }

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

    /// The four regressors: Slotine–Li (`q, qd, v, a`) or torque form (`q, qd, qdd`), all
    /// columns or the base ones.
    fn regressors(&self, py: Python<'_>, arrays: &[(&str, &Array<'_>)], base: bool) -> Arrays {
        let set = base.then(|| self.data.base());
        let columns = match set {
            Some(set) => set.count(),
            None => self.data.parameter_names().len(),
        };
        self.each_state(py, arrays, &[&[self.data.nv(), columns]], |d, x| {
            // The torque form is the Slotine–Li regressor at v = q̇, a = q̈.
            let (v, a) = match x.len() {
                3 => (x[1], x[2]),
                _ => (x[2], x[3]),
            };
            let y = on_either_base!(d, x[0], |d, q| d.regressor(q, x[1], v, a));
            Ok(match set {
                Some(set) => set.base_regressor(&y),
                None => y,
            })
        })
    }
}

#[pymethods]
impl Robot {
    /// End-effector pose in the base frame (the world on a floating base): `(rotation (3, 3),
    /// translation (3,))`.
    fn end_effector_pose(&self, py: Python<'_>, q: &Array) -> Arrays {
        self.frame_pose(py, &self.data.model.end_effector().name.clone(), q)
    }

    /// `J(q)` of the end-effector (6 × nv, rows `[linear; angular]`, base axes at the frame's
    /// origin: Pinocchio's LOCAL_WORLD_ALIGNED).
    fn jacobian(&self, py: Python<'_>, q: &Array) -> Arrays {
        let frame = self.data.model.end_effector().name.clone();
        self.frame_jacobian(py, &frame, q, "local_world_aligned")
    }

    /// `J̇(q, q̇)` of the end-effector, the time derivative of `jacobian`.
    fn jacobian_dot(&self, py: Python<'_>, q: &Array, qd: &Array) -> Arrays {
        let frame = self.data.model.end_effector().name.clone();
        self.frame_jacobian_time_variation(py, &frame, q, qd, "local_world_aligned")
    }

    /// The pose of frame `frame`: `(rotation (3, 3), translation (3,))`.
    fn frame_pose(&self, py: Python<'_>, frame: &str, q: &Array) -> Arrays {
        let index = self.data.frame_index(frame)?;
        self.each_frame_state(
            py,
            index,
            &[("q", q)],
            &[&[3, 3], &[3]],
            |motion, _| motion.pose(),
            |d, s, _| d.frame_pose(s, index),
        )
    }

    /// `J` of frame `frame` (6 × nv) in `reference`: "local", "world" or
    /// "local_world_aligned" (Pinocchio's reference frames).
    #[pyo3(signature = (frame, q, reference="local_world_aligned"))]
    fn frame_jacobian(&self, py: Python<'_>, frame: &str, q: &Array, reference: &str) -> Arrays {
        let (index, reference) = (self.data.frame_index(frame)?, reference_frame(reference)?);
        self.each_frame_state(
            py,
            index,
            &[("q", q)],
            &[&[6, self.data.nv()]],
            |motion, _| motion.jacobian(reference),
            |d, s, _| d.frame_jacobian(s, index, reference),
        )
    }

    /// `J̇` of frame `frame` in `reference`, the time derivative of `frame_jacobian`.
    #[pyo3(signature = (frame, q, qd, reference="local_world_aligned"))]
    fn frame_jacobian_time_variation(
        &self,
        py: Python<'_>,
        frame: &str,
        q: &Array,
        qd: &Array,
        reference: &str,
    ) -> Arrays {
        let (index, reference) = (self.data.frame_index(frame)?, reference_frame(reference)?);
        self.each_frame_state(
            py,
            index,
            &[("q", q), ("qd", qd)],
            &[&[6, self.data.nv()]],
            |motion, _| motion.jacobian_time_variation(reference),
            |d, s, x| d.frame_jacobian_time_variation(s, x[1], index, reference),
        )
    }

    /// The velocity `J q̇` of frame `frame` in `reference`, `[linear; angular]` (6,).
    #[pyo3(signature = (frame, q, qd, reference="local_world_aligned"))]
    fn frame_velocity(&self, py: Python<'_>, frame: &str, q: &Array, qd: &Array, reference: &str) -> Arrays {
        let (index, reference) = (self.data.frame_index(frame)?, reference_frame(reference)?);
        self.each_frame_state(
            py,
            index,
            &[("q", q), ("qd", qd)],
            &[&[6]],
            |motion, _| motion.velocity(reference),
            |d, s, x| d.frame_velocity(s, x[1], index, reference),
        )
    }

    /// The classical acceleration of frame `frame` at `q̈` in `reference` (Pinocchio's
    /// `getFrameClassicalAcceleration`), `[linear; angular]` (6,).
    #[pyo3(signature = (frame, q, qd, qdd, reference="local_world_aligned"))]
    fn frame_classical_acceleration(
        &self,
        py: Python<'_>,
        frame: &str,
        q: &Array,
        qd: &Array,
        qdd: &Array,
        reference: &str,
    ) -> Arrays {
        let (index, reference) = (self.data.frame_index(frame)?, reference_frame(reference)?);
        self.each_frame_state(
            py,
            index,
            &[("q", q), ("qd", qd), ("qdd", qdd)],
            &[&[6]],
            |motion, x| motion.classical_acceleration(reference, x[2]),
            |d, s, x| d.frame_classical_acceleration(s, x[1], x[2], index, reference),
        )
    }

    /// Generalised gravity `g(q)` (nv,): the torques that hold the robot still.
    fn gravity(&self, py: Python<'_>, q: &Array) -> Arrays {
        self.each_state(py, &[("q", q)], &[&[self.data.nv()]], |d, x| {
            Ok(match d {
                Dynamics::Fixed(d) => d.gravity_torque(x[0]),
                Dynamics::Floating(d) => d.gravity(&state(d, x[0])?),
            })
        })
    }

    /// The Slotine–Li torque `D a + C(q, q̇) v + g` (nv,).
    fn slotine_li(&self, py: Python<'_>, q: &Array, qd: &Array, v: &Array, a: &Array) -> Arrays {
        let arrays = [("q", q), ("qd", qd), ("v", v), ("a", a)];
        self.each_state(py, &arrays, &[&[self.data.nv()]], |d, x| {
            Ok(match d {
                Dynamics::Fixed(d) => d.slotine_li(x[0], x[1], x[2], x[3], true),
                Dynamics::Floating(d) => d.slotine_li(&state(d, x[0])?, x[1], x[2], x[3]),
            })
        })
    }

    /// The Slotine–Li regressor `Y(q, q̇, v, a)` (nv × P), `Y θ = slotine_li(q, q̇, v, a)`.
    fn regressor(&self, py: Python<'_>, q: &Array, qd: &Array, v: &Array, a: &Array) -> Arrays {
        self.regressors(py, &[("q", q), ("qd", qd), ("v", v), ("a", a)], false)
    }

    /// The inverse-dynamics regressor `Y(q, q̇, q̇, q̈)` (nv × P), `Y θ = τ`.
    fn torque_regressor(&self, py: Python<'_>, q: &Array, qd: &Array, qdd: &Array) -> Arrays {
        self.regressors(py, &[("q", q), ("qd", qd), ("qdd", qdd)], false)
    }

    /// The base regressor `Y_b(q, q̇, v, a)` (nv × B), `Y_b θ_b = Y θ`.
    fn base_regressor(&self, py: Python<'_>, q: &Array, qd: &Array, v: &Array, a: &Array) -> Arrays {
        self.regressors(py, &[("q", q), ("qd", qd), ("v", v), ("a", a)], true)
    }

    /// The base torque regressor `Y_b(q, q̇, q̇, q̈)` (nv × B), `Y_b θ_b = τ`.
    fn base_torque_regressor(&self, py: Python<'_>, q: &Array, qd: &Array, qdd: &Array) -> Arrays {
        self.regressors(py, &[("q", q), ("qd", qd), ("qdd", qdd)], true)
    }

    /// The total energy's regressor `e_H(q, q̇)` (P,): `e_H θ = T + V` (fixed base).
    fn energy_regressor(&self, py: Python<'_>, q: &Array, qd: &Array) -> Arrays {
        let fixed = self.needs_fixed_base("energy_regressor")?;
        let p = self.data.parameter_names().len();
        self.each_state(py, &[("q", q), ("qd", qd)], &[&[p]], |_, x| {
            Ok(fixed.energy_regressor(x[0], x[1]))
        })
    }

    /// Centre of mass in the world (3,) (floating base).
    fn center_of_mass(&self, py: Python<'_>, q: &Array) -> Arrays {
        let method = "center_of_mass";
        self.each_floating_state(py, method, &[("q", q)], &[3], |d, s, _| d.center_of_mass(s))
    }

    /// The Jacobian of the centre of mass (3 × nv) (floating base).
    fn center_of_mass_jacobian(&self, py: Python<'_>, q: &Array) -> Arrays {
        let (method, shape) = ("center_of_mass_jacobian", [3, self.data.nv()]);
        self.each_floating_state(py, method, &[("q", q)], &shape, |d, s, _| {
            d.center_of_mass_jacobian(s)
        })
    }

    /// The centroidal momentum matrix `A_g` (6 × nv) (floating base).
    fn centroidal_momentum_matrix(&self, py: Python<'_>, q: &Array) -> Arrays {
        let (method, shape) = ("centroidal_momentum_matrix", [6, self.data.nv()]);
        self.each_floating_state(py, method, &[("q", q)], &shape, |d, s, _| {
            d.centroidal_momentum_matrix(s).2
        })
    }

    /// `Ȧ_g(q, ν) ν` (6,), the centroidal momentum's rate at zero acceleration (floating base).
    fn centroidal_bias(&self, py: Python<'_>, q: &Array, qd: &Array) -> Arrays {
        let arrays = [("q", q), ("qd", qd)];
        self.each_floating_state(py, "centroidal_bias", &arrays, &[6], |d, s, x| {
            d.centroidal_bias(s, x[1])
        })
    }

    /// `q ⊕ qd·dt` (nq,): the base moved along its twist for `dt` (the SE(3) exponential), the
    /// joints by `q̇ dt` (floating base).
    fn integrate(&self, py: Python<'_>, q: &Array, qd: &Array, dt: f64) -> Arrays {
        let floating = self.needs_floating_base("integrate")?;
        if !dt.is_finite() {
            return Err(PyValueError::new_err(format!("dt must be finite, found {dt}")));
        }
        self.each_state(py, &[("q", q), ("qd", qd)], &[&[self.data.nq()]], |_, x| {
            floating.integrate(x[0], x[1], dt).map_err(|e| e.to_string())
        })
    }

    /// The velocity (nv,) that moves `q0` to `q1` in unit time (floating base).
    fn difference(&self, py: Python<'_>, q0: &Array, q1: &Array) -> Arrays {
        let floating = self.needs_floating_base("difference")?;
        let nq = self.data.nq();
        let configuration = |name, value| Argument {
            name,
            value,
            length: nq,
        };
        let batch = batch(&[configuration("q0", q0), configuration("q1", q1)])?;
        evaluate(py, &batch, &[&[self.data.nv()]], |x, out| {
            out[0].copy_from_slice(&floating.difference(x[0], x[1]).map_err(|e| e.to_string())?);
            Ok(())
        })?
        .into_python(py)
    }
}
