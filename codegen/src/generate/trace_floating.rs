//! The tracer of a floating-base robot: the floating algorithms run on symbolic inputs, the
//! base pose entering as its rotation matrix and position (`FloatingTrig` computes them once
//! per tick from the quaternion), velocities of `nv = dof + 6` entries. Driven by the quantity
//! table and the chosen groups as the fixed-base tracer is, in an order of its own (which is
//! the order of the floating-base module's methods); `trace::trace_functions` chooses it.

use super::code_size::Shapes;
use super::quantities::{Dims, QuantityKind};
use super::trace::{
    base_columns, frame_rows, frame_spellings, full_from_base, ids, inputs, matrix_ids, pair_ids,
    traced_references,
};
use super::trace::{Inputs, Quantity, Traced};
use super::trace_contacts::contact_outputs;
use crate::base_parameters::BaseParameterSet;
use crate::dynamics::constrained::OriginRates;
use crate::dynamics::floating::{self as algorithms, FloatingBase};
use crate::dynamics::joint_terms::{add_armature_after, with_joint_term_torques};
use crate::dynamics::newton_euler::OriginMotion;
use crate::dynamics::slotine_li::gravity_vector;
use crate::dynamics::{self, FloatingDynamics, FrameMotion};
use crate::model::{Frame, JointTermValues, Model};
use crate::scalar::Scalar;
use crate::spatial::{Mat3, RigidInertia, Transform, Vec3};
use crate::symbolic::{Expr, Id};
use crate::{FunctionGroup, Functions};
use dyngen_runtime::ReferenceFrame;

/// The rows of a floating-base robot traced before its frames, in trace order (which is their
/// order in the module).
const BEFORE_FRAMES: [QuantityKind; 14] = [
    QuantityKind::MassMatrix,
    QuantityKind::CoriolisMatrix,
    QuantityKind::Gravity,
    QuantityKind::InverseDynamics,
    QuantityKind::SlotineLi,
    QuantityKind::Regressor,
    QuantityKind::BaseRegressor,
    QuantityKind::TorqueRegressor,
    QuantityKind::BaseTorqueRegressor,
    QuantityKind::ForwardDynamics,
    QuantityKind::MassMatrixInverse,
    QuantityKind::CenterOfMass,
    QuantityKind::CentroidalMomentumMatrix,
    QuantityKind::CentroidalBias,
];

/// The rows traced after the frames: the derivatives, last so the functions before keep their
/// node ids.
const AFTER_FRAMES: [QuantityKind; 2] = [
    QuantityKind::InverseDynamicsDerivatives,
    QuantityKind::ForwardDynamicsDerivatives,
];

/// The quantities a floating-base robot has besides its per-frame ones, in the module's order.
pub(crate) fn floating_kinds() -> impl Iterator<Item = QuantityKind> {
    BEFORE_FRAMES.into_iter().chain(AFTER_FRAMES)
}

/// The tracer of a floating-base robot: the inputs and the values its rows share, and what it
/// has recorded. Each row's outputs come from [`FloatingTracer::outputs`]; its arguments and
/// shape from the table ([`QuantityKind::signature`]).
pub(super) struct FloatingTracer<'a> {
    model: &'a Model,
    base_parameters: &'a BaseParameterSet,
    /// The groups traced, and the reference frames of the frame rows.
    functions: Functions,
    references: &'static [ReferenceFrame],
    /// The rows written composed: recorded, not traced.
    composed: Vec<QuantityKind>,
    dims: Dims,
    /// The joints' positions, and the base pose as its rotation matrix (row-major) and
    /// position.
    q: Vec<Expr>,
    rotation: Vec<Expr>,
    position: Vec<Expr>,
    /// Velocity-space inputs (`nv` entries, the base's six first).
    qd: Vec<Expr>,
    v: Vec<Expr>,
    a: Vec<Expr>,
    tau: Vec<Expr>,
    /// The base (pose and inertia), the joint transforms, the bodies' poses and inertias, the
    /// joint-level terms.
    base: FloatingBase<Expr>,
    x: Vec<Transform<Expr>>,
    world: Vec<Transform<Expr>>,
    inertias: Vec<RigidInertia<Expr>>,
    joint_values: Vec<JointTermValues>,
    /// The Slotine–Li and the torque-form regressor, gravity, the centre of mass and the
    /// centroidal momentum matrix, traced before any row: the rows after them were written with
    /// these node ids.
    y: Vec<Id>,
    torque_y: Vec<Id>,
    gravity: Option<Vec3<Expr>>,
    center_of_mass: Vec<Id>,
    centroidal_matrix: Vec<Id>,
    quantities: Vec<Quantity>,
}

