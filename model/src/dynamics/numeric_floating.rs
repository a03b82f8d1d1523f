//! The floating-base algorithms instantiated with `f64`: dyngen's reference dynamics of a robot
//! on a free-flying base, in Pinocchio's configuration and velocity layout. Mimic joints and
//! joint-level terms mean what they mean on a fixed base (`NumericDynamics`), on the joint rows.

use super::floating::{self, FloatingBase};
use super::frames::FrameMotion;
use super::joint_terms::{add_armature_after, with_joint_term_torques};
use super::{body_inertias, joint_term_values, joint_transforms};
use crate::model::{JointTermValues, Model};
use crate::spatial::{Mat3, RigidInertia, Transform, Vec3};
use dyngen_runtime::PARAMETERS_PER_BODY;
use dyngen_runtime::{BasePose, NonUnitQuaternion, ReferenceFrame};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3, Vector6};

/// Numeric dynamics of a floating-base model ([`Model::floating_base`]). Configurations are
/// `q = [x, y, z, qx, qy, qz, qw, q_joints…]` (`nq = dof + 7`), velocities
/// `ν = [v; ω; q̇]` with the base twist in the base frame (`nv = dof + 6`); the first six
/// entries of a generalised force are the base wrench `[f; n]` in the base frame. With mimic
/// joints `q` and `q̇` are the coordinates' (`dof` of them), as on a fixed base.
#[derive(Clone, Debug)]
pub struct FloatingDynamics<'m> {
    pub model: &'m Model,
    pub(super) base_inertia: RigidInertia<f64>,
    pub(super) inertias: Vec<RigidInertia<f64>>,
    /// Joint-level values that act (chosen kinds; others 0).
    pub(super) joint_values: Vec<JointTermValues>,
}

/// One configuration, checked (a unit quaternion) and with its joint transforms computed once
/// for every quantity asked of it ([`FloatingDynamics::state`]).
#[derive(Clone, Debug)]
pub struct FloatingState {
    base: BasePose,
    pub(super) pose: Transform<f64>,
    pub(super) transforms: Vec<Transform<f64>>,
    world: Vec<Transform<f64>>,
    /// The joints' coordinates (`q[7..]`).
    pub(super) joints: Vec<f64>,
}

impl FloatingState {
    /// The base pose.
    pub fn base(&self) -> &BasePose {
        &self.base
    }
}

fn to_matrix3(m: &Mat3<f64>) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| m.0[i][j])
}

impl<'m> FloatingDynamics<'m> {
    /// The dynamics of `model`, `None` if its base is fixed.
    pub fn new(model: &'m Model) -> Option<Self> {
        let base = model.floating_base()?;
        Some(FloatingDynamics {
            model,
            base_inertia: RigidInertia::from_parameters(&base.inertia.parameters()),
            inertias: body_inertias(model),
            joint_values: joint_term_values(model),
        })
    }

    /// The number of standard parameters: the base body's ten, then the model's
    /// ([`Model::parameter_count`]: ten per body, then the joint-level ones).
    pub fn parameter_count(model: &Model) -> usize {
        PARAMETERS_PER_BODY + model.parameter_count()
    }

    /// The same robot with the parameters `θ`: the base body's ten first, then ten per body in
    /// joint order, then the joint-level ones (the columns of [`FloatingDynamics::regressor`]).
    pub fn with_parameters(model: &'m Model, theta: &[f64]) -> Option<Self> {
        let mut dynamics = FloatingDynamics::new(model)?;
        assert_eq!(
            theta.len(),
            Self::parameter_count(model),
            "θ has the wrong length"
        );
        let inertial = PARAMETERS_PER_BODY + model.inertial_parameter_count();
        let mut bodies = super::inertias_from_parameters(&theta[..inertial]);
        dynamics.inertias = bodies.split_off(1);
        dynamics.base_inertia = bodies[0];
        dynamics.joint_values = model.joint_term_values_from(&theta[PARAMETERS_PER_BODY..]);
        Some(dynamics)
    }

