//! The accuracy a forward-dynamics computation can have: its error against the same algorithm
//! run on [`DoubleDouble`], in units of what a backward-stable computation may lose.

use crate::double_double::DoubleDouble;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::internals::dynamics::{
    forward_dynamics, inertias_from_parameters, joint_transforms, mass_matrix,
};
use dyngen_codegen::internals::scalar::Scalar;
use dyngen_codegen::model::Model;

/// `q̈` of `model` with parameters `theta` (ten per body, then the joint-level ones), to about
/// 1e-30 relative: the double-double run of the generic algorithm, rounded to `f64`.
pub fn exact_forward_dynamics(model: &Model, theta: &[f64], q: &[f64], qd: &[f64], tau: &[f64]) -> Vec<f64> {
    let dd = |v: &[f64]| -> Vec<DoubleDouble> { v.iter().map(|&x| DoubleDouble::from_f64(x)).collect() };
    let inertial = dd(&theta[..model.inertial_parameter_count()]);
    forward_dynamics(
        model,
        &joint_transforms(model, &dd(q)),
        &inertias_from_parameters(&inertial),
        &model.joint_term_values_from(theta),
        &dd(qd),
        &dd(tau),
    )
    .iter()
    .map(|x| x.to_f64())
    .collect()
}

/// The singular values of `D(q)` of the rigid bodies (armature only raises the smallest).
fn mass_matrix_extremes(model: &Model, theta: &[f64], q: &[f64]) -> (f64, f64) {
    let inertias = inertias_from_parameters(&theta[..model.inertial_parameter_count()]);
    let s = mass_matrix(model, &joint_transforms(model, q), &inertias).singular_values();
    (s.max(), s.min())
}

/// A computed `q̈` against the exact one, in units of what a backward-stable computation of
/// `q̈ = D⁻¹ (τ − h)`, `h = C q̇ + g` (+ joint terms), may lose:
/// `‖δq̈‖ / (ε · (cond₂(D) ‖q̈‖ + (‖τ‖ + ‖h‖) / σ_min(D)))`. The first term is the solve's, the
/// second forming `τ − h` (cancellation there is the data's, not the algorithm's).
pub fn error_in_stable_units(
    got: &[f64],
    model: &Model,
    theta: &[f64],
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
) -> f64 {
    let exact = exact_forward_dynamics(model, theta, q, qd, tau);
    let norm = |v: &mut dyn Iterator<Item = f64>| v.map(|x| x * x).sum::<f64>().sqrt();
    let error = norm(&mut got.iter().zip(&exact).map(|(a, b)| a - b));
    let zero = vec![0.0; q.len()];
    let h = NumericDynamics::with_parameters(model, theta).inverse_dynamics(q, qd, &zero);
    let (largest, smallest) = mass_matrix_extremes(model, theta, q);
    let scale = largest / smallest * norm(&mut exact.iter().copied())
        + (norm(&mut tau.iter().copied()) + norm(&mut h.iter().copied())) / smallest;
    error / (f64::EPSILON * scale)
}
