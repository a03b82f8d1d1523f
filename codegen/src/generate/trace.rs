//! Runs the generic dynamics algorithms on symbolic inputs: one graph holds every quantity a
//! controller needs, so shared subexpressions (joint transforms, body velocities) are one node.

use super::quantities::QuantityKind;
use crate::base_parameters::BaseParameterSet;
use crate::dynamics::{self, Directions, Placements};
use crate::frame_names::frame_identifiers;
use crate::model::Model;
use crate::scalar::Scalar;
use crate::scalar_dual::{LaneTangent, Tangent};
use crate::symbolic::{record, Expr, Graph, Id, LaneExpr};
use crate::{FunctionGroup, Functions};
use dyngen_runtime::ReferenceFrame;
use nalgebra::DMatrix;
use std::collections::HashMap;

/// The vectors a generated function takes besides the joint sines and cosines.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Arg {
    Qd,
    V,
    A,
    /// Joint torques (forward dynamics).
    Tau,
    /// The first `len` parameters `θ` (a parameter vector of that length: all of them, or the
    /// base parameters).
    Theta(usize),
    /// The vector `r` an adaptation law multiplies `Yᵀ` with.
    R,
}

/// What a generated function returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shape {
    /// A vector of `n` entries.
    Vector(usize),
    /// A `rows × cols` matrix (outputs column-major).
    Matrix(usize, usize),
    /// A rotation (3×3, column-major) followed by a translation.
    Pose,
    /// Two `n × n` matrices (derivatives with respect to `q` and `q̇`), each column-major.
    MatrixPair(usize),
    /// A pose, then `J` and `J̇` (6 × n each, column-major): the kinematics of a control tick.
    Kinematics(usize),
    /// Two vectors, of `n` and of `m` entries (`Y θ` and `Yᵀ r`).
    VectorPair(usize, usize),
}

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
    /// Output nodes in the order of the shape (column-major for matrices).
    pub outputs: Vec<Id>,
}

impl FrameOf {
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
    /// Values per chunk function when emitted ([`CHUNK_VALUES`] as traced): a function that
    /// computes more is emitted in chunks. Tests set it small to run the chunked code of a small
    /// robot.
    pub chunk_values: usize,
    /// The outputs of functions computed in lane vectors (the regressors, four rows at a time)
    /// in a scalar formulation, by function name: the form for several states per call
    /// (`_lanes`), generic over its lane type, computes these.
    pub scalar_forms: HashMap<String, Vec<Id>>,
}

use super::emit::CHUNK_VALUES;

pub(super) fn ids(v: &[Expr]) -> Vec<Id> {
    v.iter().map(|e| e.id()).collect()
}

pub(super) fn matrix_ids(m: &DMatrix<Expr>) -> Vec<Id> {
    m.iter().map(|e| e.id()).collect() // nalgebra iterates column-major
}

pub(super) fn inputs(prefix: &str, n: usize) -> Vec<Expr> {
    (0..n).map(|i| Expr::input(&format!("{prefix}{i}"))).collect()
}

/// Records forward kinematics, `J`, `J̇`, `D`, `C`, `g`, `τ`, the Slotine–Li torque, the
/// regressor and the base-parameter regressor of `model`, in that order.
pub fn trace(model: &Model) -> SymbolicRobot {
    trace_with_base(model, BaseParameterSet::compute(model))
}

/// [`trace`] with base parameters computed beforehand.
pub fn trace_with_base(model: &Model, base: BaseParameterSet) -> SymbolicRobot {
    trace_functions(model, base, Functions::all())
}

