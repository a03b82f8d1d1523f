//! The generic Rust dynamics (`NumericDynamics`, `FloatingDynamics`) of each function of the
//! C libraries' tables, by the function's name: what the programs' results must equal.

use super::build::Library;
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::dynamics::{FloatingDynamics, NumericDynamics};
use dyngen_runtime::nalgebra::{DMatrix, Matrix3, Vector3};
use dyngen_runtime::ReferenceFrame;

/// The wrench the C++ program's controller tick applies at frame 0: `[force; moment]`.
pub(super) const TICK_WRENCH: [f64; 6] = [20.0, -10.0, 5.0, 1.0, 0.5, -0.2];

/// A function's name split into its quantity and reference frame (`frame_jacobian_local`).
fn quantity(function: &str) -> (&str, Option<ReferenceFrame>) {
    for reference in [
        ReferenceFrame::LocalWorldAligned,
        ReferenceFrame::World,
        ReferenceFrame::Local,
    ] {
        if let Some(q) = function.strip_suffix(&format!("_{}", reference.keyword())) {
            if q.starts_with("frame_") {
                return (q, Some(reference));
            }
        }
    }
    (function, None)
}

fn column(values: &[f64]) -> DMatrix<f64> {
    DMatrix::from_column_slice(values.len(), 1, values)
}

fn pose((rotation, translation): (Matrix3<f64>, Vector3<f64>)) -> Vec<DMatrix<f64>> {
    vec![
        DMatrix::from_column_slice(3, 3, rotation.as_slice()),
        column(translation.as_slice()),
    ]
}

/// The generic dynamics of one library's robot.
pub(super) struct Reference<'a> {
    library: &'a Library,
    base: BaseParameterSet,
}

impl<'a> Reference<'a> {
    pub fn new(library: &'a Library) -> Self {
        Reference {
            library,
            base: BaseParameterSet::compute(&library.model),
        }
    }

    /// θ_b of θ.
    pub fn base_parameters(&self, theta: &[f64]) -> Vec<f64> {
        self.base.base_parameters(theta)
    }

    /// The outputs of `function` at frame `frame` and state `s`, in the table's order.
    pub fn outputs(&self, function: &str, frame: usize, s: usize) -> Vec<DMatrix<f64>> {
        match self.library.model.floating_base() {
            Some(_) => self.floating(function, frame, s),
            None => self.fixed(function, frame, s),
        }
    }

    fn fixed(&self, function: &str, frame: usize, s: usize) -> Vec<DMatrix<f64>> {
        let (model, input) = (&self.library.model, |name| self.library.input(name, s));
        let generic = NumericDynamics::new(model);
        let [q, qd, v, a, qdd, tau, theta, theta_b, r] = [
            "q",
            "qd",
            "v",
            "a",
            "qdd",
            "tau",
            "parameters",
            "base_parameters",
            "r",
        ]
        .map(input);
        let frame_name = &model.frames()[frame].name;
        let motion = || {
            generic
                .frame_motion(frame_name, q, qd)
                .expect("a frame of the model")
        };
        let (name, reference) = quantity(function);
        let lwa = ReferenceFrame::LocalWorldAligned;
        let in_reference = || reference.expect("a reference frame");
        match name {
            "forward_kinematics" => pose(generic.end_effector_pose(q)),
            "jacobian" => vec![generic.jacobian(q)],
            "jacobian_dot" => vec![generic.jacobian_dot(q, qd)],
            "kinematics" => {
                let mut outputs = pose(generic.end_effector_pose(q));
                outputs.extend([generic.jacobian(q), generic.jacobian_dot(q, qd)]);
                outputs
            }
            "mass_matrix" => vec![generic.mass_matrix(q)],
            "coriolis_matrix" => vec![generic.coriolis_matrix(q, qd)],
            "gravity" => vec![column(generic.gravity_torque(q).as_slice())],
            "inverse_dynamics" => vec![column(generic.inverse_dynamics(q, qd, qdd).as_slice())],
            "slotine_li" => vec![column(generic.slotine_li(q, qd, v, a, true).as_slice())],
            "regressor" => vec![generic.regressor(q, qd, v, a)],
            "torque_regressor" => vec![generic.regressor(q, qd, qd, qdd)],
            "base_regressor" => vec![self.base.base_regressor(&generic.regressor(q, qd, v, a))],
            "base_torque_regressor" => vec![self.base.base_regressor(&generic.regressor(q, qd, qd, qdd))],
            "regressor_products" => products(&generic.regressor(q, qd, v, a), theta, r),
            "base_regressor_products" => products(
                &self.base.base_regressor(&generic.regressor(q, qd, v, a)),
                theta_b,
                r,
            ),
            "forward_dynamics" => vec![column(generic.forward_dynamics(q, qd, tau).as_slice())],
            "mass_matrix_inverse" => vec![generic.mass_matrix_inverse(q)],
            "inverse_dynamics_derivatives" => pair(generic.inverse_dynamics_derivatives(q, qd, qdd)),
            "forward_dynamics_derivatives" => pair(generic.forward_dynamics_derivatives(q, qd, tau)),
            "frame_pose" => pose(motion().pose()),
            "frame_jacobian" => vec![motion().jacobian(in_reference())],
            "frame_jacobian_time_variation" => vec![motion().jacobian_time_variation(in_reference())],
            "frame_velocity" => vec![column(motion().velocity(in_reference()).as_slice())],
            "frame_classical_acceleration" => {
                vec![column(
                    motion().classical_acceleration(in_reference(), qdd).as_slice(),
                )]
            }
            "frame_kinematics" => {
                let m = motion();
                let mut outputs = pose(m.pose());
                outputs.extend([m.jacobian(lwa), m.jacobian_time_variation(lwa)]);
                outputs
            }
            "tick" => {
                let tau = generic.inverse_dynamics(q, qd, qdd);
                let j = motion().jacobian(lwa);
                vec![column((tau - j.transpose() * column(&TICK_WRENCH)).as_slice())]
            }
            other => panic!("{}: no reference for the function {other}", self.library.prefix),
        }
    }