impl<'a> FloatingTracer<'a> {
    /// The inputs and the shared values, traced (the inertial parameters the representative
    /// ones of the base parameters, [`BaseParameterSet::representative`], as for a fixed base).
    pub(super) fn new(
        model: &'a Model,
        base_parameters: &'a BaseParameterSet,
        functions: Functions,
        shapes: &Shapes,
    ) -> Self {
        let (n, nv) = (model.dof(), model.nv());
        let description = FloatingDynamics::new(model)
            .expect("trace_floating needs a floating base")
            .parameters();
        let theta = base_parameters.representative(&description);
        let (q, rotation, position) = (inputs("q", n), inputs("rot", 9), inputs("pos", 3));
        let (qd, v, a, tau) = (
            inputs("qd", nv),
            inputs("v", nv),
            inputs("a", nv),
            inputs("tau", nv),
        );
        let pose = Transform {
            rot: Mat3(std::array::from_fn(|r| {
                std::array::from_fn(|c| rotation[3 * r + c])
            })),
            pos: Vec3([position[0], position[1], position[2]]),
        };
        // The base body's ten first, then the model's layout: the bodies', the joint-level ones.
        let joint_values = model.joint_term_values_from(&theta[10..]);
        let inertial = 10 + model.inertial_parameter_count();
        let theta: Vec<Expr> = theta[..inertial].iter().map(|&x| Expr::from_f64(x)).collect();
        let mut inertias: Vec<RigidInertia<Expr>> = dynamics::inertias_from_parameters(&theta);
        let base = FloatingBase {
            pose,
            inertia: inertias.remove(0),
        };
        let x = dynamics::joint_transforms(model, &q);
        let world = algorithms::floating_body_poses(model, &pose, &x);
        let regressor = |v: &[Expr]| {
            let full = algorithms::floating_regressor(model, &pose.rot, &x, &qd, v, &a);
            matrix_ids(&full_from_base(&full, base_parameters))
        };
        // Traced here, before the rows that come after them in a trace of every group, and only
        // when chosen, as the fixed-base tracer does.
        let (y, torque_y) = match functions.contains(FunctionGroup::Regressors) {
            true => (regressor(&v), regressor(&qd)),
            false => (Vec::new(), Vec::new()),
        };
        let gravity = Some(Vec3::from_f64(model.gravity().into()));
        let centroidal = algorithms::centroidal_momentum_matrix(model, &base, &x, &inertias);
        FloatingTracer {
            model,
            base_parameters,
            functions,
            references: traced_references(shapes.frame_references),
            composed: shapes.composed.clone(),
            dims: Dims {
                n: nv,
                p: FloatingDynamics::parameter_count(model),
                b: base_parameters.count(),
                c: model.contact_rows(),
            },
            q,
            rotation,
            position,
            qd,
            v,
            a,
            tau,
            base,
            x,
            world,
            inertias,
            joint_values,
            y,
            torque_y,
            gravity,
            center_of_mass: ids(&centroidal.com.0),
            centroidal_matrix: matrix_ids(&centroidal.matrix),
            quantities: Vec::new(),
        }
    }

