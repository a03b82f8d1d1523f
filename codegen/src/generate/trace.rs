//! Runs the generic dynamics algorithms on symbolic inputs: one graph holds every quantity a
//! controller needs, so shared subexpressions (joint transforms, body velocities) are one node.
//!
//! The tracer is driven by the quantity table: it creates the inputs and the values the rows
//! share, then goes through the rows of the chosen groups in the table's order, each row's
//! outputs from one `match` on its kind (`FixedTracer::outputs`), its arguments and shape from
//! the table ([`QuantityKind::signature`]); the per-frame rows, last in the table, frame by
//! frame ([`frame_rows`]); then other formulations of some rows, kept where they cost less.
//! Node ids follow creation order and the generated code follows node ids, so this order is
//! append-only: what is added is traced after everything else.

use super::code_size::Shapes;
use super::quantities::{Arg, Coefficient, Dims, QuantityKind, Shape};
use super::trace_contact_derivatives::Tree;
use super::trace_contacts::{contact_outputs, ContactInputs, ContactState};
use crate::base_parameters::BaseParameterSet;
use crate::description::FrameReferences;
use crate::dynamics::{self, Directions, Placements};
use crate::frame_names::{frame_identifiers, FrameIdentifiers};
use crate::model::{Frame, JointTermValues, Model};
use crate::scalar::Scalar;
use crate::scalar_dual::{LaneTangent, Tangent};
use crate::spatial::{CompositeFrame, JointFrame, RigidInertia, Transform, Vec3};
use crate::symbolic::{record, Expr, Graph, Id, LaneExpr};
use crate::{FunctionGroup, Functions};
use dyngen_runtime::ReferenceFrame;
use nalgebra::DMatrix;
use std::collections::HashMap;

/// Which frame, and in which reference frame, a frame quantity is of.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameOf {
    /// Index into `Model::frames`.
    pub index: usize,
    /// The frame's name as function names spell it.
    pub snake: String,
    /// `None` for what has no reference frame: the pose, and `(pose, J, J̇)` together.
    pub reference: Option<ReferenceFrame>,
}

/// One quantity: a named function of the joint state.
#[derive(Clone, Debug)]
pub struct Quantity {
    pub kind: QuantityKind,
    /// The frame of a quantity of the group `frames` (`None` for every other).
    pub frame: Option<FrameOf>,
    pub args: Vec<Arg>,
    pub shape: Shape,
    /// Output nodes in the order of the shape (column-major for matrices); none for a
    /// composed row.
    pub outputs: Vec<Id>,
    /// Whether it is computed from the robot's smaller functions (`code_shape: composed`)
    /// rather than traced.
    pub composed: bool,
}

impl Quantity {
    /// Row `kind` (not per frame) with `outputs`, its arguments and shape from the table.
    pub(super) fn new(kind: QuantityKind, dims: Dims, outputs: Vec<Id>) -> Quantity {
        let (args, shape) = kind.signature(dims);
        Quantity {
            kind,
            frame: None,
            args,
            shape,
            outputs,
            composed: false,
        }
    }

    /// Row `kind` written composed.
    pub(super) fn composed(kind: QuantityKind, dims: Dims) -> Quantity {
        Quantity {
            composed: true,
            ..Quantity::new(kind, dims, Vec::new())
        }
    }
}

impl FrameOf {
    /// Frame `index` of `Model::frames`, spelled `snake` in function names, in `reference`.
    pub fn new(index: usize, snake: &str, reference: Option<ReferenceFrame>) -> FrameOf {
        FrameOf {
            index,
            snake: snake.to_owned(),
            reference,
        }
    }

    /// The name of the function that computes `kind` for this frame and reference frame:
    /// the kind's, the frame's identifier, the reference frame (`frame_jacobian_tool0_local`).
    pub fn function_name(&self, kind: QuantityKind) -> String {
        match self.reference {
            Some(r) => format!("{}_{}_{}", kind.name(), self.snake, r.keyword()),
            None => format!("{}_{}", kind.name(), self.snake),
        }
    }
}

impl Quantity {
    /// The generated function's name: the kind's, and for a frame quantity
    /// [`FrameOf::function_name`].
    pub fn name(&self) -> String {
        match &self.frame {
            None => self.kind.name().to_owned(),
            Some(frame) => frame.function_name(self.kind),
        }
    }
}

/// Inputs of the graph, by role.
#[derive(Clone, Debug)]
pub struct Inputs {
    pub q: Vec<Id>,
    pub qd: Vec<Id>,
    pub v: Vec<Id>,
    pub a: Vec<Id>,
    /// Joint torques, created after every other quantity is traced (so adding forward dynamics
    /// left the node ids, and so the code, of the earlier functions unchanged).
    pub tau: Vec<Id>,
    /// The parameters `θ` of the regressor products (as many as there are standard
    /// parameters; the base form takes the first `B`), created after `tau`.
    pub theta: Vec<Id>,
    /// The vector `r` of `Yᵀ r`.
    pub r: Vec<Id>,
    /// A floating base's rotation (row-major) and position in the world; empty for a fixed
    /// base.
    pub base_rotation: Vec<Id>,
    pub base_position: Vec<Id>,
}

