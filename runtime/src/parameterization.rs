//! Which parameters a regressor multiplies: the standard ten per body, or the base
//! (identifiable) set. An adaptive controller or a simulator is generic over this choice; the
//! robot comes with it, so generic code names one type (`arm7::Base`) and two numbers.

use crate::joint::JointTrig;
use crate::parameter::{ParameterKind, PARAMETERS_PER_BODY};
use crate::robot::{ForwardDynamics, Kinematics, Regressors, RobotDynamics};
use crate::ResultBuffer;
use core::marker::PhantomData;
use nalgebra::{SMatrix, SVector};

/// A linear parameterisation `φ = Φ θ` of a robot's dynamics with `M` parameters, such that
/// `regressor(q, q̇, v, a) · Φ θ = D a + C v + g` for the standard parameters θ of any robot
/// with the same kinematics.
pub trait Parameterization<const N: usize, const M: usize> {
    /// The robot whose dynamics these are.
    type Robot: Kinematics<N>;
    /// The robot's standard parameters θ (`SVector<f64, P>`).
    type StandardParameters;

    /// Names of the `M` parameters, e.g. `"m[link3]"`.
    const NAMES: [&'static str; M];

    /// `Φ θ`: the parameters this regressor multiplies, from the standard ones.
    fn from_standard(theta: &Self::StandardParameters) -> SVector<f64, M>;
    /// `Φ θ` of the robot's description.
    fn description() -> SVector<f64, M>;
    /// `Φ θ` of a θ that is zero except for body `body`'s ten standard parameters `p`: what
    /// a rigid payload on that body adds (by linearity).
    ///
    /// # Panics
    /// If `body` is not a body of the robot.
    fn from_body_parameters(body: usize, p: &[f64; PARAMETERS_PER_BODY]) -> SVector<f64, M>;
    /// `Φ θ'` where `θ'` is the description's θ with every standard parameter multiplied by
    /// `scale(kind)`: an estimate that is off by kind (the demo starts the inertial parameters
    /// at half and the joint friction at its nominal value), or a true robot whose friction and
    /// armature differ from the nominal values of its description.
    fn description_scaled_by_kind(scale: impl Fn(ParameterKind) -> f64) -> SVector<f64, M>;
    /// The diagonal of `Φ Γ Φᵀ` for the diagonal standard gain `Γ` that gives each standard
    /// parameter `gain(kind)`: the gain with which the standard law would move each of these
    /// parameters (a combination that absorbs masses adapts as fast as they would).
    fn gain_by_kind(gain: impl Fn(ParameterKind) -> f64) -> SVector<f64, M>;
    /// The regressor: `N × M`, linear in `v` and `a`.
    fn regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, M>;
    /// `(Y θ, Yᵀ r)` of [`Self::regressor`], without forming it where the robot's generated
    /// code can (what an adaptive law needs each tick: the torque `Y θ̂`, the adaptation's
    /// `Yᵀ r`).
    fn regressor_products(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
        theta: &SVector<f64, M>,
        r: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, M>);
    /// Forward dynamics of the robot with the description's parameters (the generated
    /// function): exact for a true robot whose parameters are [`Self::description`].
    fn description_forward_dynamics(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N>;
}

/// A robot whose generator also emitted its base (minimal, identifiable) parameters: `B`
/// combinations of the standard ones that span every torque the robot can produce (the group
/// `base_parameters`).
#[diagnostic::on_unimplemented(
    message = "`{Self}` was generated without the group `base_parameters`",
    note = "add `base_parameters` to `functions:` in the robot's description (or to \
            `Builder::functions`, or to `dyngen gen --functions`) and generate it again"
)]
pub trait BaseParameters<const N: usize, const P: usize, const B: usize>: Regressors<N, P> {
    /// Readable names that show what each base parameter combines, e.g. `"Izz[link1] + Iyy[link2] + …"`.
    const BASE_PARAMETER_NAMES: [&'static str; B];
    /// `θ_b = Φ θ`, a constant linear map fixed by the kinematics.
    fn base_parameters(theta: &SVector<f64, P>) -> SVector<f64, B>;
    /// `Y_b(q, q̇, v, a)` with `Y_b θ_b = Y θ = D a + C v + g`.
    fn base_regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, B>;
    /// [`Self::base_regressor`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn base_regressor_into(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
        out: &mut ResultBuffer<SMatrix<f64, N, B>>,
    ) {
        out.replace(Self::base_regressor(t, qd, v, a));
    }
    /// `(Y_b θ_b, Y_bᵀ r)` with `Y_b = Y_b(q, q̇, v, a)` (see
    /// [`Regressors::regressor_products`]).
    fn base_regressor_products(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
        theta_b: &SVector<f64, B>,
        r: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, B>) {
        crate::robot::products_of(&Self::base_regressor(t, qd, v, a), theta_b, r)
    }
    /// `Y_b(q, q̇, q̇, q̈)` with `Y_b θ_b = τ`: the base regressor in torque form (see
    /// [`Regressors::torque_regressor`]).
    fn base_torque_regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
    ) -> SMatrix<f64, N, B> {
        Self::base_regressor(t, qd, qd, qdd)
    }
    /// [`Self::base_torque_regressor`] written into `out`, a result kept between calls
    /// (see [`ResultBuffer`]).
    fn base_torque_regressor_into(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
        out: &mut ResultBuffer<SMatrix<f64, N, B>>,
    ) {
        out.replace(Self::base_torque_regressor(t, qd, qdd));
    }
}