    /// Traces the rows of `functions` in trace order (the rows of `BEFORE_FRAMES`, the
    /// per-frame rows frame by frame, the rows of `AFTER_FRAMES`), then the other formulation
    /// of `D⁻¹`.
    pub(super) fn run(mut self) -> Traced {
        let functions = self.functions;
        let chosen = |kind: &QuantityKind| functions.contains(kind.group());
        for kind in BEFORE_FRAMES.into_iter().filter(chosen) {
            self.record_row(kind);
        }
        if functions.contains(FunctionGroup::Frames) {
            let spelled = frame_spellings(self.model);
            for (index, frame) in self.model.frames().iter().enumerate() {
                self.trace_frame(index, frame, &spelled[index].snake);
            }
        }
        for kind in AFTER_FRAMES.into_iter().filter(chosen) {
            self.record_row(kind);
        }
        // D⁻¹ by sums over common ancestors, traced last so the functions above keep their node
        // ids; kept where it costs less. (The regressors by the bodies' Jacobians cost fewer
        // operations on the G1 but ran slower: longer-lived values. Four rows at a time, as for
        // a fixed base, they ran slower on Solo-12: every body's columns carry the six dense
        // base rows, while the scalar form gets each joint row from one entry of the force it
        // carries up anyway; `BENCHMARKS.md`.)
        let (model, base, x, inertias) = (self.model, &self.base, &self.x, &self.inertias);
        let jv = &self.joint_values;
        let other_forms = match self.composed.contains(&QuantityKind::MassMatrixInverse) {
            true => Vec::new(),
            false => {
                let inverse =
                    algorithms::floating_mass_matrix_inverse_by_ancestors(model, base, x, inertias, jv);
                vec![(
                    QuantityKind::MassMatrixInverse.name().to_owned(),
                    matrix_ids(&inverse),
                )]
            }
        };
        // The contacts' rows after everything else, so every row before keeps its node ids.
        if functions.contains(FunctionGroup::Contacts) && !model.contacts().is_empty() {
            let mass = algorithms::factor(model, base, x, inertias, jv);
            let motion = |frame: usize| self.frame_motion(&model.frames()[frame]);
            let (qd, tau) = (&self.qd, &self.tau);
            // As `floating_forward_dynamics` computes it: `τ` less the bias.
            let free_force = || {
                let bias = algorithms::floating_bias(model, base, x, inertias, jv, qd);
                tau.iter().zip(&bias).map(|(&t, &b)| t - b).collect()
            };
            // Each frame's rates at `a = 0` from the bodies' motions of the bias pass above.
            let (root, bodies) = algorithms::floating_motions_at_rest(model, base, x, qd);
            let world = &self.world;
            let rates_at_rest = |k: usize, motion: &FrameMotion<Expr>| {
                let frame = &model.frames()[k];
                let (rotation, body) = match frame.parent {
                    Some(b) => (&world[b].rot, bodies[b]),
                    None => (&base.pose.rot, root),
                };
                rates_from_body(model, frame, rotation, &body, motion, qd)
            };
            let state = super::trace_contacts::ContactState {
                qd: &self.qd,
                a: &self.a,
                mass: &mass,
                free_force: &free_force,
                rates_at_rest: Some(&rates_at_rest),
                tree: super::trace_contact_derivatives::Tree::Floating {
                    base,
                    q: &self.q,
                    inertias,
                    joint_values: jv,
                },
            };
            for (kind, outputs) in contact_outputs(model, motion, state) {
                self.record(kind, outputs);
            }
        }
        Traced {
            inputs: self.inputs(),
            quantities: self.quantities,
            other_forms,
            row_lane_forms: Vec::new(),
        }
    }

    /// Traces row `kind` and records it, or records it composed.
    fn record_row(&mut self, kind: QuantityKind) {
        match self.composed.contains(&kind) {
            true => self.quantities.push(Quantity::composed(kind, self.dims)),
            false => {
                let outputs = self.outputs(kind);
                self.record(kind, outputs);
            }
        }
    }

    /// Records `outputs` as row `kind`, with the table's arguments and shape.
    fn record(&mut self, kind: QuantityKind, outputs: Vec<Id>) {
        self.quantities.push(Quantity::new(kind, self.dims, outputs));
    }

