//! Composite adaptation (Slotine and Li, *Composite adaptive control of robot manipulators*,
//! Automatica 1989): the update also descends the prediction error `e = W θ̂ − τ_f` of the
//! filtered joint torque, `θ̂̇ = −Γ (Yᵀ r + Wᵀ R e)`.
//!
//! No joint acceleration is measured, so `W` is built from the momentum form of the dynamics,
//! which needs none:
//!
//! ```text
//! D q̈ + C q̇ + g + F_v q̇ + F_c σ(q̇) + f_o = d/dt (Y_p θ) + Y_q θ
//! Y_p = Y(q, 0, 0, q̇)                             Y_p θ = D q̇ + g + f_o
//! Y_q = Y(q, q̇, q̇, 0) − ∂/∂s Y(q + s q̇, 0, 0, q̇)|₀  Y_q θ = C q̇ − Ḋ q̇ − ġ + g + F_v q̇ + F_c σ(q̇) + f_o
//! ```
//!
//! and the filter `λ_f/(s + λ_f)` of a derivative is `λ_f (x − x_f)`, so with `P_f`, `Q_f`,
//! `τ_f` the filtered `Y_p`, `Y_q` and `τ − Jᵀ F̄`,
//!
//! ```text
//! W = λ_f (Y_p − P_f) + Q_f        W θ = τ_f        (from P_f(0) = Y_p(0), Q_f(0) = 0, τ_f(0) = 0)
//! ```
//!
//! exactly, for any motion. The one derivative the generated code does not give, the
//! regressor of `Ḋ q̇ + ġ`, is a central difference of `Y(q, 0, 0, q̇)` along `q̇` (step
//! [`DIRECTION_STEP`] rad): an analytic function differenced, with an error of order 1e-9 of
//! that term, not an estimate of a measured signal. The controller's tick steps the prediction
//! term of `θ̂̇` implicitly (`implicit_step`), since it is stiff. `docs/controller.md` gives the
//! stability argument.

use super::error::ConfigError;
use super::spd::SpdFactor;
use dyngen_runtime::{JointTrig, Parameterization};
use nalgebra::{SMatrix, SVector};

/// The step (rad, along the largest joint velocity) of the central difference that gives the
/// regressor of `Ḋ q̇ + ġ`: truncation error `~ step²/6` relative, rounding `~ 1e-16/step`.
pub const DIRECTION_STEP: f64 = 1e-4;

/// The settings of the composite adaptation: the bandwidth `λ_f` (rad/s) of the first-order
/// filter `λ_f/(s + λ_f)` applied alike to the joint torque and to the regressor, and the weight
/// `ρ` of the prediction error, `R = ρ I` (it weighs `eᵀ e`, in (N·m)², against `rᵀ G r` in the
/// Lyapunov function's decrease). `ρ = 0` is the Slotine–Li law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Composite {
    pub bandwidth: f64,
    pub weight: f64,
}

impl Default for Composite {
    /// [`Composite::DEFAULT_BANDWIDTH`] and [`Composite::DEFAULT_WEIGHT`], chosen on the demo's
    /// pose task on `arm7_friction` (`docs/controller.md`, composite adaptation).
    fn default() -> Self {
        Composite {
            bandwidth: Self::DEFAULT_BANDWIDTH,
            weight: Self::DEFAULT_WEIGHT,
        }
    }
}

impl Composite {
    /// `λ_f` (rad/s): high enough to keep the torque steps of Coulomb friction at velocity
    /// reversals, which the joint terms must predict.
    pub const DEFAULT_BANDWIDTH: f64 = 500.0;
    /// `ρ`.
    pub const DEFAULT_WEIGHT: f64 = 0.5;

    /// `λ_f` finite and > 0, `ρ` finite and ≥ 0.
    pub fn validate(&self) -> Result<(), ConfigError> {
        if !(self.bandwidth.is_finite() && self.bandwidth > 0.0) {
            return Err(ConfigError::NotPositiveDefinite {
                name: "λ_f",
                detail: format!(
                    "the prediction filter's bandwidth is {}; it must be > 0",
                    self.bandwidth
                ),
            });
        }
        if !(self.weight.is_finite() && self.weight >= 0.0) {
            return Err(ConfigError::NotPositiveDefinite {
                name: "R",
                detail: format!(
                    "the prediction error's weight is {}; it must be ≥ 0 (0 is the Slotine–Li law)",
                    self.weight
                ),
            });
        }
        Ok(())
    }
}