/// [`trace_with_base`] of the groups `functions` only: the others are not traced at all (what
/// is traced keeps the order of the full trace, so with every group the graph is the same).
pub fn trace_functions(model: &Model, base: BaseParameterSet, functions: Functions) -> SymbolicRobot {
    let n = model.dof();
    let regressors = functions.contains(FunctionGroup::Regressors);
    let (graph, (inputs, mut quantities, other_forms, row_lane_forms)) = record(|| {
        let (q, qd, v, a) = (inputs("q", n), inputs("qd", n), inputs("v", n), inputs("a", n));
        let x = dynamics::joint_transforms(model, &q);
        let world = dynamics::body_poses(model, &x);
        let theta = base.representative(&model.parameters());
        let inertias = representative_inertias(model, &theta);
        let pose = pose_ids(&dynamics::end_effector_pose(model, &world));
        let g = dynamics::gravity_torque(model, &x, &inertias);
        // Joint-level terms (armature, friction, offset) are added only when the model has
        // them, so a model without them records exactly the graph it always did.
        let joint_values = model.joint_term_values_from(&theta);
        let has_joint_terms = !model.joint_terms().kinds.is_empty();
        let with_joint_terms = |rigid: Vec<Expr>, v: &[Expr], a: &[Expr]| match has_joint_terms {
            true => dynamics::add_torques(
                rigid,
                &dynamics::joint_term_torques(model, &joint_values, &qd, v, a),
            ),
            false => rigid,
        };
        // Called where `D` was always recorded: node ids follow creation order, and the emitted
        // code of a robot without joint terms must stay byte-identical.
        let mass_matrix = || {
            let mut d = dynamics::mass_matrix(model, &x, &inertias);
            dynamics::add_armature(model, &joint_values, &mut d);
            d
        };
        let y = match regressors {
            true => matrix_ids(&full_from_base(
                &dynamics::regressor(model, &x, &qd, &v, &a),
                &base,
            )),
            false => Vec::new(),
        };
        let y_base = base_columns(&y, &base, n);
        let quantities = vec![
            Quantity {
                kind: QuantityKind::ForwardKinematics,
                frame: None,
                args: vec![],
                shape: Shape::Pose,
                outputs: pose,
            },
            Quantity {
                kind: QuantityKind::Jacobian,
                frame: None,
                args: vec![],
                shape: Shape::Matrix(6, n),
                outputs: matrix_ids(&dynamics::jacobian(model, &world)),
            },
            Quantity {
                kind: QuantityKind::JacobianDot,
                frame: None,
                args: vec![Arg::Qd],
                shape: Shape::Matrix(6, n),
                outputs: matrix_ids(&dynamics::jacobian_dot(model, &world, &qd)),
            },
            Quantity {
                kind: QuantityKind::MassMatrix,
                frame: None,
                args: vec![],
                shape: Shape::Matrix(n, n),
                outputs: matrix_ids(&mass_matrix()),
            },
            Quantity {
                kind: QuantityKind::CoriolisMatrix,
                frame: None,
                args: vec![Arg::Qd],
                shape: Shape::Matrix(n, n),
                outputs: matrix_ids(&dynamics::coriolis_matrix(model, &x, &inertias, &qd)),
            },
            Quantity {
                kind: QuantityKind::Gravity,
                frame: None,
                args: vec![],
                shape: Shape::Vector(n),
                outputs: ids(&g),
            },
            Quantity {
                kind: QuantityKind::InverseDynamics,
                frame: None,
                args: vec![Arg::Qd, Arg::A],
                shape: Shape::Vector(n),
                outputs: ids(&with_joint_terms(
                    dynamics::inverse_dynamics(model, &x, &inertias, &qd, &a),
                    &qd,
                    &a,
                )),
            },
            Quantity {
                kind: QuantityKind::SlotineLi,
                frame: None,
                args: vec![Arg::Qd, Arg::V, Arg::A],
                shape: Shape::Vector(n),
                outputs: ids(&with_joint_terms(
                    dynamics::slotine_li(
                        model,
                        &x,
                        &inertias,
                        &qd,
                        &v,
                        &a,
                        Some(crate::spatial::Vec3::from_f64(model.gravity().into())),
                    ),
                    &v,
                    &a,
                )),
            },
            Quantity {
                kind: QuantityKind::Regressor,
                frame: None,
                args: vec![Arg::Qd, Arg::V, Arg::A],
                shape: Shape::Matrix(n, model.parameter_count()),
                outputs: y,
            },
            Quantity {
                kind: QuantityKind::BaseRegressor,
                frame: None,
                args: vec![Arg::Qd, Arg::V, Arg::A],
                shape: Shape::Matrix(n, base.count()),
                outputs: y_base,
            },
        ];
        let mut quantities = quantities;
        let tau = inputs("tau", n);
        let (forward, mut other_forms) =
            forward_quantities(model, &inertias, &joint_values, &q, &qd, &a, &tau, functions);
        quantities.extend(forward);
        if regressors {
            quantities.extend(torque_regressors(model, &x, &qd, &a, &base));
        }
        quantities.push(fused_kinematics(&quantities, n));
        let (theta, r) = (inputs("theta", model.parameter_count()), inputs("r", n));
        if regressors {
            quantities.extend(regressor_products(model, &x, [&qd, &v, &a], &theta, &r, &base));
        }
        if functions.contains(FunctionGroup::Frames) {
            for (index, frame) in model.frames().iter().enumerate() {
                let (traced, frame_forms) = frame_quantities(model, &x, &world, &qd, &a, index, frame);
                quantities.extend(traced);
                other_forms.extend(frame_forms);
            }
        }
        if regressors {
            // The regressors by the bodies' Jacobians, traced last so the functions above keep
            // their node ids; kept per function where they cost less.
            for (name, base_name, v) in [
                ("regressor", "base_regressor", &v),
                ("torque_regressor", "base_torque_regressor", &qd),
            ] {
                let y = matrix_ids(&full_from_base(
                    &dynamics::regressor_by_jacobians(model, &x, &qd, v, &a),
                    &base,
                ));
                let y_base = base_columns(&y, &base, n);
                other_forms.push((name.to_string(), y));
                other_forms.push((base_name.to_string(), y_base));
            }
        }
        let row_lane_forms = match regressors {
            true => row_lane_regressors(model, &x, [&qd, &v, &a], &base),
            false => Vec::new(),
        };
        if has_tilted_placements(model) {
            // `D`, `τ`, forward dynamics and `D⁻¹` through each joint's placement and own motion
            // one after the other, traced after everything else so the functions above keep
            // their node ids; kept where they cost less. (`C` in this form cost 8% fewer
            // operations on the xArm as written but ran 1.33× slower in default builds.)
            let factored = dynamics::joint_factored_transforms(model, &q);
            let mut d = dynamics::mass_matrix(model, &factored, &inertias);
            dynamics::add_armature(model, &joint_values, &mut d);
            other_forms.push((QuantityKind::MassMatrix.name().to_owned(), matrix_ids(&d)));
            let id = with_joint_terms(
                dynamics::inverse_dynamics(model, &factored, &inertias, &qd, &a),
                &qd,
                &a,
            );
            other_forms.push((QuantityKind::InverseDynamics.name().to_owned(), ids(&id)));
            if functions.contains(FunctionGroup::ForwardDynamics) {
                let forward =
                    dynamics::forward_dynamics(model, &factored, &inertias, &joint_values, &qd, &tau);
                other_forms.push((QuantityKind::ForwardDynamics.name().to_owned(), ids(&forward)));
                let inverse = dynamics::mass_matrix_inverse(model, &factored, &inertias, &joint_values);
                other_forms.push((
                    QuantityKind::MassMatrixInverse.name().to_owned(),
                    matrix_ids(&inverse),
                ));
            }
            if functions.contains(FunctionGroup::Derivatives) {
                for directions in [Directions::OneByOne, Directions::Lanes] {
                    let args = [&q[..], &qd, &a, &tau];
                    let (inverse, forward) = derivatives(
                        model,
                        directions,
                        Placements::Factored,
                        &inertias,
                        &joint_values,
                        args,
                    );
                    other_forms.push((
                        QuantityKind::InverseDynamicsDerivatives.name().to_owned(),
                        inverse,
                    ));
                    other_forms.push((
                        QuantityKind::ForwardDynamicsDerivatives.name().to_owned(),
                        forward,
                    ));
                }
            }
        }
        quantities.retain(|q| functions.contains(q.kind.group()));
        (
            Inputs {
                q: ids(&q),
                qd: ids(&qd),
                v: ids(&v),
                a: ids(&a),
                tau: ids(&tau),
                theta: ids(&theta),
                r: ids(&r),
                base_rotation: Vec::new(),
                base_position: Vec::new(),
            },
            quantities,
            other_forms,
            row_lane_forms,
        )
    });
    // Each function in its other formulation where that costs less: the derivatives in lanes
    // rather than one direction at a time, some frame quantities by another algorithm.
    keep_cheaper(&graph, &mut quantities, other_forms);
    // The regressors four rows at a time, their cheaper scalar form kept for several states per
    // call: on the Panda, the UR5 and the xArm as written the row lanes compiled to 4–38% fewer
    // instructions than either scalar form and ran faster on every regressor (Zen 3, side by
    // side with both anchors), though they count more operations.
    let mut scalar_forms = HashMap::new();
    for (name, outputs) in row_lane_forms {
        if let Some(q) = quantities.iter_mut().find(|q| q.name() == name) {
            scalar_forms.insert(name, std::mem::replace(&mut q.outputs, outputs));
        }
    }
    SymbolicRobot {
        graph,
        inputs,
        quantities,
        base,
        functions,
        chunk_values: CHUNK_VALUES,
        scalar_forms,
    }
}

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
/// to carry their directions ([`Directions`]). Measured (`BENCHMARKS.md`, AVX-512): the Panda's
/// derivatives ran 1.5–2.2× faster in lanes (6,850 scalar operations against 1,151 + 2,675
/// lane ones), the UR5's no faster (3,050 against 808 + 1,587), as this weight predicts.
const LANE_OP_COST: usize = 2;