    /// How row `kind` (one not per frame) is traced: its outputs.
    fn outputs(&self, kind: QuantityKind) -> Vec<Id> {
        use QuantityKind as K;
        let (model, base, x, inertias) = (self.model, &self.base, &self.x, &self.inertias);
        let (qd, v, a, tau) = (&self.qd, &self.v, &self.a, &self.tau);
        let jv = &self.joint_values;
        let base_columns = |y: &[Id]| base_columns(y, self.base_parameters, self.dims.n);
        // The joint-level torques on the joint rows, `v` the reference velocity (none added
        // without chosen kinds: such a robot records the graph it always did).
        let with_joint_terms = |rigid: Vec<Expr>, v: &[Expr]| {
            with_joint_term_torques(model, jv, rigid, 6, (&qd[6..], &v[6..], &a[6..]))
        };
        match kind {
            K::MassMatrix => {
                let mut d = algorithms::floating_mass_matrix(model, &base.inertia, x, inertias);
                add_armature_after(model, jv, &mut d, 6);
                matrix_ids(&d)
            }
            K::CoriolisMatrix => matrix_ids(&algorithms::floating_coriolis_matrix(
                model, base, x, inertias, qd,
            )),
            K::Gravity => ids(&algorithms::floating_gravity(model, base, x, inertias)),
            K::InverseDynamics => ids(&with_joint_terms(
                algorithms::floating_inverse_dynamics(model, base, x, inertias, qd, a),
                qd,
            )),
            K::SlotineLi => ids(&with_joint_terms(
                algorithms::floating_slotine_li(model, base, x, inertias, qd, v, a, self.gravity),
                v,
            )),
            K::Regressor => self.y.clone(),
            K::BaseRegressor => base_columns(&self.y),
            K::TorqueRegressor => self.torque_y.clone(),
            K::BaseTorqueRegressor => base_columns(&self.torque_y),
            K::ForwardDynamics => ids(&algorithms::floating_forward_dynamics(
                model, base, x, inertias, jv, qd, tau,
            )),
            K::MassMatrixInverse => matrix_ids(&algorithms::floating_mass_matrix_inverse(
                model, base, x, inertias, jv,
            )),
            K::CenterOfMass => self.center_of_mass.clone(),
            K::CentroidalMomentumMatrix => self.centroidal_matrix.clone(),
            K::CentroidalBias => ids(&algorithms::centroidal_bias(model, base, x, inertias, qd)),
            K::InverseDynamicsDerivatives => pair_ids(algorithms::floating_inverse_dynamics_derivatives(
                model, base, &self.q, inertias, jv, qd, a,
            )),
            K::ForwardDynamicsDerivatives => pair_ids(algorithms::floating_forward_dynamics_derivatives(
                model, base, &self.q, inertias, jv, qd, tau,
            )),
            _ => unreachable!("{kind:?} is not a row of a floating base traced on its own"),
        }
    }

    /// The per-frame rows of one frame, of its motion with the base's.
    fn trace_frame(&mut self, index: usize, frame: &Frame, snake: &str) {
        let motion = self.frame_motion(frame);
        let rows = frame_rows(
            &motion,
            &self.qd,
            &self.a,
            index,
            snake,
            self.dims,
            self.references,
        );
        self.quantities.extend(rows);
    }

    /// A frame's pose, `J` and `J̇` with the base's motion.
    fn frame_motion(&self, frame: &Frame) -> FrameMotion<Expr> {
        let (model, pose, world) = (self.model, &self.base.pose, &self.world);
        FrameMotion {
            pose: dynamics::kinematics::frame_pose(Some(pose), world, frame),
            jacobian: algorithms::floating_frame_jacobian(model, pose, world, frame),
            jacobian_dot: algorithms::floating_frame_jacobian_dot(model, pose, world, &self.qd, frame),
        }
    }

    /// The inputs by role.
    fn inputs(&self) -> Inputs {
        Inputs {
            q: ids(&self.q),
            qd: ids(&self.qd),
            v: ids(&self.v),
            a: ids(&self.a),
            tau: ids(&self.tau),
            theta: Vec::new(),
            r: Vec::new(),
            base_rotation: ids(&self.rotation),
            base_position: ids(&self.position),
        }
    }
}

/// A frame's rates at `a = 0` in world axes (`OriginRates`) from its body's motion at rest
/// (`rotation` the body's orientation in the world, `body` its motion in its own axes, the field
/// folded in as an upward acceleration): the origin's classical acceleration `R (a + α × p + ω ×
/// (ω × p)) + g`, the body's `R α`, and the velocities from the frame's `J`.
fn rates_from_body(
    model: &Model,
    frame: &Frame,
    rotation: &Mat3<Expr>,
    body: &OriginMotion<Expr>,
    motion: &FrameMotion<Expr>,
    qd: &[Expr],
) -> OriginRates<Expr> {
    let t = frame.placement.translation;
    let p = Vec3::from_f64([t.x, t.y, t.z]);
    let (w, alpha) = (body.omega, body.alpha);
    let classical = body.accel + alpha.cross(&p) + w.cross(&w.cross(&p));
    let [v0, v1, v2, w0, w1, w2] = motion.velocity_in(ReferenceFrame::LocalWorldAligned, qd);
    OriginRates {
        p: motion.pose.pos,
        v: Vec3([v0, v1, v2]),
        w: Vec3([w0, w1, w2]),
        c: rotation.mul_vec(&classical) + gravity_vector(model),
        alpha: rotation.mul_vec(&alpha),
    }
}
