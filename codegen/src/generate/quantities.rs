//! The one table of generated functions: each quantity's name, its group (which a user chooses
//! it by, and whose `dyngen-runtime` trait it is a method of), whether it also has a lane form,
//! and what it takes and returns ([`QuantityKind::signature`]). The tracer records quantities by
//! these kinds, in the table's order, the emitter places each method by its group, and a test
//! holds the table to the traits of `dyngen-runtime` and to the reference in `docs/dynamics.md`.

use crate::FunctionGroup;

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
    /// The contact forces `λ`, one per contact row (`len` of them).
    Forces(usize),
    /// What the contact rows' acceleration `J a + drift` is asked to be besides its feedback
    /// terms (`len` rows; zero holds them still, Baumgarte's `−K_p e` pulls them back).
    Target(usize),
    /// One number of a contact solve, an `f64` of its own.
    Coefficient(Coefficient),
}

/// The scalar settings contact solves take, each an `f64` argument named as here.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Coefficient {
    /// Baumgarte's velocity gain `K_d`: the rows are asked for `… − K_d J q̇`.
    VelocityGain,
    /// The regularisation `μ` added to the Delassus matrix's diagonal.
    Regularisation,
    /// The damping `ε` of the operational-space inertia `(K + ε I)⁻¹`.
    Damping,
    /// An impact's restitution `r`: `J q̇⁺ = −r J q̇⁻`.
    Restitution,
}

impl Coefficient {
    pub const ALL: [Coefficient; 4] = [
        Coefficient::VelocityGain,
        Coefficient::Regularisation,
        Coefficient::Damping,
        Coefficient::Restitution,
    ];

    /// The argument's name in generated code (and of its input in the graph).
    pub fn name(self) -> &'static str {
        match self {
            Coefficient::VelocityGain => "kd",
            Coefficient::Regularisation => "mu",
            Coefficient::Damping => "damping",
            Coefficient::Restitution => "restitution",
        }
    }
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
    /// Two `rows × cols` matrices (derivatives with respect to `q` and `q̇`), each
    /// column-major.
    MatrixPair(usize, usize),
    /// A pose, then `J` and `J̇` (6 × n each, column-major): the kinematics of a control tick.
    Kinematics(usize),
    /// Two vectors, of `n` and of `m` entries (`Y θ` and `Yᵀ r`).
    VectorPair(usize, usize),
    /// `dyngen_runtime::ContactMatrices` of `n` velocity coordinates and `c` contact rows:
    /// `J` (c × n), `M⁻¹ Jᵀ` (n × c), `K` (c × c), each column-major.
    ContactMatrices(usize, usize),
    /// `dyngen_runtime::ContactSystem`: the outputs of [`Shape::ContactMatrices`], then the
    /// drift (c) and the free acceleration (n).
    ContactSystem(usize, usize),
    /// `dyngen_runtime::ContactStep` of `n` velocity coordinates and `c` rows: the
    /// acceleration (n), the forces and those of the step before (c each), the Delassus matrix
    /// (c × c), the pivots of its regularised factor (c) and the right-hand side (c).
    ContactStep(usize, usize),
    /// `dyngen_runtime::ContactInertia` of `c` rows: `(K + ε I)⁻¹` (c × c), the pivots of
    /// `K + ε I` (c) and `K`'s diagonal (c).
    ContactInertia(usize),
}

/// The sizes a function's arguments and result are written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dims {
    /// Velocity coordinates: the joints' (fixed base), or the base twist's six and the joints'.
    pub n: usize,
    /// Standard parameters.
    pub p: usize,
    /// Base parameters.
    pub b: usize,
    /// Contact rows.
    pub c: usize,
}