    fn floating(&self, function: &str, frame: usize, s: usize) -> Vec<DMatrix<f64>> {
        let (model, input) = (&self.library.model, |name| self.library.input(name, s));
        let generic = FloatingDynamics::new(model).expect("a floating base");
        let [q, qd, v, a, qdd, tau] = ["q", "qd", "v", "a", "qdd", "tau"].map(input);
        let st = generic.state(q).expect("a unit quaternion");
        let (name, reference) = quantity(function);
        let lwa = ReferenceFrame::LocalWorldAligned;
        let in_reference = || reference.expect("a reference frame");
        let regressor = |v: &[f64], a: &[f64]| generic.regressor(&st, qd, v, a);
        match name {
            "mass_matrix" => vec![generic.mass_matrix(&st)],
            "coriolis_matrix" => vec![generic.coriolis_matrix(&st, qd)],
            "gravity" => vec![column(generic.gravity(&st).as_slice())],
            "inverse_dynamics" => vec![column(generic.inverse_dynamics(&st, qd, qdd).as_slice())],
            "slotine_li" => vec![column(generic.slotine_li(&st, qd, v, a).as_slice())],
            "regressor" => vec![regressor(v, a)],
            "torque_regressor" => vec![regressor(qd, qdd)],
            "base_regressor" => vec![self.base.base_regressor(&regressor(v, a))],
            "base_torque_regressor" => vec![self.base.base_regressor(&regressor(qd, qdd))],
            "forward_dynamics" => vec![column(generic.forward_dynamics(&st, qd, tau).as_slice())],
            "mass_matrix_inverse" => vec![generic.mass_matrix_inverse(&st)],
            "center_of_mass" => vec![column(generic.center_of_mass(&st).as_slice())],
            "centroidal_momentum_matrix" => vec![generic.centroidal_momentum_matrix(&st).2],
            "centroidal_bias" => vec![column(generic.centroidal_bias(&st, qd).as_slice())],
            "inverse_dynamics_derivatives" => pair(generic.inverse_dynamics_derivatives(&st, qd, qdd)),
            "forward_dynamics_derivatives" => pair(generic.forward_dynamics_derivatives(&st, qd, tau)),
            "frame_pose" => pose(generic.frame_pose(&st, frame)),
            "frame_jacobian" => vec![generic.frame_jacobian(&st, frame, in_reference())],
            "frame_jacobian_time_variation" => {
                vec![generic.frame_jacobian_time_variation(&st, qd, frame, in_reference())]
            }
            "frame_velocity" => vec![column(
                generic.frame_velocity(&st, qd, frame, in_reference()).as_slice(),
            )],
            "frame_classical_acceleration" => vec![column(
                generic
                    .frame_classical_acceleration(&st, qd, qdd, frame, in_reference())
                    .as_slice(),
            )],
            "frame_kinematics" => {
                let mut outputs = pose(generic.frame_pose(&st, frame));
                outputs.extend([
                    generic.frame_jacobian(&st, frame, lwa),
                    generic.frame_jacobian_time_variation(&st, qd, frame, lwa),
                ]);
                outputs
            }
            "tick" => {
                let tau = generic.inverse_dynamics(&st, qd, qdd);
                let j = generic.frame_jacobian(&st, frame, lwa);
                vec![column((tau - j.transpose() * column(&TICK_WRENCH)).as_slice())]
            }
            other => panic!("{}: no reference for the function {other}", self.library.prefix),
        }
    }
}

fn pair((first, second): (DMatrix<f64>, DMatrix<f64>)) -> Vec<DMatrix<f64>> {
    vec![first, second]
}

/// `(Y θ, Yᵀ r)`.
fn products(y: &DMatrix<f64>, theta: &[f64], r: &[f64]) -> Vec<DMatrix<f64>> {
    vec![y * column(theta), y.transpose() * column(r)]
}