/// Every quantity of one model, recorded in one graph.
#[derive(Clone, Debug)]
pub struct SymbolicRobot {
    pub graph: Graph,
    pub inputs: Inputs,
    pub quantities: Vec<Quantity>,
    /// The base parameters whose regressor is the quantity [`QuantityKind::BaseRegressor`].
    pub base: BaseParameterSet,
    /// The groups traced.
    pub functions: Functions,
    /// The inputs the contacts' rows take (`Arg::Forces`, `Arg::Target`, `Arg::Coefficient`),
    /// created by them after every other (none without contacts).
    pub contact_inputs: ContactInputs,
    /// The outputs of functions computed in lane vectors (the regressors, four rows at a time)
    /// in a scalar formulation, by function name: the form for several states per call
    /// (`_lanes`), generic over its lane type, computes these.
    pub scalar_forms: HashMap<String, Vec<Id>>,
}

pub(super) fn ids(v: &[Expr]) -> Vec<Id> {
    v.iter().map(|e| e.id()).collect()
}

pub(super) fn matrix_ids(m: &DMatrix<Expr>) -> Vec<Id> {
    m.iter().map(|e| e.id()).collect() // nalgebra iterates column-major
}

pub(super) fn inputs(prefix: &str, n: usize) -> Vec<Expr> {
    (0..n).map(|i| Expr::input(&format!("{prefix}{i}"))).collect()
}

/// Records every quantity of `model`, fixed or floating: every group, in trace order.
pub fn trace(model: &Model) -> SymbolicRobot {
    trace_with_base(model, BaseParameterSet::compute(model))
}

/// [`trace`] with base parameters computed beforehand.
pub fn trace_with_base(model: &Model, base: BaseParameterSet) -> SymbolicRobot {
    trace_functions(model, base, Functions::all(), &Shapes::flat())
}

/// [`trace_with_base`] of the groups `functions` only: the rows of the others are not traced at
/// all (what is traced keeps the order of the full trace, so with every group the graph is the
/// same). A fixed base and a floating one take the same groups, each row by its own tracer
/// (`trace_floating.rs` for a floating base), written as `shapes` says: the frame rows in the
/// reference frames it makes straight-line code (every one, or base axes alone), and the
/// composed rows not traced at all (recorded without outputs, the emitter composes them).
pub fn trace_functions(
    model: &Model,
    base: BaseParameterSet,
    functions: Functions,
    shapes: &Shapes,
) -> SymbolicRobot {
    let (graph, traced) = match model.floating_base() {
        Some(_) => {
            record(|| super::trace_floating::FloatingTracer::new(model, &base, functions, shapes).run())
        }
        None => record(|| FixedTracer::new(model, &base, functions, shapes).run()),
    };
    traced.into_robot(graph, base, functions)
}

/// What a tracer records in the graph: the inputs, the chosen rows' quantities, and other
/// formulations of some of them.
pub(super) struct Traced {
    pub(super) inputs: Inputs,
    pub(super) quantities: Vec<Quantity>,
    /// Other formulations by function name, each kept where it costs less.
    pub(super) other_forms: Vec<(String, Vec<Id>)>,
    /// The regressors with their columns computed four rows at a time, by function name.
    pub(super) row_lane_forms: Vec<(String, Vec<Id>)>,
}

impl Traced {
    /// The traced robot of `graph`: each function in its cheapest formulation.
    pub(super) fn into_robot(
        self,
        graph: Graph,
        base: BaseParameterSet,
        functions: Functions,
    ) -> SymbolicRobot {
        let Traced {
            inputs,
            mut quantities,
            other_forms,
            row_lane_forms,
        } = self;
        // Each function in its other formulation where that costs less: the derivatives in lanes
        // rather than one direction at a time, some frame quantities by another algorithm.
        keep_cheaper(&graph, &mut quantities, other_forms);
        // The regressors four rows at a time, their cheaper scalar form kept for several states
        // per call (generic over its own lane type): the row lanes compile to fewer instructions
        // than either scalar form and run faster, though they count more operations
        // (`BENCHMARKS.md`).
        let mut scalar_forms = HashMap::new();
        for (name, outputs) in row_lane_forms {
            if let Some(q) = quantities.iter_mut().find(|q| q.name() == name) {
                scalar_forms.insert(name, std::mem::replace(&mut q.outputs, outputs));
            }
        }
        // `contacts` is a group of a robot with contacts only: without any it is not generated
        // (nor imported, nor named in the module's docs).
        let functions = match quantities
            .iter()
            .any(|q| q.kind.group() == FunctionGroup::Contacts)
        {
            true => functions,
            false => functions.without(FunctionGroup::Contacts),
        };
        SymbolicRobot {
            contact_inputs: ContactInputs::of(&graph),
            graph,
            inputs,
            quantities,
            base,
            functions,
            scalar_forms,
        }
    }
}

/// Whether row `kind` is traced for the groups `functions`: when its group is chosen, and a row
/// of base columns whenever the regressors are (it is their columns, or is traced beside them),
/// so choosing the base parameters or not leaves the node ids of the rows after it as they
/// are. What is traced for a group not chosen is dropped at the end.
fn traced(functions: &Functions, kind: QuantityKind) -> bool {
    match kind.group() {
        FunctionGroup::BaseParameters => functions.contains(FunctionGroup::Regressors),
        group => functions.contains(group),
    }
}