/// One generated function. The order of [`QuantityKind::ALL`] is the order the tracer records
/// them in, which is append-only: node ids follow creation order, so a quantity added at the end
/// leaves every earlier function's code byte-identical.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum QuantityKind {
    ForwardKinematics,
    Jacobian,
    JacobianDot,
    MassMatrix,
    CoriolisMatrix,
    Gravity,
    InverseDynamics,
    SlotineLi,
    Regressor,
    BaseRegressor,
    ForwardDynamics,
    MassMatrixInverse,
    InverseDynamicsDerivatives,
    ForwardDynamicsDerivatives,
    TorqueRegressor,
    BaseTorqueRegressor,
    Kinematics,
    RegressorProducts,
    BaseRegressorProducts,
    FramePose,
    FrameJacobian,
    FrameJacobianTimeVariation,
    FrameVelocity,
    FrameClassicalAcceleration,
    FrameKinematics,
    CenterOfMass,
    CentroidalMomentumMatrix,
    CentroidalBias,
    ContactJacobian,
    ContactDrift,
    ContactResponse,
    ContactForwardDynamicsDerivatives,
    ContactAccelerationDerivatives,
    ContactDelassus,
    ContactMatrices,
    ContactSystem,
    ContactSolve,
    ContactProximalSolve,
    ContactImpulse,
    ContactForwardDynamics,
    ContactInertia,
}

/// A row of the table.
#[derive(Clone, Copy, Debug)]
struct Row {
    name: &'static str,
    group: FunctionGroup,
    lane_form: bool,
}

impl QuantityKind {
    /// Every kind, in trace order.
    pub const ALL: [QuantityKind; 25] = [
        QuantityKind::ForwardKinematics,
        QuantityKind::Jacobian,
        QuantityKind::JacobianDot,
        QuantityKind::MassMatrix,
        QuantityKind::CoriolisMatrix,
        QuantityKind::Gravity,
        QuantityKind::InverseDynamics,
        QuantityKind::SlotineLi,
        QuantityKind::Regressor,
        QuantityKind::BaseRegressor,
        QuantityKind::ForwardDynamics,
        QuantityKind::MassMatrixInverse,
        QuantityKind::InverseDynamicsDerivatives,
        QuantityKind::ForwardDynamicsDerivatives,
        QuantityKind::TorqueRegressor,
        QuantityKind::BaseTorqueRegressor,
        QuantityKind::Kinematics,
        QuantityKind::RegressorProducts,
        QuantityKind::BaseRegressorProducts,
        QuantityKind::FramePose,
        QuantityKind::FrameJacobian,
        QuantityKind::FrameJacobianTimeVariation,
        QuantityKind::FrameVelocity,
        QuantityKind::FrameClassicalAcceleration,
        QuantityKind::FrameKinematics,
    ];

    /// The kinds only a floating-base robot has (`FloatingBaseDynamics`), traced after the ones
    /// of [`QuantityKind::ALL`] it shares with fixed-base robots.
    pub const FLOATING_ONLY: [QuantityKind; 3] = [
        QuantityKind::CenterOfMass,
        QuantityKind::CentroidalMomentumMatrix,
        QuantityKind::CentroidalBias,
    ];

    /// The kinds of a robot with contacts (`ContactDynamics`), traced after every other.
    pub const CONTACTS: [QuantityKind; 13] = [
        QuantityKind::ContactJacobian,
        QuantityKind::ContactDrift,
        QuantityKind::ContactResponse,
        QuantityKind::ContactForwardDynamicsDerivatives,
        QuantityKind::ContactAccelerationDerivatives,
        QuantityKind::ContactDelassus,
        QuantityKind::ContactMatrices,
        QuantityKind::ContactSystem,
        QuantityKind::ContactSolve,
        QuantityKind::ContactProximalSolve,
        QuantityKind::ContactImpulse,
        QuantityKind::ContactForwardDynamics,
        QuantityKind::ContactInertia,
    ];

