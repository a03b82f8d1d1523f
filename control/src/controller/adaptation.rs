//! The adaptation gain `Γ` (diagonal) and the update `θ̂̇ = −Γ Yᵀ r` (Lemma 3).

use super::error::ConfigError;
use dyngen_runtime::{ParameterKind, Parameterization};
use nalgebra::SVector;

/// Per-kind adaptation gains: mass, first moment `m·c`, second moment `I`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GammaByKind {
    pub mass: f64,
    pub first_moment: f64,
    pub inertia: f64,
    /// Joint-level parameters (armature, friction, offset), for robots whose description
    /// chooses those regressor columns. 0 holds them at their estimate `θ̂(0)` (the
    /// description's nominal values) while the inertial parameters adapt.
    pub joint: f64,
}

impl Default for GammaByKind {
    /// `[100, 10, 1]` over `[m, m·c, I]`: what worked in the reference prototype at 1 kHz.
    /// Joint-level parameters: [`GammaByKind::DEFAULT_JOINT`].
    fn default() -> Self {
        GammaByKind {
            mass: 100.0,
            first_moment: 10.0,
            inertia: 1.0,
            joint: Self::DEFAULT_JOINT,
        }
    }
}

impl GammaByKind {
    /// The default gain of the joint-level parameters (`docs/controller.md`, adaptation).
    pub const DEFAULT_JOINT: f64 = 1000.0;

    /// Every inertial gain finite and > 0; the joint-level gain finite and ≥ 0 (0: the joint
    /// terms keep their estimate).
    pub fn validate(&self) -> Result<(), ConfigError> {
        let refuse = |what: &str, g: f64, bound: &str| {
            Err(ConfigError::NotPositiveDefinite {
                name: "Γ",
                detail: format!("the {what} gain is {g}; it must be {bound}"),
            })
        };
        for (what, g) in [
            ("mass", self.mass),
            ("first-moment", self.first_moment),
            ("inertia", self.inertia),
        ] {
            if !(g.is_finite() && g > 0.0) {
                return refuse(what, g, "> 0");
            }
        }
        if !(self.joint.is_finite() && self.joint >= 0.0) {
            return refuse(
                "joint-term",
                self.joint,
                "≥ 0 (0 keeps the joint terms at their estimate)",
            );
        }
        Ok(())
    }

    /// The gain of one standard parameter, by its kind.
    pub fn of(&self, kind: ParameterKind) -> f64 {
        match kind {
            ParameterKind::Mass => self.mass,
            ParameterKind::FirstMoment => self.first_moment,
            ParameterKind::Inertia => self.inertia,
            ParameterKind::Armature
            | ParameterKind::ViscousFriction
            | ParameterKind::CoulombFriction
            | ParameterKind::Offset => self.joint,
        }
    }

    /// The diagonal `Γ` for the parameters of `Z`, carried over from these per-kind gains of
    /// the standard parameters: the diagonal of `Φ Γ Φᵀ`, where `θ_z = Φ θ`.
    ///
    /// Why: with `Y = Y_z Φ`, the standard law `θ̂̇ = −Γ Yᵀ r` moves `θ̂_z = Φ θ̂` with the gain
    /// `Φ Γ Φᵀ`. A base parameter such as `mcz[l3] + 0.39·m[l4] + 0.39·m[l5]` absorbs masses, so
    /// it must adapt about as fast as they would (`10 + 2·0.39²·100`), not at the first-moment
    /// gain of its first term. For the standard parameters (`Φ = I`) each parameter gets the
    /// gain of its kind.
    pub fn carried_to<Z, const N: usize, const M: usize>(&self) -> SVector<f64, M>
    where
        Z: Parameterization<N, M>,
    {
        Z::gain_by_kind(|kind| self.of(kind))
    }
}

/// `½ θ̃ᵀ Γ⁻¹ θ̃` over the adapted parameters (`Γᵢ > 0`): the parameter part of the Lyapunov
/// function. A parameter with `Γᵢ = 0` is held at its estimate; its error is not a state of
/// the adaptation and has no term (what it does to the argument: `docs/controller.md`).
pub fn parameter_error_energy<const M: usize>(theta_error: &SVector<f64, M>, gamma: &SVector<f64, M>) -> f64 {
    0.5 * theta_error
        .iter()
        .zip(gamma.iter())
        .filter(|(_, g)| **g > 0.0)
        .map(|(e, g)| e * e / g)
        .sum::<f64>()
}

/// `θ̂̇ = −Γ (Yᵀ r)` from `Yᵀ r` already computed (the law gets it with `Y θ̂` from
/// [`Parameterization::regressor_products`]).
#[inline]
pub(crate) fn rate_from_regressor_product<const M: usize>(
    gamma: &SVector<f64, M>,
    y_tr_r: &SVector<f64, M>,
) -> SVector<f64, M> {
    // Arrays, not `component_mul`: nalgebra's zipped iterators do not unroll or vectorise.
    let (gamma, y_tr_r) = (&gamma.data.0[0], &y_tr_r.data.0[0]);
    let mut rate = [0.0; M];
    for i in 0..M {
        rate[i] = -gamma[i] * y_tr_r[i];
    }
    SVector::from(rate)
}