/// The tracer of a fixed-base robot: the inputs and the values its rows share, and what it has
/// recorded. Each row's outputs come from [`FixedTracer::outputs`]; its arguments and shape
/// from the table ([`QuantityKind::signature`]).
struct FixedTracer<'a> {
    model: &'a Model,
    base: &'a BaseParameterSet,
    functions: Functions,
    /// The reference frames of the frame rows.
    references: &'static [ReferenceFrame],
    /// The rows written composed: recorded, not traced.
    composed: Vec<QuantityKind>,
    dims: Dims,
    /// The state, created first: the shared values read it.
    q: Vec<Expr>,
    qd: Vec<Expr>,
    v: Vec<Expr>,
    a: Vec<Expr>,
    /// Torques, parameters and the vector of `Yᵀ r`, created before the first row that takes
    /// them ([`FixedTracer::create_inputs`]).
    tau: Vec<Expr>,
    theta: Vec<Expr>,
    r: Vec<Expr>,
    /// Joint transforms and body poses.
    x: Vec<Transform<Expr>>,
    world: Vec<Transform<Expr>>,
    /// The bodies' inertias and joint-level terms, of the base parameters' representative
    /// parameters.
    inertias: Vec<RigidInertia<Expr>>,
    joint_values: Vec<JointTermValues>,
    /// The end-effector pose, the gravity torque and (with the regressors) `Y`, traced before
    /// any row: the rows after them were written with these node ids.
    pose: Vec<Id>,
    gravity: Vec<Expr>,
    y: Vec<Id>,
    quantities: Vec<Quantity>,
    other_forms: Vec<(String, Vec<Id>)>,
}

impl<'a> FixedTracer<'a> {
    /// The state and the shared values, traced.
    fn new(model: &'a Model, base: &'a BaseParameterSet, functions: Functions, shapes: &Shapes) -> Self {
        let n = model.dof();
        let (q, qd, v, a) = (inputs("q", n), inputs("qd", n), inputs("v", n), inputs("a", n));
        let x = dynamics::joint_transforms(model, &q);
        let world = dynamics::body_poses(model, &x);
        let representative = base.representative(&model.parameters());
        let inertias = representative_inertias(model, &representative);
        let pose = pose_ids(&dynamics::end_effector_pose(model, &world));
        let gravity = dynamics::gravity_torque(model, &x, &inertias);
        let joint_values = model.joint_term_values_from(&representative);
        let y = match functions.contains(FunctionGroup::Regressors) {
            true => matrix_ids(&full_from_base(
                &dynamics::regressor(model, &x, &qd, &v, &a),
                base,
            )),
            false => Vec::new(),
        };
        FixedTracer {
            model,
            base,
            functions,
            references: traced_references(shapes.frame_references),
            composed: shapes.composed.clone(),
            dims: Dims {
                n,
                p: model.parameter_count(),
                b: base.count(),
                c: model.contact_rows(),
            },
            q,
            qd,
            v,
            a,
            tau: Vec::new(),
            theta: Vec::new(),
            r: Vec::new(),
            x,
            world,
            inertias,
            joint_values,
            pose,
            gravity,
            y,
            quantities: Vec::new(),
            other_forms: Vec::new(),
        }
    }

    /// Traces the chosen rows in the order of [`QuantityKind::ALL`] (the per-frame ones, last
    /// there, frame by frame), then the other formulations.
    fn run(mut self) -> Traced {
        for kind in QuantityKind::ALL.into_iter().filter(|k| !k.is_per_frame()) {
            self.create_inputs(kind);
            if !traced(&self.functions, kind) {
                continue;
            }
            match self.composed.contains(&kind) {
                true => self.record_composed(kind),
                false => {
                    let outputs = self.outputs(kind);
                    self.record(kind, outputs);
                }
            }
            if kind == QuantityKind::ForwardDynamicsDerivatives {
                // Both derivatives with their directions in lanes too, traced after the one by
                // one forms (which keep the code they had before lanes existed).
                for kind in self.flat_derivatives() {
                    let lanes = self.derivative(kind, Directions::Lanes, Placements::Multiplied);
                    self.other_forms.push((kind.name().to_owned(), lanes));
                }
            }
        }
        if self.functions.contains(FunctionGroup::Frames) {
            let spelled = frame_spellings(self.model);
            for (index, frame) in self.model.frames().iter().enumerate() {
                self.trace_frame(index, frame, &spelled[index].snake);
            }
        }
        let row_lane_forms = self.trace_other_forms();
        // The contacts' rows last, so every row before keeps its node ids.
        if self.functions.contains(FunctionGroup::Contacts) && !self.model.contacts().is_empty() {
            let (model, world, qd) = (self.model, &self.world, &self.qd);
            let mass = dynamics::forward_dynamics::factor_mass_matrix(
                model,
                &self.x,
                &self.inertias,
                &self.joint_values,
            );
            let motion = |frame: usize| dynamics::FrameMotion::new(model, world, qd, &model.frames()[frame]);
            let (x, inertias, joint_values, tau) = (&self.x, &self.inertias, &self.joint_values, &self.tau);
            // As `forward_dynamics_factored` computes it: `τ` less the bias.
            let free_force = || {
                let bias = dynamics::forward_dynamics::bias_torque(model, x, inertias, joint_values, qd);
                tau.iter().zip(&bias).map(|(&t, &b)| t - b).collect()
            };
            let state = ContactState {
                qd,
                a: &self.a,
                mass: &mass,
                tree: Tree::Fixed {
                    q: &self.q,
                    inertias: &self.inertias,
                    joint_values: &self.joint_values,
                },
                free_force: &free_force,
                rates_at_rest: None,
            };
            for (kind, outputs) in contact_outputs(model, motion, state) {
                self.record(kind, outputs);
            }
        }
        let functions = self.functions;
        self.quantities.retain(|q| functions.contains(q.kind.group()));
        Traced {
            inputs: Inputs {
                q: ids(&self.q),
                qd: ids(&self.qd),
                v: ids(&self.v),
                a: ids(&self.a),
                tau: ids(&self.tau),
                theta: ids(&self.theta),
                r: ids(&self.r),
                base_rotation: Vec::new(),
                base_position: Vec::new(),
            },
            quantities: self.quantities,
            other_forms: self.other_forms,
            row_lane_forms,
        }
    }