/// The state of the prediction filter of the composite adaptation: `P_f`, `Q_f` and `τ_f`, the
/// filtered `Y_p`, `Y_q` and joint torque `τ − Jᵀ F̄`, from which `W = λ_f (Y_p − P_f) + Q_f`
/// (`docs/controller.md`, composite adaptation). What an integrator that treats the filter as
/// part of the closed-loop state integrates
/// ([`super::HybridController::evaluate_composite`] gives its rate). Inside the controller,
/// between ticks, the filter is kept advanced over the coming control period by everything
/// known at the tick, so that the next tick only adds what it measures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PredictionFilter<const N: usize, const M: usize> {
    /// `P_f`, the filtered `Y_p` (`Y_p θ = D q̇ + g + f_o`).
    pub momentum: SMatrix<f64, N, M>,
    /// `Q_f`, the filtered `Y_q` (`Y_q θ = C q̇ − Ḋ q̇ − ġ + g + F_v q̇ + F_c σ(q̇) + f_o`).
    pub rest: SMatrix<f64, N, M>,
    /// `τ_f`, the filtered torque the robot's dynamics see, `τ − Jᵀ F̄`.
    pub torque: SVector<f64, N>,
}

/// What the filter takes in at one instant, besides the torque the law commands.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PredictionSignals<const N: usize, const M: usize> {
    /// `Y_p(q, q̇)`.
    pub momentum: SMatrix<f64, N, M>,
    /// `Y_q(q, q̇)`.
    pub rest: SMatrix<f64, N, M>,
    /// `Jᵀ F̄`, the contact's share of the torque.
    pub contact: SVector<f64, N>,
}

/// `Y_p` and `Y_q` at the measured state, four regressor evaluations.
pub(crate) fn prediction_signals<Z, const N: usize, const M: usize>(
    trig: &JointTrig<N>,
    q: &SVector<f64, N>,
    qd: &SVector<f64, N>,
    contact: SVector<f64, N>,
) -> PredictionSignals<N, M>
where
    Z: Parameterization<N, M>,
{
    let zero = SVector::<f64, N>::zeros();
    let momentum = Z::regressor(trig, &zero, &zero, qd);
    let mut rest = Z::regressor(trig, qd, qd, &zero);
    let speed = qd.amax();
    // At rest the derivative along q̇ is 0; dividing by the speed would not be.
    if speed > 0.0 {
        let s = DIRECTION_STEP / speed;
        let ahead = Z::regressor(&JointTrig::new(&(q + qd * s)), &zero, &zero, qd);
        let behind = Z::regressor(&JointTrig::new(&(q - qd * s)), &zero, &zero, qd);
        rest -= (ahead - behind) * (0.5 / s);
    }
    PredictionSignals {
        momentum,
        rest,
        contact,
    }
}

impl<const N: usize, const M: usize> PredictionFilter<N, M> {
    /// The state at the start: `P_f = Y_p`, the rest 0, so that `W θ = τ_f` from the first
    /// instant on (`W = 0`, `τ_f = 0`).
    pub(crate) fn start(signals: &PredictionSignals<N, M>) -> Self {
        PredictionFilter {
            momentum: signals.momentum,
            rest: SMatrix::zeros(),
            torque: SVector::zeros(),
        }
    }

    /// `W = λ_f (Y_p − P_f) + Q_f`.
    pub(crate) fn regressor(&self, signals: &PredictionSignals<N, M>, bandwidth: f64) -> SMatrix<f64, N, M> {
        (signals.momentum - self.momentum) * bandwidth + self.rest
    }

    /// `(Ṗ_f, Q̇_f, τ̇_f) = λ_f ((Y_p, Y_q, τ − Jᵀ F̄) − (P_f, Q_f, τ_f))`.
    pub(crate) fn rate(
        &self,
        signals: &PredictionSignals<N, M>,
        tau: &SVector<f64, N>,
        bandwidth: f64,
    ) -> Self {
        PredictionFilter {
            momentum: (signals.momentum - self.momentum) * bandwidth,
            rest: (signals.rest - self.rest) * bandwidth,
            torque: (tau - signals.contact - self.torque) * bandwidth,
        }
    }

    /// The exact step of the filter over one control period `h` with the torque `τ` held and
    /// the other inputs linear between the ticks: `x(h) = a x(0) + c₀ u(0) + c₁ u(h)` with
    /// `a = e^(−λ_f h)`, `c₁ = 1 − (1 − a)/(λ_f h)`, `c₀ = 1 − a − c₁`. This is everything but
    /// the `c₁ u(h)` that the next tick adds ([`Self::completed`]) when it measures `u(h)`.
    pub(crate) fn advanced(
        &self,
        signals: &PredictionSignals<N, M>,
        tau: &SVector<f64, N>,
        step: &FilterStep,
    ) -> Self {
        let (a, c0) = (step.decay, step.start_weight);
        PredictionFilter {
            momentum: self.momentum * a + signals.momentum * c0,
            rest: self.rest * a + signals.rest * c0,
            torque: self.torque * a + tau * (1.0 - a) - signals.contact * c0,
        }
    }