    /// The standard parameters these dynamics use: the base body's ten, then ten per body in
    /// joint order, then the joint-level ones (the model's, or those given to
    /// [`FloatingDynamics::with_parameters`]).
    pub fn parameters(&self) -> Vec<f64> {
        let mut theta: Vec<f64> = std::iter::once(&self.base_inertia)
            .chain(&self.inertias)
            .flat_map(|i| {
                [
                    i.m, i.h.0[0], i.h.0[1], i.h.0[2], i.i[0], i.i[1], i.i[2], i.i[3], i.i[4], i.i[5],
                ]
            })
            .collect();
        for values in self.joint_values.iter().take(self.model.joints().len()) {
            theta.extend(self.model.joint_terms().kinds.iter().map(|&k| values.get(k)));
        }
        theta
    }

    /// Names of the entries of [`FloatingDynamics::parameters`], e.g. `"mcx[trunk]"`,
    /// `"fv[knee]"`.
    pub fn parameter_names(model: &Model) -> Vec<String> {
        let base = &model.floating_base().expect("a floating model").name;
        let mut names: Vec<String> = dyngen_runtime::BODY_PARAMETER_NAMES
            .iter()
            .map(|p| format!("{p}[{base}]"))
            .collect();
        names.extend(model.parameter_names());
        names
    }

    /// The configuration `q` (length nq), checked.
    pub fn state(&self, q: &[f64]) -> Result<FloatingState, NonUnitQuaternion> {
        assert_eq!(q.len(), self.model.nq(), "q has the wrong length");
        let base = BasePose::from_configuration(q)?;
        let pose = Transform {
            rot: Mat3(std::array::from_fn(|i| {
                std::array::from_fn(|j| base.rotation[(i, j)])
            })),
            pos: Vec3(base.position.into()),
        };
        let transforms = joint_transforms(self.model, &q[7..]);
        let world = floating::floating_body_poses(self.model, &pose, &transforms);
        Ok(FloatingState {
            base,
            pose,
            transforms,
            world,
            joints: q[7..].to_vec(),
        })
    }

    pub(super) fn base(&self, s: &FloatingState) -> FloatingBase<f64> {
        FloatingBase {
            pose: s.pose,
            inertia: self.base_inertia,
        }
    }

    /// `(∂τ/∂q, ∂τ/∂ν)` of inverse dynamics at `(q, ν, ν̇ = a)`, `q` moved in the tangent space
    /// (`q ⊕ δ`, nv columns; the base translation's three are zero: nothing but gravity sees
    /// the base, and it sees only its orientation), by forward-mode dual numbers in lanes.
    pub fn inverse_dynamics_derivatives(
        &self,
        s: &FloatingState,
        v: &[f64],
        a: &[f64],
    ) -> (DMatrix<f64>, DMatrix<f64>) {
        self.check_velocity(v);
        self.check_velocity(a);
        floating::floating_inverse_dynamics_derivatives(
            self.model,
            &self.base(s),
            &s.joints,
            &self.inertias,
            &self.joint_values,
            v,
            a,
        )
    }

    /// `(∂ν̇/∂q, ∂ν̇/∂ν)` of forward dynamics at `(q, ν, τ)`: `−D⁻¹ ∂τ/∂x` at `ν̇ = FD(q, ν, τ)`
    /// (`∂ν̇/∂τ = D⁻¹`).
    pub fn forward_dynamics_derivatives(
        &self,
        s: &FloatingState,
        v: &[f64],
        tau: &[f64],
    ) -> (DMatrix<f64>, DMatrix<f64>) {
        self.check_velocity(v);
        self.check_velocity(tau);
        floating::floating_forward_dynamics_derivatives(
            self.model,
            &self.base(s),
            &s.joints,
            &self.inertias,
            &self.joint_values,
            v,
            tau,
        )
    }

    fn check_velocity(&self, v: &[f64]) {
        assert_eq!(
            v.len(),
            self.model.nv(),
            "a velocity or acceleration has the wrong length"
        );
    }

    /// `D(q)` (nv × nv), with the armature on the joints' diagonal when the model has that
    /// column.
    pub fn mass_matrix(&self, s: &FloatingState) -> DMatrix<f64> {
        let mut d =
            floating::floating_mass_matrix(self.model, &self.base_inertia, &s.transforms, &self.inertias);
        add_armature_after(self.model, &self.joint_values, &mut d, 6);
        d
    }

    /// The Coriolis matrix `C(q, ν)`, with `Ḋ = C + Cᵀ`.
    pub fn coriolis_matrix(&self, s: &FloatingState, v: &[f64]) -> DMatrix<f64> {
        self.check_velocity(v);
        floating::floating_coriolis_matrix(self.model, &self.base(s), &s.transforms, &self.inertias, v)
    }