    /// The inputs row `kind` takes that do not exist yet (`τ`, `θ`, `r`), created before the
    /// row whether it is chosen or not, so the rows after it are traced as in the full trace
    /// (node ids follow creation order).
    fn create_inputs(&mut self, kind: QuantityKind) {
        let Dims { n, p, .. } = self.dims;
        for arg in kind.signature(self.dims).0 {
            match arg {
                Arg::Tau if self.tau.is_empty() => self.tau = inputs("tau", n),
                Arg::Theta(_) if self.theta.is_empty() => self.theta = inputs("theta", p),
                Arg::R if self.r.is_empty() => self.r = inputs("r", n),
                _ => {}
            }
        }
    }

    /// Records `outputs` as row `kind`, with the table's arguments and shape.
    fn record(&mut self, kind: QuantityKind, outputs: Vec<Id>) {
        self.quantities.push(Quantity::new(kind, self.dims, outputs));
    }

    /// Records row `kind` as composed: no outputs of its own.
    fn record_composed(&mut self, kind: QuantityKind) {
        self.quantities.push(Quantity::composed(kind, self.dims));
    }

    /// The derivative rows traced as straight-line code.
    fn flat_derivatives(&self) -> Vec<QuantityKind> {
        (DERIVATIVES.into_iter())
            .filter(|kind| !self.composed.contains(kind))
            .collect()
    }

    /// The outputs of row `kind` as recorded, if it was (empty if not).
    fn recorded(&self, kind: QuantityKind) -> Vec<Id> {
        (self.quantities.iter())
            .find(|q| q.kind == kind)
            .map(|q| q.outputs.clone())
            .unwrap_or_default()
    }

    /// How row `kind` (one not per frame) is traced: its outputs.
    fn outputs(&mut self, kind: QuantityKind) -> Vec<Id> {
        use QuantityKind as K;
        let (model, x, inertias, jv) = (self.model, &self.x, &self.inertias, &self.joint_values);
        let (qd, a) = (&self.qd, &self.a);
        match kind {
            K::ForwardKinematics => self.pose.clone(),
            K::Jacobian => matrix_ids(&dynamics::jacobian(model, &self.world)),
            K::JacobianDot => matrix_ids(&dynamics::jacobian_dot(model, &self.world, qd)),
            K::MassMatrix => matrix_ids(&self.mass_matrix(x)),
            K::CoriolisMatrix => matrix_ids(&dynamics::coriolis_matrix(model, x, inertias, qd)),
            K::Gravity => ids(&self.gravity),
            K::InverseDynamics => ids(&self.inverse_dynamics(x)),
            K::SlotineLi => ids(&self.slotine_li()),
            K::Regressor => self.y.clone(),
            K::TorqueRegressor => {
                let y = dynamics::regressor(model, x, qd, qd, a);
                matrix_ids(&full_from_base(&y, self.base))
            }
            K::BaseRegressor => base_columns(&self.recorded(K::Regressor), self.base, self.dims.n),
            K::BaseTorqueRegressor => {
                base_columns(&self.recorded(K::TorqueRegressor), self.base, self.dims.n)
            }
            K::ForwardDynamics => ids(&dynamics::forward_dynamics(model, x, inertias, jv, qd, &self.tau)),
            K::MassMatrixInverse => matrix_ids(&dynamics::mass_matrix_inverse(model, x, inertias, jv)),
            K::InverseDynamicsDerivatives => {
                self.derivative(kind, Directions::OneByOne, Placements::Multiplied)
            }
            K::ForwardDynamicsDerivatives => {
                self.derivative(kind, Directions::OneByOne, Placements::Multiplied)
            }
            // Forward kinematics, `J` and `J̇` in one function: the nodes the three share (joint
            // transforms, body poses) are computed once. No new nodes, only their outputs.
            K::Kinematics => [K::ForwardKinematics, K::Jacobian, K::JacobianDot]
                .into_iter()
                .flat_map(|k| self.recorded(k))
                .collect(),
            K::RegressorProducts | K::BaseRegressorProducts => self.regressor_products(kind),
            _ => unreachable!("{kind:?} is not a row of a fixed base traced on its own"),
        }
    }

    /// `D` with the armature, of the joint transforms `x`.
    fn mass_matrix<X: CompositeFrame<Expr>>(&self, x: &[X]) -> DMatrix<Expr> {
        let mut d = dynamics::mass_matrix(self.model, x, &self.inertias);
        dynamics::add_armature(self.model, &self.joint_values, &mut d);
        d
    }

    /// `τ` with the joint-level terms, of the joint transforms `x`.
    fn inverse_dynamics<X: JointFrame<Expr>>(&self, x: &[X]) -> Vec<Expr> {
        let rigid = dynamics::inverse_dynamics(self.model, x, &self.inertias, &self.qd, &self.a);
        self.with_joint_terms(rigid, &self.qd)
    }