    fn row(self) -> Row {
        use FunctionGroup as G;
        let row = |name, group, lane_form| Row {
            name,
            group,
            lane_form,
        };
        match self {
            QuantityKind::ForwardKinematics => row("forward_kinematics", G::Kinematics, false),
            QuantityKind::Jacobian => row("jacobian", G::Kinematics, false),
            QuantityKind::JacobianDot => row("jacobian_dot", G::Kinematics, false),
            QuantityKind::MassMatrix => row("mass_matrix", G::Dynamics, false),
            QuantityKind::CoriolisMatrix => row("coriolis_matrix", G::Dynamics, false),
            QuantityKind::Gravity => row("gravity", G::Dynamics, false),
            QuantityKind::InverseDynamics => row("inverse_dynamics", G::Dynamics, true),
            QuantityKind::SlotineLi => row("slotine_li", G::Dynamics, false),
            QuantityKind::Regressor => row("regressor", G::Regressors, false),
            QuantityKind::BaseRegressor => row("base_regressor", G::BaseParameters, false),
            QuantityKind::ForwardDynamics => row("forward_dynamics", G::ForwardDynamics, false),
            QuantityKind::MassMatrixInverse => row("mass_matrix_inverse", G::ForwardDynamics, false),
            QuantityKind::InverseDynamicsDerivatives => {
                row("inverse_dynamics_derivatives", G::Derivatives, false)
            }
            QuantityKind::ForwardDynamicsDerivatives => {
                row("forward_dynamics_derivatives", G::Derivatives, false)
            }
            QuantityKind::TorqueRegressor => row("torque_regressor", G::Regressors, false),
            QuantityKind::BaseTorqueRegressor => row("base_torque_regressor", G::BaseParameters, true),
            QuantityKind::Kinematics => row("kinematics", G::Kinematics, false),
            QuantityKind::RegressorProducts => row("regressor_products", G::Regressors, false),
            QuantityKind::BaseRegressorProducts => row("base_regressor_products", G::BaseParameters, false),
            QuantityKind::FramePose => row("frame_pose", G::Frames, false),
            QuantityKind::FrameJacobian => row("frame_jacobian", G::Frames, false),
            QuantityKind::FrameJacobianTimeVariation => {
                row("frame_jacobian_time_variation", G::Frames, false)
            }
            QuantityKind::FrameVelocity => row("frame_velocity", G::Frames, false),
            QuantityKind::FrameClassicalAcceleration => row("frame_classical_acceleration", G::Frames, false),
            QuantityKind::FrameKinematics => row("frame_kinematics", G::Frames, false),
            QuantityKind::CenterOfMass => row("center_of_mass", G::Dynamics, false),
            QuantityKind::CentroidalMomentumMatrix => row("centroidal_momentum_matrix", G::Dynamics, false),
            QuantityKind::CentroidalBias => row("centroidal_bias", G::Dynamics, false),
            QuantityKind::ContactJacobian => row("contact_jacobian", G::Contacts, false),
            QuantityKind::ContactDrift => row("contact_drift", G::Contacts, false),
            QuantityKind::ContactResponse => row("contact_response", G::Contacts, false),
            QuantityKind::ContactForwardDynamicsDerivatives => {
                row("contact_forward_dynamics_derivatives", G::Contacts, false)
            }
            QuantityKind::ContactAccelerationDerivatives => {
                row("contact_acceleration_derivatives", G::Contacts, false)
            }
            QuantityKind::ContactDelassus => row("contact_delassus", G::Contacts, false),
            QuantityKind::ContactMatrices => row("contact_matrices", G::Contacts, false),
            QuantityKind::ContactSystem => row("contact_system", G::Contacts, false),
            QuantityKind::ContactSolve => row("contact_solve", G::Contacts, false),
            QuantityKind::ContactProximalSolve => row("contact_proximal_solve", G::Contacts, false),
            QuantityKind::ContactImpulse => row("contact_impulse", G::Contacts, false),
            QuantityKind::ContactForwardDynamics => row("contact_forward_dynamics", G::Contacts, false),
            QuantityKind::ContactInertia => row("contact_inertia", G::Contacts, false),
        }
    }