/// Each function named in `other_forms` in that formulation where it costs less.
pub(super) fn keep_cheaper(graph: &Graph, quantities: &mut [Quantity], other_forms: Vec<(String, Vec<Id>)>) {
    for (name, outputs) in other_forms {
        if let Some(q) = quantities.iter_mut().find(|q| q.name() == name) {
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

/// Forward dynamics, `D⁻¹` and the derivatives of the dynamics, traced after the other
/// quantities so that they reuse (never renumber) the nodes those created. The derivatives are
/// traced with their directions one by one (first, so their code is what it was before lanes
/// existed), and in lanes: the second list holds the lane forms' outputs by function name, which
/// [`trace_functions`] keeps where they cost less.
#[allow(clippy::too_many_arguments)]
fn forward_quantities(
    model: &Model,
    inertias: &[crate::spatial::RigidInertia<Expr>],
    jv: &[crate::model::JointTermValues],
    q: &[Expr],
    qd: &[Expr],
    a: &[Expr],
    tau: &[Expr],
    functions: Functions,
) -> (Vec<Quantity>, Vec<(String, Vec<Id>)>) {
    let n = model.dof();
    let x = dynamics::joint_transforms(model, q);
    let mut quantities = Vec::new();
    if functions.contains(FunctionGroup::ForwardDynamics) {
        let forward = ids(&dynamics::forward_dynamics(model, &x, inertias, jv, qd, tau));
        let inverse_mass = matrix_ids(&dynamics::mass_matrix_inverse(model, &x, inertias, jv));
        quantities.push(Quantity {
            kind: QuantityKind::ForwardDynamics,
            frame: None,
            args: vec![Arg::Qd, Arg::Tau],
            shape: Shape::Vector(n),
            outputs: forward,
        });
        quantities.push(Quantity {
            kind: QuantityKind::MassMatrixInverse,
            frame: None,
            args: vec![],
            shape: Shape::Matrix(n, n),
            outputs: inverse_mass,
        });
    }
    if !functions.contains(FunctionGroup::Derivatives) {
        return (quantities, Vec::new());
    }
    let derivatives = |directions| {
        derivatives(
            model,
            directions,
            Placements::Multiplied,
            inertias,
            jv,
            [q, qd, a, tau],
        )
    };
    let (inverse_derivatives, forward_derivatives) = derivatives(Directions::OneByOne);
    let (inverse_lanes, forward_lanes) = derivatives(Directions::Lanes);
    quantities.extend([
        Quantity {
            kind: QuantityKind::InverseDynamicsDerivatives,
            frame: None,
            args: vec![Arg::Qd, Arg::A],
            shape: Shape::MatrixPair(n),
            outputs: inverse_derivatives,
        },
        Quantity {
            kind: QuantityKind::ForwardDynamicsDerivatives,
            frame: None,
            args: vec![Arg::Qd, Arg::Tau],
            shape: Shape::MatrixPair(n),
            outputs: forward_derivatives,
        },
    ]);
    let lanes = vec![
        (
            QuantityKind::InverseDynamicsDerivatives.name().to_owned(),
            inverse_lanes,
        ),
        (
            QuantityKind::ForwardDynamicsDerivatives.name().to_owned(),
            forward_lanes,
        ),
    ];
    (quantities, lanes)
}

/// The outputs of `∂τ/∂x` and `∂q̈/∂x`, their directions and transforms carried as
/// `directions` and `placements` say.
fn derivatives(
    model: &Model,
    directions: Directions,
    placements: Placements,
    inertias: &[crate::spatial::RigidInertia<Expr>],
    jv: &[crate::model::JointTermValues],
    [q, qd, a, tau]: [&[Expr]; 4],
) -> (Vec<Id>, Vec<Id>) {
    let inverse = pair_ids(dynamics::inverse_dynamics_derivatives_by(
        directions, placements, model, q, inertias, jv, qd, a,
    ));
    let forward = pair_ids(dynamics::forward_dynamics_derivatives_by(
        directions, placements, model, q, inertias, jv, qd, tau,
    ));
    (inverse, forward)
}

/// The regressor at `v = q̇`, `a = q̈` (identification's form, `Y θ = τ`), and its base columns:
/// traced last, so the earlier functions keep their node ids. The body forces take the cheaper
/// `v ×* I v` form there, so these are smaller than the Slotine–Li regressor.
fn torque_regressors(
    model: &Model,
    x: &[crate::spatial::Transform<Expr>],
    qd: &[Expr],
    a: &[Expr],
    base: &BaseParameterSet,
) -> Vec<Quantity> {
    let n = model.dof();
    let y = matrix_ids(&full_from_base(&dynamics::regressor(model, x, qd, qd, a), base));
    let y_base = base_columns(&y, base, n);
    vec![
        Quantity {
            kind: QuantityKind::TorqueRegressor,
            frame: None,
            args: vec![Arg::Qd, Arg::A],
            shape: Shape::Matrix(n, model.parameter_count()),
            outputs: y,
        },
        Quantity {
            kind: QuantityKind::BaseTorqueRegressor,
            frame: None,
            args: vec![Arg::Qd, Arg::A],
            shape: Shape::Matrix(n, base.count()),
            outputs: y_base,
        },
    ]
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

/// `(Y θ, Yᵀ r)` of the Slotine–Li regressor and `(Y_b θ_b, Y_bᵀ r)` of its base columns,
/// without forming either regressor (`dynamics::regressor_products`): what an adaptive law
/// needs each tick. Traced last, on inputs of their own, so the earlier functions keep their
/// node ids.
fn regressor_products(
    model: &Model,
    x: &[crate::spatial::Transform<Expr>],
    [qd, v, a]: [&[Expr]; 3],
    theta: &[Expr],
    r: &[Expr],
    base: &BaseParameterSet,
) -> Vec<Quantity> {
    let (n, p, b) = (model.dof(), model.parameter_count(), base.count());
    let all: Vec<usize> = (0..p).collect();
    [
        (QuantityKind::RegressorProducts, all.as_slice(), p),
        (QuantityKind::BaseRegressorProducts, &base.columns, b),
    ]
    .into_iter()
    .map(|(kind, columns, len)| {
        let (y_theta, y_tr_r) = dynamics::regressor_products(model, x, qd, v, a, columns, &theta[..len], r);
        Quantity {
            kind,
            frame: None,
            args: vec![Arg::Qd, Arg::V, Arg::A, Arg::Theta(len), Arg::R],
            shape: Shape::VectorPair(n, len),
            outputs: ids(&y_theta).into_iter().chain(ids(&y_tr_r)).collect(),
        }
    })
    .collect()
}

/// Forward kinematics, `J` and `J̇` in one function: the nodes the three share (joint
/// transforms, body poses) are computed once. No new nodes, only the union of their outputs.
fn fused_kinematics(quantities: &[Quantity], n: usize) -> Quantity {
    let outputs_of = |kind: QuantityKind| {
        quantities
            .iter()
            .find(|q| q.kind == kind)
            .map(|q| q.outputs.clone())
            .unwrap_or_default()
    };
    let mut outputs = outputs_of(QuantityKind::ForwardKinematics);
    outputs.extend(outputs_of(QuantityKind::Jacobian));
    outputs.extend(outputs_of(QuantityKind::JacobianDot));
    Quantity {
        kind: QuantityKind::Kinematics,
        frame: None,
        args: vec![Arg::Qd],
        shape: Shape::Kinematics(n),
        outputs,
    }
}

/// The pose, `J`, `J̇` in each reference frame, velocity, classical acceleration and `(pose,
/// J, J̇)` of one frame, traced after every other quantity (they add nodes, never renumber).
/// The second list holds other formulations of some of them (the local `J` carried back from
/// the frame, velocity and acceleration by the forward recursion), by function name, which
/// [`trace_functions`] keeps where they cost less.
fn frame_quantities(
    model: &Model,
    x: &[crate::spatial::Transform<Expr>],
    world: &[crate::spatial::Transform<Expr>],
    qd: &[Expr],
    qdd: &[Expr],
    index: usize,
    frame: &crate::model::Frame,
) -> (Vec<Quantity>, Vec<(String, Vec<Id>)>) {
    let motion = dynamics::FrameMotion::new(model, world, qd, frame);
    let snake = frame_identifiers(model.frames().iter().map(|f| f.name.as_str()))
        .swap_remove(index)
        .snake;
    let out = frame_motion_quantities(&motion, qd, qdd, index, &snake, model.dof());
    let frame_of = |reference| FrameOf {
        index,
        snake: snake.clone(),
        reference,
    };
    let name_of = |kind, reference| frame_of(Some(reference)).function_name(kind);
    let mut other_forms = vec![(
        name_of(QuantityKind::FrameJacobian, ReferenceFrame::Local),
        matrix_ids(&dynamics::local_jacobian(model, x, frame)),
    )];
    let rates = dynamics::FrameRates::new(model, x, qd, qdd, frame);
    for r in ReferenceFrame::ALL {
        other_forms.push((
            name_of(QuantityKind::FrameVelocity, r),
            ids(&rates.velocity_in(r, &motion.pose)),
        ));
        other_forms.push((
            name_of(QuantityKind::FrameClassicalAcceleration, r),
            ids(&rates.classical_acceleration_in(r, &motion.pose)),
        ));
    }
    (out, other_forms)
}

/// The frame quantities of one frame from its motion (`n` velocity coordinates): the pose, `J`
/// and `J̇` in each reference frame, velocity, classical acceleration, and `(pose, J, J̇)`.
pub(super) fn frame_motion_quantities(
    motion: &dynamics::FrameMotion<Expr>,
    qd: &[Expr],
    qdd: &[Expr],
    index: usize,
    snake: &str,
    n: usize,
) -> Vec<Quantity> {
    let frame_of = |reference| FrameOf {
        index,
        snake: snake.to_owned(),
        reference,
    };
    let quantity = |kind, reference, args: Vec<Arg>, shape, outputs| Quantity {
        kind,
        frame: Some(frame_of(reference)),
        args,
        shape,
        outputs,
    };
    let pose = pose_ids(&motion.pose);
    let mut out = vec![quantity(
        QuantityKind::FramePose,
        None,
        vec![],
        Shape::Pose,
        pose.clone(),
    )];
    for r in ReferenceFrame::ALL {
        let j = matrix_ids(&motion.jacobian_in(r));
        out.push(quantity(
            QuantityKind::FrameJacobian,
            Some(r),
            vec![],
            Shape::Matrix(6, n),
            j,
        ));
    }
    for r in ReferenceFrame::ALL {
        let jd = matrix_ids(&motion.jacobian_dot_in(r, qd));
        out.push(quantity(
            QuantityKind::FrameJacobianTimeVariation,
            Some(r),
            vec![Arg::Qd],
            Shape::Matrix(6, n),
            jd,
        ));
    }
    for r in ReferenceFrame::ALL {
        let v = ids(&motion.velocity_in(r, qd));
        out.push(quantity(
            QuantityKind::FrameVelocity,
            Some(r),
            vec![Arg::Qd],
            Shape::Vector(6),
            v,
        ));
    }
    for r in ReferenceFrame::ALL {
        let a = ids(&motion.classical_acceleration_in(r, qd, qdd));
        out.push(quantity(
            QuantityKind::FrameClassicalAcceleration,
            Some(r),
            vec![Arg::Qd, Arg::A],
            Shape::Vector(6),
            a,
        ));
    }
    let mut fused = pose;
    fused.extend(matrix_ids(&motion.jacobian));
    fused.extend(matrix_ids(&motion.jacobian_dot));
    out.push(quantity(
        QuantityKind::FrameKinematics,
        None,
        vec![Arg::Qd],
        Shape::Kinematics(n),
        fused,
    ));
    out
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
        ] {
            for (id, x) in ids.iter().zip(xs) {
                if let crate::symbolic::Node::Input(k) = self.graph.node(*id) {
                    values[k as usize] = *x;
                }
            }
        }
        Some(crate::symbolic::evaluate(&self.graph, &values, &quantity.outputs))
    }
}