    /// The Slotine–Li torque with the joint-level terms.
    fn slotine_li(&self) -> Vec<Expr> {
        let (model, x, inertias) = (self.model, &self.x, &self.inertias);
        let gravity = Some(Vec3::from_f64(model.gravity().into()));
        let rigid = dynamics::slotine_li(model, x, inertias, &self.qd, &self.v, &self.a, gravity);
        self.with_joint_terms(rigid, &self.v)
    }

    /// `rigid` torques plus the joint-level terms (armature, friction, offset) with `v` as the
    /// reference velocity (Slotine–Li's `v`, else `q̇`). Added only when the model has them, so
    /// a model without them records exactly the graph it always did.
    fn with_joint_terms(&self, rigid: Vec<Expr>, v: &[Expr]) -> Vec<Expr> {
        if self.model.joint_terms().kinds.is_empty() {
            return rigid;
        }
        let terms = dynamics::joint_term_torques(self.model, &self.joint_values, &self.qd, v, &self.a);
        dynamics::add_torques(rigid, &terms)
    }

    /// The outputs of derivative row `kind` (of `τ` or of `q̈`), their directions and joint
    /// transforms carried as `directions` and `placements` say.
    fn derivative(&self, kind: QuantityKind, directions: Directions, placements: Placements) -> Vec<Id> {
        let (model, q, inertias, jv, qd) =
            (self.model, &self.q, &self.inertias, &self.joint_values, &self.qd);
        pair_ids(match kind {
            QuantityKind::InverseDynamicsDerivatives => dynamics::inverse_dynamics_derivatives_by(
                directions, placements, model, q, inertias, jv, qd, &self.a,
            ),
            QuantityKind::ForwardDynamicsDerivatives => dynamics::forward_dynamics_derivatives_by(
                directions, placements, model, q, inertias, jv, qd, &self.tau,
            ),
            _ => unreachable!("{kind:?} is not a derivative"),
        })
    }

    /// `(Y θ, Yᵀ r)` of the Slotine–Li regressor, or `(Y_b θ_b, Y_bᵀ r)` of its base columns,
    /// without forming either regressor (`dynamics::regressor_products`): what an adaptive law
    /// needs each tick, on inputs of its own.
    fn regressor_products(&self, kind: QuantityKind) -> Vec<Id> {
        let all: Vec<usize> = (0..self.dims.p).collect();
        let (columns, len) = match kind.uses_base_columns() {
            true => (&self.base.columns, self.dims.b),
            false => (&all, self.dims.p),
        };
        let (qd, v, a) = (&self.qd, &self.v, &self.a);
        let (y_theta, y_tr_r) = dynamics::regressor_products(
            self.model,
            &self.x,
            qd,
            v,
            a,
            columns,
            &self.theta[..len],
            &self.r,
        );
        ids(&y_theta).into_iter().chain(ids(&y_tr_r)).collect()
    }

    /// The per-frame rows of one frame, then other formulations of some of them (the local `J`
    /// carried back from the frame, velocity and acceleration by the forward recursion), kept
    /// where they cost less.
    fn trace_frame(&mut self, index: usize, frame: &Frame, snake: &str) {
        let (model, qd) = (self.model, &self.qd);
        let motion = dynamics::FrameMotion::new(model, &self.world, qd, frame);
        let rows = frame_rows(&motion, qd, &self.a, index, snake, self.dims, self.references);
        self.quantities.extend(rows);
        let name_of = |kind, reference| FrameOf::new(index, snake, Some(reference)).function_name(kind);
        let mut other_forms = Vec::new();
        if self.references.contains(&ReferenceFrame::Local) {
            other_forms.push((
                name_of(QuantityKind::FrameJacobian, ReferenceFrame::Local),
                matrix_ids(&dynamics::local_jacobian(model, &self.x, frame)),
            ));
        }
        let rates = dynamics::FrameRates::new(model, &self.x, qd, &self.a, frame);
        for &r in self.references {
            other_forms.push((
                name_of(QuantityKind::FrameVelocity, r),
                ids(&rates.velocity_in(r, &motion.pose)),
            ));
            other_forms.push((
                name_of(QuantityKind::FrameClassicalAcceleration, r),
                ids(&rates.classical_acceleration_in(r, &motion.pose)),
            ));
        }
        self.other_forms.extend(other_forms);
    }

    /// Other formulations of some rows, traced after every row so those keep their node ids,
    /// each kept where it costs less; returns the regressors four rows at a time.
    fn trace_other_forms(&mut self) -> Vec<(String, Vec<Id>)> {
        let regressors = self.functions.contains(FunctionGroup::Regressors);
        if regressors {
            self.regressors_by_jacobians();
        }
        let row_lane_forms = match regressors {
            true => row_lane_regressors(self.model, &self.x, [&self.qd, &self.v, &self.a], self.base),
            false => Vec::new(),
        };
        if has_tilted_placements(self.model) {
            self.factored_forms();
        }
        row_lane_forms
    }