/// The description's θ of robot `R`, each entry times `scale` of its kind.
fn scaled_by_kind<R: RobotDynamics<N, P>, const N: usize, const P: usize>(
    scale: impl Fn(ParameterKind) -> f64,
) -> SVector<f64, P> {
    let theta = R::parameters();
    SVector::from_fn(|i, _| theta[i] * scale(R::PARAMETER_KINDS[i]))
}

/// The standard parameters of robot `R`: ten per body, `Φ = I`. Generated modules name it
/// `Standard` (`arm7::Standard`).
pub struct Standard<R>(PhantomData<R>);

/// The base parameters of robot `R` with `P` standard parameters. Generated modules name it
/// `Base` (`arm7::Base`), so nobody has to write `P`.
pub struct Base<R, const P: usize>(PhantomData<R>);

/// θ that is zero except for body `body`'s ten entries.
fn body_only<const P: usize>(body: usize, p: &[f64; PARAMETERS_PER_BODY]) -> SVector<f64, P> {
    let start = body * PARAMETERS_PER_BODY;
    assert!(
        start + PARAMETERS_PER_BODY <= P,
        "body {body} is not a body of this robot"
    );
    SVector::from_fn(|i, _| {
        if (start..start + PARAMETERS_PER_BODY).contains(&i) {
            p[i - start]
        } else {
            0.0
        }
    })
}

impl<R: Regressors<N, P> + ForwardDynamics<N, P>, const N: usize, const P: usize> Parameterization<N, P>
    for Standard<R>
{
    type Robot = R;
    type StandardParameters = SVector<f64, P>;
    const NAMES: [&'static str; P] = R::PARAMETER_NAMES;

    fn from_standard(theta: &SVector<f64, P>) -> SVector<f64, P> {
        *theta
    }
    fn description() -> SVector<f64, P> {
        R::parameters()
    }
    fn from_body_parameters(body: usize, p: &[f64; PARAMETERS_PER_BODY]) -> SVector<f64, P> {
        body_only(body, p)
    }
    fn description_scaled_by_kind(scale: impl Fn(ParameterKind) -> f64) -> SVector<f64, P> {
        scaled_by_kind::<R, N, P>(scale)
    }
    fn gain_by_kind(gain: impl Fn(ParameterKind) -> f64) -> SVector<f64, P> {
        SVector::from_fn(|i, _| gain(R::PARAMETER_KINDS[i]))
    }
    fn regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, P> {
        R::regressor(t, qd, v, a)
    }
    fn regressor_products(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
        theta: &SVector<f64, P>,
        r: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, P>) {
        R::regressor_products(t, qd, v, a, theta, r)
    }
    fn description_forward_dynamics(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        R::forward_dynamics(t, qd, tau)
    }
}

impl<R: BaseParameters<N, P, B> + ForwardDynamics<N, P>, const N: usize, const P: usize, const B: usize>
    Parameterization<N, B> for Base<R, P>
{
    type Robot = R;
    type StandardParameters = SVector<f64, P>;
    const NAMES: [&'static str; B] = R::BASE_PARAMETER_NAMES;

    fn from_standard(theta: &SVector<f64, P>) -> SVector<f64, B> {
        R::base_parameters(theta)
    }
    fn description() -> SVector<f64, B> {
        R::base_parameters(&R::parameters())
    }
    fn from_body_parameters(body: usize, p: &[f64; PARAMETERS_PER_BODY]) -> SVector<f64, B> {
        R::base_parameters(&body_only(body, p))
    }
    fn description_scaled_by_kind(scale: impl Fn(ParameterKind) -> f64) -> SVector<f64, B> {
        R::base_parameters(&scaled_by_kind::<R, N, P>(scale))
    }
    fn gain_by_kind(gain: impl Fn(ParameterKind) -> f64) -> SVector<f64, B> {
        // Γ_b = diag(Φ Γ Φᵀ) = Σᵢ Γᵢ (Φ eᵢ)², with Φ eᵢ from the generated map (computed once
        // at set-up, so the cost of P calls does not matter).
        let mut sum = SVector::<f64, B>::zeros();
        for (i, kind) in R::PARAMETER_KINDS.iter().enumerate() {
            let column = R::base_parameters(&SVector::from_fn(|k, _| f64::from(u8::from(k == i))));
            sum += column.component_mul(&column) * gain(*kind);
        }
        sum
    }
    fn regressor(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
    ) -> SMatrix<f64, N, B> {
        R::base_regressor(t, qd, v, a)
    }
    fn regressor_products(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        v: &SVector<f64, N>,
        a: &SVector<f64, N>,
        theta_b: &SVector<f64, B>,
        r: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, B>) {
        R::base_regressor_products(t, qd, v, a, theta_b, r)
    }
    fn description_forward_dynamics(
        t: &JointTrig<N>,
        qd: &SVector<f64, N>,
        tau: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        R::forward_dynamics(t, qd, tau)
    }
}