    /// The advanced state completed with the inputs measured at the end of the period.
    pub(crate) fn completed(&self, signals: &PredictionSignals<N, M>, step: &FilterStep) -> Self {
        let c1 = step.end_weight;
        PredictionFilter {
            momentum: self.momentum + signals.momentum * c1,
            rest: self.rest + signals.rest * c1,
            torque: self.torque - signals.contact * c1,
        }
    }
}

/// The weights of one exact filter step ([`PredictionFilter::advanced`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FilterStep {
    pub decay: f64,
    pub start_weight: f64,
    pub end_weight: f64,
}

impl FilterStep {
    pub(crate) fn new(bandwidth: f64, period: f64) -> Self {
        let x = bandwidth * period;
        let decay = (-x).exp();
        // 1 − (1 − a)/x loses every digit for a tiny x; its series does not.
        let end_weight = if x < 1e-4 {
            x / 2.0 - x * x / 6.0
        } else {
            1.0 - (-x).exp_m1() / -x
        };
        FilterStep {
            decay,
            start_weight: -(-x).exp_m1() - end_weight,
            end_weight,
        }
    }
}

/// `Yᵀ r + Wᵀ R e` for `R = ρ I`, `e = W θ̂ − τ_f`; returns the sum and `e`.
pub(crate) fn composite_product<const N: usize, const M: usize>(
    y_tr_r: &SVector<f64, M>,
    w: &SMatrix<f64, N, M>,
    filter: &PredictionFilter<N, M>,
    theta_hat: &SVector<f64, M>,
    weight: f64,
) -> (SVector<f64, M>, SVector<f64, N>) {
    let e = w * theta_hat - filter.torque;
    (y_tr_r + w.tr_mul(&(e * weight)), e)
}

/// One step of `θ̂` over `dt`, the Slotine–Li term explicit and the prediction term implicit:
/// `θ̂⁺ = b − dt Γ Wᵀ R ê` with `b = θ̂ − dt Γ Yᵀ r` (`slotine_li_rate = −Γ Yᵀ r`) and
/// `ê = W θ̂⁺ − τ_f`, the prediction error after the step.
///
/// Why implicit: `Γ Wᵀ R W` carries the mass gains times `(g·lever)²`, so explicit Euler of the
/// prediction term is unstable at 1 kHz for all but a tiny `R`. `W` has rank ≤ N, so the
/// implicit step needs one N×N solve, not an M×M one: multiplying by `W`,
/// `(I + R A) ê = W b − τ_f` with `A = dt W Γ Wᵀ` (positive semi-definite); for `R = ρ I`,
/// `I + ρ A` is positive definite. With `ρ = 0` this is the Slotine–Li step to the bit. `None`
/// if the system is not finite.
pub(crate) fn implicit_step<const N: usize, const M: usize>(
    theta_hat: &SVector<f64, M>,
    slotine_li_rate: &SVector<f64, M>,
    w: &SMatrix<f64, N, M>,
    filter: &PredictionFilter<N, M>,
    gamma: &SVector<f64, M>,
    weight: f64,
    dt: f64,
) -> Option<SVector<f64, M>> {
    let b = theta_hat + slotine_li_rate * dt;
    let mut w_gamma = *w;
    for (mut column, g) in w_gamma.column_iter_mut().zip(gamma.iter()) {
        column *= g * dt;
    }
    let system = SMatrix::<f64, N, N>::identity() + w_gamma * w.transpose() * weight;
    let e_after = SpdFactor::new(&system)?.solve(&(w * b - filter.torque));
    let correction = w_gamma.tr_mul(&(e_after * weight));
    Some(b - correction)
}

#[cfg(test)]
mod tests {
    use super::FilterStep;

    /// The step's weights against the integrals they stand for, by the midpoint rule.
    #[test]
    fn filter_step_weights_are_the_exact_integrals() {
        for (bandwidth, period) in [(20.0, 1e-3), (1.0, 1e-3), (500.0, 1e-2), (1e-3, 1e-3)] {
            let step = FilterStep::new(bandwidth, period);
            let n = 200_000;
            let (mut c0, mut c1) = (0.0, 0.0);
            for i in 0..n {
                let s = (i as f64 + 0.5) / n as f64 * period;
                let kernel = bandwidth * (-bandwidth * (period - s)).exp() * period / n as f64;
                c0 += kernel * (1.0 - s / period);
                c1 += kernel * s / period;
            }
            assert!((step.decay - (-bandwidth * period).exp()).abs() < 1e-15);
            assert!(
                (step.start_weight - c0).abs() <= 1e-9 * c0.max(1e-12),
                "{bandwidth} {period}: {} {c0}",
                step.start_weight
            );
            assert!(
                (step.end_weight - c1).abs() <= 1e-9 * c1.max(1e-12),
                "{bandwidth} {period}: {} {c1}",
                step.end_weight
            );
        }
    }
}