    /// The regressors (and their base columns) by the bodies' Jacobians, kept per function where
    /// they cost less.
    fn regressors_by_jacobians(&mut self) {
        use QuantityKind as K;
        let (model, x, qd, a) = (self.model, &self.x, &self.qd, &self.a);
        let mut forms = Vec::new();
        for (kind, base_kind, v) in [
            (K::Regressor, K::BaseRegressor, &self.v),
            (K::TorqueRegressor, K::BaseTorqueRegressor, qd),
        ] {
            let y = matrix_ids(&full_from_base(
                &dynamics::regressor_by_jacobians(model, x, qd, v, a),
                self.base,
            ));
            let y_base = base_columns(&y, self.base, self.dims.n);
            forms.push((kind.name().to_owned(), y));
            forms.push((base_kind.name().to_owned(), y_base));
        }
        self.other_forms.extend(forms);
    }

    /// `D`, `τ`, forward dynamics, `D⁻¹` and the derivatives (of the chosen groups) through each
    /// joint's placement and own motion one after the other, kept where they cost less. (`C` in
    /// this form counts fewer operations on the xArm as written but runs slower in default
    /// builds, `BENCHMARKS.md`.)
    fn factored_forms(&mut self) {
        use QuantityKind as K;
        let (model, inertias, jv, qd) = (self.model, &self.inertias, &self.joint_values, &self.qd);
        let factored = dynamics::joint_factored_transforms(model, &self.q);
        let mut forms = vec![
            (K::MassMatrix, matrix_ids(&self.mass_matrix(&factored))),
            (K::InverseDynamics, ids(&self.inverse_dynamics(&factored))),
        ];
        if self.functions.contains(FunctionGroup::ForwardDynamics) {
            if !self.composed.contains(&K::ForwardDynamics) {
                let forward = dynamics::forward_dynamics(model, &factored, inertias, jv, qd, &self.tau);
                forms.push((K::ForwardDynamics, ids(&forward)));
            }
            if !self.composed.contains(&K::MassMatrixInverse) {
                let inverse = dynamics::mass_matrix_inverse(model, &factored, inertias, jv);
                forms.push((K::MassMatrixInverse, matrix_ids(&inverse)));
            }
        }
        if self.functions.contains(FunctionGroup::Derivatives) {
            for directions in [Directions::OneByOne, Directions::Lanes] {
                for kind in self.flat_derivatives() {
                    forms.push((kind, self.derivative(kind, directions, Placements::Factored)));
                }
            }
        }
        let named = forms
            .into_iter()
            .map(|(kind, outputs)| (kind.name().to_owned(), outputs));
        self.other_forms.extend(named);
    }
}

/// The derivative rows, in the order they are traced.
const DERIVATIVES: [QuantityKind; 2] = [
    QuantityKind::InverseDynamicsDerivatives,
    QuantityKind::ForwardDynamicsDerivatives,
];

/// Whether a joint's placement in its parent turns by anything but quarter turns (a vendor's
/// `1.5708`, a tilted axis): there, carrying vectors and inertias through the placement and the
/// joint's own rotation one after the other ([`FactoredTransform`](crate::spatial::FactoredTransform))
/// can cost less than through their product, whose every entry the tilt makes dense. With
/// quarter turns only, the product is as sparse as its factors and the usual form is kept as
/// it is.
fn has_tilted_placements(model: &Model) -> bool {
    model
        .joints()
        .iter()
        .any(|j| j.origin.rotation.iter().any(|&r| r != 0.0 && r.abs() != 1.0))
}

/// The bodies' inertias of the parameter vector `theta` (ten per body, then joint terms).
fn representative_inertias(model: &Model, theta: &[f64]) -> Vec<crate::spatial::RigidInertia<Expr>> {
    let inertial: Vec<Expr> = theta[..model.inertial_parameter_count()]
        .iter()
        .map(|&x| <Expr as crate::scalar::Scalar>::from_f64(x))
        .collect();
    dynamics::inertias_from_parameters(&inertial)
}

pub(super) fn pair_ids((first, second): (DMatrix<Expr>, DMatrix<Expr>)) -> Vec<Id> {
    let mut out = matrix_ids(&first);
    out.extend(matrix_ids(&second));
    out
}

/// A lane operation (`f64x8`) weighed as this many scalar ones when the derivatives choose how
/// to carry their directions ([`Directions`]): the weight that tells the measured cases apart
/// (`BENCHMARKS.md`, AVX-512). The Panda's derivatives (6,850 scalar operations against 1,151 +
/// 2,675 lane ones) run faster in lanes, the UR5's (3,050 against 808 + 1,587) do not.
const LANE_OP_COST: usize = 2;

/// Each function named in `other_forms` in that formulation where it costs less.
pub(super) fn keep_cheaper(graph: &Graph, quantities: &mut [Quantity], other_forms: Vec<(String, Vec<Id>)>) {
    for (name, outputs) in other_forms {
        // A composed row has no outputs: nothing to replace.
        if let Some(q) = quantities.iter_mut().find(|q| q.name() == name && !q.composed) {
            if cost(graph, &outputs) < cost(graph, &q.outputs) {
                q.outputs = outputs;
            }
        }
    }
}

/// What a function costs by [`LANE_OP_COST`].
fn cost(graph: &Graph, outputs: &[Id]) -> usize {
    let c = graph.op_counts(outputs);
    c.mul + c.add + c.neg + c.div + LANE_OP_COST * c.lanes
}

/// The base columns of a column-major `Y` (`n` rows; column `c` is `y[c·n .. (c+1)·n]`); none
/// when `Y` was not traced.
pub(super) fn base_columns(y: &[Id], base: &BaseParameterSet, n: usize) -> Vec<Id> {
    base.columns
        .iter()
        .flat_map(|&c| y.get(c * n..(c + 1) * n).unwrap_or_default().iter().copied())
        .collect()
}

