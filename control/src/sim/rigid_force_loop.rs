//! How the controller's force loop behaves on a rigid table, checked before a run.
//!
//! On a rigid surface the contact force is algebraic in the torque: the torque of one tick
//! sets the force the next tick measures. In `τ = Jᵀ F̄ + Y θ̂ − G r` the measured force
//! comes back whole through `Jᵀ F̄`, and `−G r` adds the correction: with the point held still
//! along the normal, the normal part of `r` is minus the force rows' reference velocity,
//! `λ (F_t − F_d) / k`. So `F_{k+1} − F_d = (1 − α)(F_k − F_d)` with
//!
//! `α = (λ / k) · (nᵀ J D⁻¹ G J⁺ n) / (nᵀ J D⁻¹ Jᵀ n)`,
//!
//! (`n` the normal, `J` the contact point's linear rows, `J⁺` the task's pseudo-inverse applied
//! to the normal, `D` the true mass matrix): the force settles for `0 < α < 2` and oscillates,
//! growing, above 2 (arm7 at the demo's gains: `k = 4·10⁴ N/m` gives `α = 2.09` and a force
//! that chatters between 0 and tens of newtons, `5·10⁴` gives 1.68 and holds the force). On a
//! compliant surface the model stiffness `k` sets the force loop's bandwidth instead; on a
//! rigid one it sets this gain, and a larger `k` is a slower force loop.

use super::plant::Plant;
use crate::controller::{ConfigError, Desired, HybridController};
use dyngen_runtime::{JointTrig, Parameterization};
use nalgebra::SVector;

/// Above this gain the force diverges.
pub(crate) const RIGID_FORCE_LOOP_LIMIT: f64 = 2.0;

/// `α` of `controller` on `plant`'s rigid surface at rest at `q0` (`d0` the desired motion
/// there, for the task rows).
pub(crate) fn rigid_force_loop_gain<Z, const N: usize, const M: usize, const T: usize>(
    plant: &Plant<Z, N, M>,
    controller: &HybridController<Z, N, M, T>,
    q0: &SVector<f64, N>,
    d0: &Desired<N, 1>,
) -> Result<f64, ConfigError>
where
    Z: Parameterization<N, M>,
{
    let t = JointTrig::new(q0);
    let normal = plant.contact.normal();
    let row = normal.transpose() * plant.linear_jacobian(&t);
    let along_normal = SVector::<f64, T>::from_fn(|i, _| if i < 3 { normal[i] } else { 0.0 });
    let joint_velocity = controller
        .task_pseudo_inverse_mul(q0, d0, &along_normal)
        .map_err(|e| ConfigError::Invalid {
            name: "q0",
            detail: format!("the task rows at the start: {e}"),
        })?;
    let mass = plant
        .mass_matrix(&t)
        .cholesky()
        .ok_or_else(|| ConfigError::Invalid {
            name: "payload",
            detail: "the true mass matrix at the start is not positive definite".into(),
        })?;
    let gains = &controller.config().gains;
    let k = controller.stiffness().fixed_columns::<3>(0).norm();
    let pushed = (row * mass.solve(&(gains.g * joint_velocity)))[0];
    let inverse_mass = (row * mass.solve(&row.transpose()))[0];
    Ok(gains.lambda / k * pushed / inverse_mass)
}