    /// The generalised gravity `g(q)`.
    pub fn gravity(&self, s: &FloatingState) -> DVector<f64> {
        DVector::from_vec(floating::floating_gravity(
            self.model,
            &self.base(s),
            &s.transforms,
            &self.inertias,
        ))
    }

    /// Inverse dynamics: the base wrench and joint torques that give `a = ν̇` at `(q, ν)`,
    /// joint-level terms included.
    pub fn inverse_dynamics(&self, s: &FloatingState, v: &[f64], a: &[f64]) -> DVector<f64> {
        self.check_velocity(v);
        self.check_velocity(a);
        let rigid = floating::floating_inverse_dynamics(
            self.model,
            &self.base(s),
            &s.transforms,
            &self.inertias,
            v,
            a,
        );
        let joints = (&v[6..], &v[6..], &a[6..]);
        DVector::from_vec(with_joint_term_torques(
            self.model,
            &self.joint_values,
            rigid,
            6,
            joints,
        ))
    }

    /// The Slotine–Li form `D a_r + C(q, ν) v_r + g` plus the joint-level terms.
    pub fn slotine_li(&self, s: &FloatingState, v: &[f64], vr: &[f64], ar: &[f64]) -> DVector<f64> {
        for x in [v, vr, ar] {
            self.check_velocity(x);
        }
        let g = super::slotine_li::gravity_vector(self.model);
        let (base, x) = (self.base(s), &s.transforms);
        let rigid = floating::floating_slotine_li(self.model, &base, x, &self.inertias, v, vr, ar, Some(g));
        let joints = (&v[6..], &vr[6..], &ar[6..]);
        DVector::from_vec(with_joint_term_torques(
            self.model,
            &self.joint_values,
            rigid,
            6,
            joints,
        ))
    }

    /// The regressor `Y` with `Y θ` the Slotine–Li torque ([`FloatingDynamics::parameters`]).
    pub fn regressor(&self, s: &FloatingState, v: &[f64], vr: &[f64], ar: &[f64]) -> DMatrix<f64> {
        for x in [v, vr, ar] {
            self.check_velocity(x);
        }
        floating::floating_regressor(self.model, &s.pose.rot, &s.transforms, v, vr, ar)
    }

    /// Forward dynamics `ν̇` under the base wrench and joint torques `tau`.
    pub fn forward_dynamics(&self, s: &FloatingState, v: &[f64], tau: &[f64]) -> DVector<f64> {
        self.check_velocity(v);
        self.check_velocity(tau);
        DVector::from_vec(floating::floating_forward_dynamics(
            self.model,
            &self.base(s),
            &s.transforms,
            &self.inertias,
            &self.joint_values,
            v,
            tau,
        ))
    }

    /// `D(q)⁻¹`.
    pub fn mass_matrix_inverse(&self, s: &FloatingState) -> DMatrix<f64> {
        let (base, x) = (self.base(s), &s.transforms);
        floating::floating_mass_matrix_inverse(self.model, &base, x, &self.inertias, &self.joint_values)
    }

    pub(super) fn frame_motion(&self, s: &FloatingState, v: &[f64], frame: usize) -> FrameMotion<f64> {
        let frame = &self.model.frames()[frame];
        FrameMotion {
            pose: super::kinematics::frame_pose(Some(&s.pose), &s.world, frame),
            jacobian: floating::floating_frame_jacobian(self.model, &s.pose, &s.world, frame),
            jacobian_dot: floating::floating_frame_jacobian_dot(self.model, &s.pose, &s.world, v, frame),
        }
    }

    /// The pose of frame `frame` (an index into [`Model::frames`]) in the world.
    pub fn frame_pose(&self, s: &FloatingState, frame: usize) -> (Matrix3<f64>, Vector3<f64>) {
        let pose = super::kinematics::frame_pose(Some(&s.pose), &s.world, &self.model.frames()[frame]);
        (to_matrix3(&pose.rot), Vector3::from(pose.pos.0))
    }