/// `Y` rebuilt from its base columns. `θ_b = K θ` for every `θ` (exact folding), so `Y = Y_b K`:
/// a folded column is the few base columns its parameter folds into, scaled, instead of a
/// regressor column traced on its own (torque-form `Y`: UR5 1,732 → 1,321 operations, Panda
/// 2,178 → 1,761; Slotine–Li `Y`: Panda 3,108 → 2,397). A parameter that folds into nothing has
/// a zero column.
pub(super) fn full_from_base(y: &DMatrix<Expr>, base: &BaseParameterSet) -> DMatrix<Expr> {
    full_from_base_entries(y, base, <Expr as Scalar>::zero(), |c, e| Expr::from_f64(c) * e)
}

/// [`full_from_base`] on any entries: scalars, or the lane vectors of rows computed side by side
/// (`scale(c, e)` is `c·e`).
fn full_from_base_entries<T: nalgebra::Scalar + Copy + std::ops::Add<Output = T>>(
    y: &DMatrix<T>,
    base: &BaseParameterSet,
    zero: T,
    scale: impl Fn(f64, T) -> T,
) -> DMatrix<T> {
    let mut full = DMatrix::from_element(y.nrows(), y.ncols(), zero);
    for (k, terms) in base.terms.iter().enumerate() {
        let kept = base.columns[k];
        for &(j, c) in terms {
            for r in 0..y.nrows() {
                let scaled = match c == 1.0 {
                    true => y[(r, kept)],
                    false => scale(c, y[(r, kept)]),
                };
                full[(r, j)] = full[(r, j)] + scaled;
            }
        }
    }
    full
}

/// The four regressors (Slotine–Li and torque form, all and base columns) with their columns
/// computed [`dynamics::ROW_LANES`] rows at a time ([`dynamics::regressor_row_lanes`]), by
/// function name: the folded columns rebuilt from the base columns on the lane vectors. Traced
/// last, so the other functions keep their node ids.
fn row_lane_regressors(
    model: &Model,
    x: &[crate::spatial::Transform<Expr>],
    [qd, v, a]: [&[Expr]; 3],
    base: &BaseParameterSet,
) -> Vec<(String, Vec<Id>)> {
    let n = model.dof();
    let mut forms = Vec::new();
    for (name, base_name, v) in [
        ("regressor", "base_regressor", v),
        ("torque_regressor", "base_torque_regressor", qd),
    ] {
        let runs = dynamics::regressor_row_lanes(model, x, qd, v, a);
        let runs = DMatrix::from_fn(runs.len(), model.parameter_count(), |r, c| runs[r][c]);
        let full = full_from_base_entries(&runs, base, LaneExpr::zero(), |c, e| e.scale(Expr::from_f64(c)));
        let rows = dynamics::ROW_LANES;
        let y: Vec<Id> = (0..full.ncols())
            .flat_map(|c| (0..n).map(move |i| (i, c)))
            .map(|(i, c)| full[(i / rows, c)].lane(i % rows).id())
            .collect();
        let y_base = base_columns(&y, base, n);
        forms.push((name.to_string(), y));
        forms.push((base_name.to_string(), y_base));
    }
    forms
}

/// How the model's frames are spelled in generated code, told apart where two would be spelled
/// alike (`frame_names`): the one list the tracers and the emitter name frames by.
pub(super) fn frame_spellings(model: &Model) -> Vec<FrameIdentifiers> {
    frame_identifiers(model.frames().iter().map(|f| f.name.as_str()))
}

/// The reference frames whose frame rows are traced: every one, or with
/// `frame_references: aligned` the base axes alone: the emitted code converts to the others at
/// run time (`dyngen_runtime::__private::frame_references`).
pub(super) fn traced_references(choice: FrameReferences) -> &'static [ReferenceFrame] {
    match choice {
        FrameReferences::Auto | FrameReferences::All => &ReferenceFrame::ALL,
        FrameReferences::Aligned => &[ReferenceFrame::LocalWorldAligned],
    }
}

/// The per-frame rows of one frame (`index` in `Model::frames`, spelled `snake`) from its
/// motion, in the table's order, each once per reference frame of `references` where it has
/// one; `dims.n` velocity coordinates.
pub(super) fn frame_rows(
    motion: &dynamics::FrameMotion<Expr>,
    qd: &[Expr],
    qdd: &[Expr],
    index: usize,
    snake: &str,
    dims: Dims,
    references: &[ReferenceFrame],
) -> Vec<Quantity> {
    let mut rows = Vec::new();
    for kind in QuantityKind::ALL.into_iter().filter(|k| k.is_per_frame()) {
        let references = match kind.has_reference_frame() {
            true => references.iter().copied().map(Some).collect(),
            false => vec![None],
        };
        for reference in references {
            let (args, shape) = kind.signature(dims);
            rows.push(Quantity {
                kind,
                frame: Some(FrameOf::new(index, snake, reference)),
                args,
                shape,
                outputs: frame_outputs(motion, kind, reference, qd, qdd),
                composed: false,
            });
        }
    }
    rows
}