    /// The generated function's name, e.g. `mass_matrix`.
    pub fn name(self) -> &'static str {
        self.row().name
    }

    /// The kind named `name`, if any.
    pub fn from_name(name: &str) -> Option<QuantityKind> {
        QuantityKind::ALL
            .into_iter()
            .chain(QuantityKind::FLOATING_ONLY)
            .chain(QuantityKind::CONTACTS)
            .find(|k| k.name() == name)
    }

    /// The group a user chooses it by; its trait is the group's.
    pub fn group(self) -> FunctionGroup {
        self.row().group
    }

    /// Whether it also comes in lane form (`<name>_lanes`, several states per call, a method
    /// of `dyngen_runtime::LaneDynamics`): what identification and batched roll-outs evaluate
    /// in bulk.
    pub fn has_lane_form(self) -> bool {
        self.row().lane_form
    }

    /// Whether it is computed once per named frame (the group `frames`): one function per frame
    /// (and reference frame), chosen by the trait method with a `match`.
    pub fn is_per_frame(self) -> bool {
        self.group() == FunctionGroup::Frames
    }

    /// Whether it can be written composed (`code_shape: composed`): computed from the robot's
    /// smaller generated functions through the tree factor of `D`, in loops of the runtime,
    /// instead of as straight-line code of its own. Its inputs: `D`, inverse dynamics and its
    /// derivatives, of the group `dynamics` (always generated) or of its own group.
    pub fn has_composed_form(self) -> bool {
        matches!(
            self,
            QuantityKind::ForwardDynamics
                | QuantityKind::MassMatrixInverse
                | QuantityKind::ForwardDynamicsDerivatives
        )
    }

    /// Whether its trait has a `_into` form that writes into a `ResultBuffer` kept between
    /// calls: the matrices whose entries are largely zero in every state, or whose size makes a
    /// fill and a copy per call worth saving.
    pub fn has_into_form(self) -> bool {
        matches!(
            self,
            QuantityKind::MassMatrix
                | QuantityKind::CoriolisMatrix
                | QuantityKind::Regressor
                | QuantityKind::TorqueRegressor
                | QuantityKind::BaseRegressor
                | QuantityKind::BaseTorqueRegressor
                | QuantityKind::MassMatrixInverse
                | QuantityKind::InverseDynamicsDerivatives
                | QuantityKind::ForwardDynamicsDerivatives
        )
    }

    /// Whether it is one of the base-parameter columns of a regressor (its doc names them).
    pub fn uses_base_columns(self) -> bool {
        self.group() == FunctionGroup::BaseParameters
    }

    /// Whether a per-frame function also comes once per reference frame
    /// (`frame_jacobian_tool0_local`): all but the pose and `(pose, J, J̇)`.
    pub fn has_reference_frame(self) -> bool {
        self.is_per_frame() && !matches!(self, QuantityKind::FramePose | QuantityKind::FrameKinematics)
    }

    /// What it computes, in one sentence with its units and conventions: the documentation of
    /// interfaces that do not see the runtime's traits (the C library's header). Velocities
    /// are written `q̇`; on a floating base that is `ν` (the base twist, then the joint rates).
    pub fn summary(self) -> &'static str {
        use QuantityKind as K;
        match self {
            K::ForwardKinematics => {
                "the end-effector frame's pose in the base frame (the world, for a floating \
                 base): its axes as the rotation's columns, its origin as the translation (m)"
            }
            K::Jacobian => {
                "the end-effector's geometric Jacobian J(q): its velocity [linear (m/s); angular \
                 (rad/s)] is J q̇, in base axes at the frame's origin (LOCAL_WORLD_ALIGNED)"
            }
            K::JacobianDot => "J̇(q, q̇), the time derivative of the end-effector's Jacobian along q̇",
            K::MassMatrix => {
                "the mass matrix D(q), symmetric positive definite (kg·m², kg·m or kg as the \
                 coordinates are angles or lengths)"
            }
            K::CoriolisMatrix => {
                "the Coriolis matrix C(q, q̇): C q̇ are the Coriolis and centrifugal forces, and \
                 Ḋ = C + Cᵀ (Christoffel-consistent on a fixed base)"
            }
            K::Gravity => "the generalised gravity g(q): the forces (N·m or N) that hold the robot still",
            K::InverseDynamics => {
                "inverse dynamics τ = D(q) q̈ + C(q, q̇) q̇ + g(q) (N·m or N; on a floating base \
                 the base wrench first)"
            }
            K::SlotineLi => {
                "the Slotine–Li torque D(q) a + C(q, q̇) v + g(q) at the reference velocity v \
                 and acceleration a"
            }
            K::Regressor => {
                "the Slotine–Li regressor Y(q, q̇, v, a), one column per standard parameter: \
                 Y θ = D a + C v + g"
            }
            K::BaseRegressor => {
                "the base-parameter regressor Y_b(q, q̇, v, a), one column per base parameter: \
                 Y_b θ_b = D a + C v + g"
            }
            K::ForwardDynamics => "forward dynamics q̈ = D⁻¹ (τ − C q̇ − g) (m/s² or rad/s²)",
            K::MassMatrixInverse => "the inverse mass matrix D(q)⁻¹",
            K::InverseDynamicsDerivatives => {
                "the derivatives ∂τ/∂q and ∂τ/∂q̇ of inverse dynamics at (q, q̇, q̈); entry (i, \
                 j) is ∂τ_i/∂x_j (∂τ/∂q̈ is D); on a floating base with respect to q in its \
                 tangent space"
            }
            K::ForwardDynamicsDerivatives => {
                "the derivatives ∂q̈/∂q and ∂q̈/∂q̇ of forward dynamics at (q, q̇, τ) (∂q̈/∂τ \
                 is D⁻¹); on a floating base with respect to q in its tangent space"
            }
            K::TorqueRegressor => {
                "the regressor in torque form Y(q, q̇, q̇, q̈): Y θ = τ, what identification stacks"
            }
            K::BaseTorqueRegressor => "the base regressor in torque form Y_b(q, q̇, q̇, q̈): Y_b θ_b = τ",
            K::Kinematics => "the end-effector's pose, J and J̇ at once, computing what they share once",
            K::RegressorProducts => {
                "(Y θ, Yᵀ r) with Y = Y(q, q̇, v, a), computed without forming Y: an adaptive \
                 law's torque and adaptation"
            }
            K::BaseRegressorProducts => {
                "(Y_b θ_b, Y_bᵀ r) with Y_b = Y_b(q, q̇, v, a), computed without forming Y_b"
            }
            K::FramePose => {
                "a named frame's pose in the base frame (the world, for a floating base): its \
                 axes as the rotation's columns, its origin as the translation (m)"
            }
            K::FrameJacobian => {
                "a named frame's geometric Jacobian J(q): its velocity [linear (m/s); angular \
                 (rad/s)] is J q̇"
            }
            K::FrameJacobianTimeVariation => "J̇(q, q̇), the time derivative of the frame's Jacobian along q̇",
            K::FrameVelocity => "the frame's velocity J q̇, [linear (m/s); angular (rad/s)]",
            K::FrameClassicalAcceleration => {
                "the frame's classical acceleration J q̈ + J̇ q̇ with ω × v added to its linear \
                 part: in LOCAL_WORLD_ALIGNED the acceleration of its origin (m/s²) and the \
                 angular acceleration (rad/s²)"
            }
            K::FrameKinematics => {
                "a frame's pose, J and J̇ (LOCAL_WORLD_ALIGNED) at once, computing what they \
                 share once"
            }
            K::CenterOfMass => "the centre of mass of the whole robot, in the world (m)",
            K::CentroidalMomentumMatrix => {
                "the centroidal momentum matrix A_g(q): A_g ν is the linear momentum and the \
                 angular momentum about the centre of mass, in world axes"
            }
            K::CentroidalBias => "Ȧ_g(q, ν) ν, the rate of the centroidal momentum at zero acceleration",
            K::ContactJacobian => {
                "the contacts' rows J(q), stacked in the order the contacts are listed: a point's \
                 three (its origin's velocity), a frame's six (its twist, linear first), each in \
                 the axes its contact is written in (LOCAL or LOCAL_WORLD_ALIGNED); a loop's \
                 rows are the motion relative to the frame it is held to"
            }
            K::ContactDrift => {
                "the rows' drift J a at a = 0 along q̇: a point's classical acceleration, a \
                 frame's spatial one; held contacts have J q̈ = −drift"
            }
            K::ContactResponse => {
                "D⁻¹ Jᵀ: how the robot accelerates under a unit force in each contact row \
                 (column k: q̈ from the force of row k)"
            }
            K::ContactForwardDynamicsDerivatives => {
                "the derivatives ∂q̈/∂q and ∂q̈/∂q̇ of forward dynamics with the contact forces λ \
                 held, at the acceleration q̈ they give: −D⁻¹ ∂(τ_ID(q, q̇, q̈) − Jᵀ λ)/∂x; on a \
                 floating base with respect to q in its tangent space"
            }
            K::ContactAccelerationDerivatives => {
                "the derivatives ∂/∂q and ∂/∂q̇ of the contact rows' acceleration J q̈ + drift \
                 with q̈ held (contact rows × velocity coordinates each); on a floating base with \
                 respect to q in its tangent space"
            }
            K::ContactDelassus => {
                "the Delassus matrix J D⁻¹ Jᵀ, symmetric: how each contact row accelerates under a \
                 unit force in each row; its inverse is the rows' operational-space inertia"
            }
            K::ContactMatrices => {
                "J, D⁻¹ Jᵀ and the Delassus matrix J D⁻¹ Jᵀ at once, sharing the kinematics and \
                 the factored mass matrix: what an impact's solve reads"
            }
            K::ContactSystem => {
                "J, D⁻¹ Jᵀ, the Delassus matrix, the drift along q̇ and forward dynamics without \
                 contacts at once, factoring the mass matrix once: what a constrained solve reads"
            }
            K::ContactSolve => {
                "constrained forward dynamics in one call, one proximal step from the forces λ₀ \
                 (zero for the exact solve): λ₁ = (K + μ I)⁻¹ (rhs + μ λ₀) with rhs = target − \
                 drift − kd J q̇ − J D⁻¹ (τ − b), and the acceleration D⁻¹ (τ − b + Jᵀ λ₁), with \
                 the Delassus matrix K, the pivots of K + μ I (one at rounding level: redundant \
                 rows) and rhs, from which the runtime checks and refines the solve"
            }
            K::ContactProximalSolve => {
                "contact_solve with four proximal steps, untested between them: what a \
                 regularised solve (μ > 0) converges in, most often"
            }
            K::ContactImpulse => {
                "an impact in one call: the impulses λ = (K + μ I)⁻¹ rhs with rhs = −(1 + r) J q̇, \
                 and the velocity after, q̇ + D⁻¹ Jᵀ λ, with K, the pivots of K + μ I and rhs"
            }
            K::ContactForwardDynamics => {
                "forward dynamics with the contact forces λ applied: D⁻¹ (τ − b + Jᵀ λ)"
            }
            K::ContactInertia => {
                "the rows' operational-space inertia (K + ε I)⁻¹, K the Delassus matrix, with the \
                 pivots of K + ε I and K's diagonal (a pivot at rounding level against it: \
                 redundant rows)"
            }
        }
    }

    /// The vectors it takes besides the configuration, and what it returns, in the sizes `d`
    /// (`θ`: the base parameters for a function of base columns, else all of them).
    pub fn signature(self, d: Dims) -> (Vec<Arg>, Shape) {
        use Arg::{Forces, Qd, Tau, A, R, V};
        use Coefficient::{Damping, Regularisation, Restitution, VelocityGain};
        let coefficient = Arg::Coefficient;
        use QuantityKind as K;
        let n = d.n;
        let (theta, p) = match self.uses_base_columns() {
            true => (Arg::Theta(d.b), d.b),
            false => (Arg::Theta(d.p), d.p),
        };
        match self {
            K::ForwardKinematics | K::FramePose => (vec![], Shape::Pose),
            K::Jacobian | K::FrameJacobian | K::CentroidalMomentumMatrix => (vec![], Shape::Matrix(6, n)),
            K::JacobianDot | K::FrameJacobianTimeVariation => (vec![Qd], Shape::Matrix(6, n)),
            K::MassMatrix | K::MassMatrixInverse => (vec![], Shape::Matrix(n, n)),
            K::CoriolisMatrix => (vec![Qd], Shape::Matrix(n, n)),
            K::Gravity => (vec![], Shape::Vector(n)),
            K::InverseDynamics => (vec![Qd, A], Shape::Vector(n)),
            K::SlotineLi => (vec![Qd, V, A], Shape::Vector(n)),
            K::Regressor | K::BaseRegressor => (vec![Qd, V, A], Shape::Matrix(n, p)),
            K::TorqueRegressor | K::BaseTorqueRegressor => (vec![Qd, A], Shape::Matrix(n, p)),
            K::RegressorProducts | K::BaseRegressorProducts => {
                (vec![Qd, V, A, theta, R], Shape::VectorPair(n, p))
            }
            K::ForwardDynamics => (vec![Qd, Tau], Shape::Vector(n)),
            K::InverseDynamicsDerivatives => (vec![Qd, A], Shape::MatrixPair(n, n)),
            K::ForwardDynamicsDerivatives => (vec![Qd, Tau], Shape::MatrixPair(n, n)),
            K::Kinematics | K::FrameKinematics => (vec![Qd], Shape::Kinematics(n)),
            K::FrameVelocity => (vec![Qd], Shape::Vector(6)),
            K::FrameClassicalAcceleration => (vec![Qd, A], Shape::Vector(6)),
            K::CenterOfMass => (vec![], Shape::Vector(3)),
            K::CentroidalBias => (vec![Qd], Shape::Vector(6)),
            K::ContactJacobian => (vec![], Shape::Matrix(d.c, n)),
            K::ContactDrift => (vec![Qd], Shape::Vector(d.c)),
            K::ContactResponse => (vec![], Shape::Matrix(n, d.c)),
            K::ContactForwardDynamicsDerivatives => (vec![Qd, A, Forces(d.c)], Shape::MatrixPair(n, n)),
            K::ContactAccelerationDerivatives => (vec![Qd, A], Shape::MatrixPair(d.c, n)),
            K::ContactDelassus => (vec![], Shape::Matrix(d.c, d.c)),
            K::ContactMatrices => (vec![], Shape::ContactMatrices(n, d.c)),
            K::ContactSystem => (vec![Qd, Tau], Shape::ContactSystem(n, d.c)),
            K::ContactSolve | K::ContactProximalSolve => (
                vec![
                    Qd,
                    Tau,
                    Arg::Target(d.c),
                    Forces(d.c),
                    coefficient(VelocityGain),
                    coefficient(Regularisation),
                ],
                Shape::ContactStep(n, d.c),
            ),
            K::ContactImpulse => (
                vec![Qd, coefficient(Restitution), coefficient(Regularisation)],
                Shape::ContactStep(n, d.c),
            ),
            K::ContactForwardDynamics => (vec![Qd, Tau, Forces(d.c)], Shape::Vector(n)),
            K::ContactInertia => (vec![coefficient(Damping)], Shape::ContactInertia(d.c)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn names_are_distinct_snake_case_and_round_trip() {
        let mut seen = HashSet::new();
        for kind in QuantityKind::ALL {
            let name = kind.name();
            assert!(seen.insert(name), "{name} twice");
            assert!(
                name.chars().all(|c| c.is_ascii_lowercase() || c == '_') && !name.starts_with('_'),
                "{name} is not a snake_case function name"
            );
            assert_eq!(QuantityKind::from_name(name), Some(kind));
        }
        assert_eq!(QuantityKind::from_name("mass_matrix_lanes"), None);
    }

    #[test]
    fn the_per_frame_rows_come_last() {
        // The tracer traces them frame by frame after every other row of `ALL`.
        let first = QuantityKind::ALL.iter().position(|k| k.is_per_frame());
        let first = first.expect("per-frame rows");
        assert!(QuantityKind::ALL[first..].iter().all(|k| k.is_per_frame()));
    }

    #[test]
    fn every_group_has_a_function() {
        for group in FunctionGroup::ALL {
            assert!(
                (QuantityKind::ALL.iter().chain(&QuantityKind::CONTACTS)).any(|k| k.group() == group),
                "{group:?} empty"
            );
        }
    }
}