    /// The Jacobian (6 × nv) of frame `frame` in `reference`.
    pub fn frame_jacobian(&self, s: &FloatingState, frame: usize, reference: ReferenceFrame) -> DMatrix<f64> {
        let frame = &self.model.frames()[frame];
        let jacobian = floating::floating_frame_jacobian(self.model, &s.pose, &s.world, frame);
        // `J` in a reference frame needs only the pose and `J`; no `J̇` is computed for it.
        FrameMotion {
            pose: super::kinematics::frame_pose(Some(&s.pose), &s.world, frame),
            jacobian_dot: DMatrix::zeros(6, jacobian.ncols()),
            jacobian,
        }
        .jacobian_in(reference)
    }

    /// `J̇` of frame `frame` in `reference` along `ν`.
    pub fn frame_jacobian_time_variation(
        &self,
        s: &FloatingState,
        v: &[f64],
        frame: usize,
        reference: ReferenceFrame,
    ) -> DMatrix<f64> {
        self.check_velocity(v);
        self.frame_motion(s, v, frame).jacobian_dot_in(reference, v)
    }

    /// The frame's velocity `J ν` in `reference`, `[linear; angular]`.
    pub fn frame_velocity(
        &self,
        s: &FloatingState,
        v: &[f64],
        frame: usize,
        reference: ReferenceFrame,
    ) -> Vector6<f64> {
        self.check_velocity(v);
        Vector6::from(self.frame_motion(s, v, frame).velocity_in(reference, v))
    }

    /// The frame's classical acceleration at `ν̇ = a` in `reference`, `[linear; angular]`.
    pub fn frame_classical_acceleration(
        &self,
        s: &FloatingState,
        v: &[f64],
        a: &[f64],
        frame: usize,
        reference: ReferenceFrame,
    ) -> Vector6<f64> {
        self.check_velocity(v);
        self.check_velocity(a);
        Vector6::from(
            self.frame_motion(s, v, frame)
                .classical_acceleration_in(reference, v, a),
        )
    }

    /// Total mass, centre of mass (world) and the centroidal momentum matrix `A_g` (6 × nv).
    pub fn centroidal_momentum_matrix(&self, s: &FloatingState) -> (f64, Vector3<f64>, DMatrix<f64>) {
        let c =
            floating::centroidal_momentum_matrix(self.model, &self.base(s), &s.transforms, &self.inertias);
        (c.mass, Vector3::from(c.com.0), c.matrix)
    }

    /// The centre of mass in the world.
    pub fn center_of_mass(&self, s: &FloatingState) -> Vector3<f64> {
        self.centroidal_momentum_matrix(s).1
    }

    /// The Jacobian of the centre of mass (3 × nv): `A_g`'s linear rows over the mass.
    pub fn center_of_mass_jacobian(&self, s: &FloatingState) -> DMatrix<f64> {
        let (mass, _, ag) = self.centroidal_momentum_matrix(s);
        ag.rows(0, 3) / mass
    }

    /// `Ȧ_g(q, ν) ν`: the rate of change of the centroidal momentum at zero acceleration.
    pub fn centroidal_bias(&self, s: &FloatingState, v: &[f64]) -> Vector6<f64> {
        self.check_velocity(v);
        Vector6::from(floating::centroidal_bias(
            self.model,
            &self.base(s),
            &s.transforms,
            &self.inertias,
            v,
        ))
    }

    /// `q ⊕ ν dt`: the base moved along its twist for `dt` (the SE(3) exponential), the joints
    /// by `q̇ dt`.
    pub fn integrate(&self, q: &[f64], v: &[f64], dt: f64) -> Result<Vec<f64>, NonUnitQuaternion> {
        self.check_velocity(v);
        let base = BasePose::from_configuration(q)?;
        let twist: [f64; 6] = std::array::from_fn(|k| v[k]);
        let mut out = base.integrate(&twist, dt).configuration().to_vec();
        out.extend(q[7..].iter().zip(&v[6..]).map(|(q, v)| q + v * dt));
        Ok(out)
    }

    /// The velocity that moves `q0` to `q1` in unit time (`q1 = q0 ⊕ difference(q0, q1)`).
    pub fn difference(&self, q0: &[f64], q1: &[f64]) -> Result<Vec<f64>, NonUnitQuaternion> {
        let (a, b) = (
            BasePose::from_configuration(q0)?,
            BasePose::from_configuration(q1)?,
        );
        let mut out = a.difference(&b).to_vec();
        out.extend(q1[7..].iter().zip(&q0[7..]).map(|(x1, x0)| x1 - x0));
        Ok(out)
    }
}