/// How per-frame row `kind` is traced: its outputs in `reference` (`None` for a row without).
fn frame_outputs(
    motion: &dynamics::FrameMotion<Expr>,
    kind: QuantityKind,
    reference: Option<ReferenceFrame>,
    qd: &[Expr],
    qdd: &[Expr],
) -> Vec<Id> {
    use QuantityKind as K;
    match (kind, reference) {
        (K::FramePose, None) => pose_ids(&motion.pose),
        (K::FrameJacobian, Some(r)) => matrix_ids(&motion.jacobian_in(r)),
        (K::FrameJacobianTimeVariation, Some(r)) => matrix_ids(&motion.jacobian_dot_in(r, qd)),
        (K::FrameVelocity, Some(r)) => ids(&motion.velocity_in(r, qd)),
        (K::FrameClassicalAcceleration, Some(r)) => ids(&motion.classical_acceleration_in(r, qd, qdd)),
        (K::FrameKinematics, None) => {
            let mut fused = pose_ids(&motion.pose);
            fused.extend(matrix_ids(&motion.jacobian));
            fused.extend(matrix_ids(&motion.jacobian_dot));
            fused
        }
        _ => unreachable!("{kind:?} in {reference:?} is not a per-frame row"),
    }
}

/// A pose's outputs: the rotation column-major, then the translation.
pub(super) fn pose_ids(pose: &crate::spatial::Transform<Expr>) -> Vec<Id> {
    let mut out: Vec<Id> = pose.rot.transpose().0.iter().flatten().map(|e| e.id()).collect();
    out.extend(pose.pos.0.iter().map(|e| e.id()));
    out
}

/// The arguments of [`SymbolicRobot::evaluate_with`], by role (empty: not given).
#[derive(Clone, Copy, Debug, Default)]
pub struct Arguments<'a> {
    pub q: &'a [f64],
    pub qd: &'a [f64],
    pub v: &'a [f64],
    pub a: &'a [f64],
    pub tau: &'a [f64],
    pub theta: &'a [f64],
    pub r: &'a [f64],
    /// The contact forces `λ`.
    pub forces: &'a [f64],
    /// The contact rows' target.
    pub target: &'a [f64],
    /// The contact solves' coefficients (those not given are 0).
    pub coefficients: &'a [(Coefficient, f64)],
}

impl SymbolicRobot {
    /// A constant of the graph that is not finite, if any: folding constants of a model with
    /// absurd magnitudes (a mass of 1e300) overflows, and such a constant cannot be emitted.
    pub fn non_finite_constant(&self) -> Option<f64> {
        (0..self.graph.len())
            .filter_map(|i| self.graph.constant_value(crate::symbolic::Id(i as u32)))
            .find(|v| !v.is_finite())
    }

    pub fn quantity(&self, name: &str) -> Option<&Quantity> {
        self.quantities.iter().find(|q| q.name() == name)
    }

    /// Evaluates a quantity with the interpreter (for tests on robots that are never compiled).
    pub fn evaluate(&self, name: &str, q: &[f64], qd: &[f64], v: &[f64], a: &[f64]) -> Option<Vec<f64>> {
        self.evaluate_with(
            name,
            &Arguments {
                q,
                qd,
                v,
                a,
                ..Arguments::default()
            },
        )
    }

    /// [`SymbolicRobot::evaluate`] of a function of the torques `tau` (forward dynamics).
    pub fn evaluate_tau(&self, name: &str, q: &[f64], qd: &[f64], tau: &[f64]) -> Option<Vec<f64>> {
        self.evaluate_with(
            name,
            &Arguments {
                q,
                qd,
                tau,
                ..Arguments::default()
            },
        )
    }

    /// [`SymbolicRobot::evaluate`] with every kind of argument (those a function does not take
    /// are ignored).
    pub fn evaluate_with(&self, name: &str, args: &Arguments) -> Option<Vec<f64>> {
        let quantity = self.quantity(name)?;
        let mut values = vec![0.0; self.graph.input_names().len()];
        // A floating base's `q` is the whole configuration: the base pose, then the joints.
        let (base_rotation, base_position, q) = match self.inputs.base_rotation.is_empty() {
            true => (Vec::new(), Vec::new(), args.q),
            false => {
                let base = dyngen_runtime::BasePose::from_configuration(args.q).ok()?;
                let rotation: Vec<f64> = (0..9).map(|k| base.rotation[(k / 3, k % 3)]).collect();
                (rotation, base.position.as_slice().to_vec(), &args.q[7..])
            }
        };
        for (ids, xs) in [
            (&self.inputs.base_rotation, &base_rotation[..]),
            (&self.inputs.base_position, &base_position[..]),
            (&self.inputs.q, q),
            (&self.inputs.qd, args.qd),
            (&self.inputs.v, args.v),
            (&self.inputs.a, args.a),
            (&self.inputs.tau, args.tau),
            (&self.inputs.theta, args.theta),
            (&self.inputs.r, args.r),
            (&self.contact_inputs.forces, args.forces),
            (&self.contact_inputs.target, args.target),
        ] {
            for (id, x) in ids.iter().zip(xs) {
                if let crate::symbolic::Node::Input(k) = self.graph.node(*id) {
                    values[k as usize] = *x;
                }
            }
        }
        for &(c, x) in args.coefficients {
            let input = self.contact_inputs.coefficient(c).map(|id| self.graph.node(id));
            if let Some(crate::symbolic::Node::Input(k)) = input {
                values[k as usize] = x;
            }
        }
        Some(crate::symbolic::evaluate(&self.graph, &values, &quantity.outputs))
    }
}
