//! The generic Rust dynamics (`NumericDynamics`, `FloatingDynamics`) of each function of the
//! C libraries' tables, by the function's name: what the programs' results must equal.

use super::build::Library;
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::dynamics::{FloatingDynamics, NumericDynamics};
use dyngen_codegen::model::Contact;
use dyngen_runtime::nalgebra::{DMatrix, Matrix3, Vector3, Vector6};
use dyngen_runtime::{ContactKind, ReferenceFrame};

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
            "contact_jacobian" | "contact_drift" | "contact_response" | "contact_delassus"
            | "contact_matrices" | "contact_system" => {
                let frame = |k: usize, reference| {
                    let m =
                        (generic.frame_motion(&model.frames()[k].name, q, qd)).expect("a frame of the model");
                    let at_rest = vec![0.0; model.nv()];
                    FrameAt {
                        rotation: m.pose().0,
                        jacobian: m.jacobian(reference),
                        velocity: m.velocity(reference),
                        classical: m.classical_acceleration(reference, &at_rest),
                    }
                };
                let (j, drift) = contact_rows(model.contacts(), frame);
                let free = column(generic.forward_dynamics(q, qd, tau).as_slice());
                contact_output(name, j, drift, &generic.mass_matrix_inverse(q), free)
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
            "contact_jacobian" | "contact_drift" | "contact_response" | "contact_delassus"
            | "contact_matrices" | "contact_system" => {
                let at_rest = vec![0.0; model.nv()];
                let frame = |k: usize, reference| FrameAt {
                    rotation: generic.frame_pose(&st, k).0,
                    jacobian: generic.frame_jacobian(&st, k, reference),
                    velocity: generic.frame_velocity(&st, qd, k, reference),
                    classical: generic.frame_classical_acceleration(&st, qd, &at_rest, k, reference),
                };
                let (j, drift) = contact_rows(model.contacts(), frame);
                let free = column(generic.forward_dynamics(&st, qd, tau).as_slice());
                contact_output(name, j, drift, &generic.mass_matrix_inverse(&st), free)
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

/// A frame at a state, in a reference frame: its axes, `J`, its velocity and its classical
/// acceleration at zero acceleration.
struct FrameAt {
    rotation: Matrix3<f64>,
    jacobian: DMatrix<f64>,
    velocity: Vector6<f64>,
    classical: Vector6<f64>,
}

/// The contacts' rows `J` and their drift from the frames' own quantities, `frame(k, axes)`
/// (docs/contacts.md): a point's rows are the linear ones, its drift its classical
/// acceleration; a frame's all six, its drift the spatial acceleration (the classical one less
/// `ω × v`); a point loop's the motion of its origin less that of the other frame's, in world
/// axes, turned into the frame's own for `Local`.
fn contact_rows(
    contacts: &[Contact],
    frame: impl Fn(usize, ReferenceFrame) -> FrameAt,
) -> (DMatrix<f64>, Vec<f64>) {
    let (mut rows, mut drift) = (Vec::new(), Vec::new());
    for c in contacts {
        let (j, d) = match (c.to, c.kind) {
            (None, kind) => {
                let f = frame(c.frame, c.reference);
                let mut d =
                    DMatrix::from_column_slice(kind.rows(), 1, &f.classical.as_slice()[..kind.rows()]);
                if kind == ContactKind::Frame {
                    let (v, w) = (f.velocity.fixed_rows::<3>(0), f.velocity.fixed_rows::<3>(3));
                    d.rows_mut(0, 3)
                        .copy_from(&(f.classical.fixed_rows::<3>(0) - w.cross(&v)));
                }
                (f.jacobian.rows(0, kind.rows()).into_owned(), d)
            }
            (Some(to), ContactKind::Point) => {
                let lwa = ReferenceFrame::LocalWorldAligned;
                let (one, two) = (frame(c.frame, lwa), frame(to, lwa));
                let turn = match c.reference {
                    ReferenceFrame::Local => one.rotation.transpose(),
                    _ => Matrix3::identity(),
                };
                let d = turn * (one.classical.fixed_rows::<3>(0) - two.classical.fixed_rows::<3>(0));
                let turn = DMatrix::from_column_slice(3, 3, turn.as_slice());
                let j = turn * (one.jacobian.rows(0, 3) - two.jacobian.rows(0, 3));
                (j, DMatrix::from_column_slice(3, 1, d.as_slice()))
            }
            (Some(_), ContactKind::Frame) => panic!("a frame loop: none among the test's robots"),
        };
        rows.push(j);
        drift.extend(d.iter());
    }
    let nv = rows.first().map_or(0, |j| j.ncols());
    let mut j = DMatrix::zeros(drift.len(), nv);
    let mut at = 0;
    for r in rows {
        j.rows_mut(at, r.nrows()).copy_from(&r);
        at += r.nrows();
    }
    (j, drift)
}

/// `contact_jacobian` (`J`), `contact_drift`, `contact_response` (`D⁻¹ Jᵀ`),
/// `contact_delassus` (`J D⁻¹ Jᵀ`), or the parts of `contact_matrices` (`J`, `D⁻¹ Jᵀ`, `K`) and
/// of `contact_system` (those, the drift and `free`, the free acceleration).
fn contact_output(
    name: &str,
    j: DMatrix<f64>,
    drift: Vec<f64>,
    mass_inverse: &DMatrix<f64>,
    free: DMatrix<f64>,
) -> Vec<DMatrix<f64>> {
    let response = mass_inverse * j.transpose();
    let delassus = &j * &response;
    match name {
        "contact_jacobian" => vec![j],
        "contact_drift" => vec![column(&drift)],
        "contact_response" => vec![response],
        "contact_delassus" => vec![delassus],
        "contact_matrices" => vec![j, response, delassus],
        _ => vec![j, response, delassus, column(&drift), free],
    }
}
