//! How the simulated closed loop moves with the base parameters: the forward sensitivity
//! equations, integrated along a simulated run ([`crate::closed_loop`]), that give DIDIM's
//! Gauss–Newton its Jacobian `∂τ_s/∂θ_b`.
//!
//! The loop's state is `x = (q, q̇, z)`, `z = ∫e`, and its sensitivity `S = ∂x/∂θ_b`
//! (`3n × b`, rows of `q`, then `q̇`, then `z`) starts at zero (the first state is the log's,
//! whatever the model). Along the motion `Ṡ = ∂f/∂x S + ∂f/∂θ_b`:
//!
//! - `Ṡ_q = S_q̇`, `Ṡ_z = −S_q` (`ż = q_r − q`);
//! - the law's torque moves with the state, `∂τ/∂θ_b = −K_p S_q − K_d S_q̇ + K_i S_z`;
//! - `Ṡ_q̇ = ∂q̈/∂q S_q + ∂q̈/∂q̇ S_q̇ + D⁻¹ (∂τ/∂θ_b − Y_b(q, q̇, q̈))`: the forward dynamics'
//!   derivatives at the law's torque, its response `D⁻¹` to that torque's change, and its
//!   change with the parameters at a fixed torque (`D q̈ + … = Y_b θ_b = τ` differentiated
//!   in `θ_b`). Gathered, `Ṡ_q̇ = G S + F` with `G = [∂q̈/∂q − D⁻¹K_p | ∂q̈/∂q̇ − D⁻¹K_d |
//!   D⁻¹K_i]` and `F = −D⁻¹ Y_b`.
//!
//! `G` and `F` are evaluated at the run's output times and taken linear in time between them;
//! `S` is integrated by fourth-order Runge–Kutta in half the run's own steps (its equations
//! are the loop's linearisation, so twice the loop's step is still well inside the method's
//! stability). The forward dynamics' derivatives cost some thirty times the forward dynamics:
//! evaluated at every stage of every step, they made DIDIM on a 6-axis arm take 17.6 s instead
//! of 2.6 s, for the same estimate to three digits. The interpolation is the Jacobian's only
//! error: against central differences of the simulated torques, at most 13% of a column's
//! largest entry through a start transient with outputs 5 ms apart, 1.1% 1.25 ms apart
//! (falling with the square of the interval). An inexact Jacobian slows Gauss–Newton, and moves its fixed point only by the
//! inexactness times the residuals' correlation with it, which is noise. The law must not add
//! the model's gravity (the stiff PD of IDIM-IV does; DIDIM never simulates it), nor read
//! rounded positions (rounding has no derivative).

use crate::closed_loop::{ControlLaw, Run};
use dyngen_model::base_parameters::BaseParameterSet;
use dyngen_model::dynamics::NumericDynamics;
use nalgebra::DMatrix;

/// `∂τ/∂θ_b` of the law at the sensitivity `s` (`3n × b`).
fn torque_sensitivity(law: &ControlLaw, s: &DMatrix<f64>) -> DMatrix<f64> {
    let n = law.gains.len();
    let mut t = DMatrix::zeros(n, s.ncols());
    for (j, g) in law.gains.iter().enumerate() {
        let row = s.row(j) * -g.kp - s.row(n + j) * g.kd + s.row(2 * n + j) * g.ki;
        t.row_mut(j).copy_from(&row);
    }
    t
}

/// `G` (`n × 3n`) and `F` (`n × b`) at output `k` of `run`; `None` where the mass matrix is
/// singular.
fn coefficients(
    dynamics: &NumericDynamics<'_>,
    base: &BaseParameterSet,
    law: &ControlLaw,
    run: &Run,
    k: usize,
) -> Option<(DMatrix<f64>, DMatrix<f64>)> {
    let (q, qd, qdd, tau) = (&run.q[k], &run.qd[k], &run.qdd[k], &run.tau[k]);
    let n = q.len();
    let inverse = dynamics.mass_matrix(q).try_inverse()?;
    let (dq, dqd) = dynamics.forward_dynamics_derivatives(q, qd, tau);
    let column = |gain: fn(&crate::closed_loop::JointGains) -> f64| {
        DMatrix::from_fn(n, n, |i, j| inverse[(i, j)] * gain(&law.gains[j]))
    };
    let mut g = DMatrix::zeros(n, 3 * n);
    g.columns_mut(0, n).copy_from(&(dq - column(|g| g.kp)));
    g.columns_mut(n, n).copy_from(&(dqd - column(|g| g.kd)));
    g.columns_mut(2 * n, n).copy_from(&column(|g| g.ki));
    let y_b = base.base_regressor(&dynamics.regressor(q, qd, qd, qdd));
    Some((g, -(inverse * y_b)))
}

/// `y += a x`.
fn add_scaled(y: &mut DMatrix<f64>, a: f64, x: &DMatrix<f64>) {
    y.zip_apply(x, |y, x| *y += a * x);
}

/// `Ṡ` at `s` with the coefficients `g`, `f`, into `out`.
fn rate(g: &DMatrix<f64>, f: &DMatrix<f64>, s: &DMatrix<f64>, out: &mut DMatrix<f64>) {
    let n = g.nrows();
    out.rows_mut(0, n).copy_from(&s.rows(n, n));
    let mut acceleration = out.rows_mut(n, n);
    acceleration.copy_from(f);
    acceleration.gemm(1.0, g, s, 1.0);
    out.rows_mut(2 * n, n).copy_from(&s.rows(0, n));
    out.rows_mut(2 * n, n).neg_mut();
}

/// The law's torques' sensitivity `∂τ/∂θ_b` (`n × b`) at every output time of `run`, the loop
/// of `law` simulated at `times` on `dynamics` (the model of the base parameters of `base`
/// simulated); an error naming the time where the mass matrix is singular.
///
/// `S` takes half as many steps as the loop (at least one): the loop's steps keep a quarter
/// radian of its fastest oscillation and one time constant of its fastest decay, and twice
/// that is still inside the method's stability (2.78).
pub(crate) fn torque_sensitivities(
    dynamics: &NumericDynamics<'_>,
    base: &BaseParameterSet,
    law: &ControlLaw,
    times: &[f64],
    run: &Run,
) -> Result<Vec<DMatrix<f64>>, String> {
    let (n, b) = (dynamics.model.dof(), base.count());
    let at = |k: usize| {
        coefficients(dynamics, base, law, run, k).ok_or_else(|| {
            format!(
                "at t = {:.3} s the simulated model's mass matrix is singular: its motion has no \
                 sensitivity to the parameters",
                times[k]
            )
        })
    };
    let steps = (run.steps / 2).max(1);
    let mut s = DMatrix::zeros(3 * n, b);
    let mut probe = s.clone();
    let mut k = [s.clone(), s.clone(), s.clone(), s.clone()];
    let (mut g, mut f) = (DMatrix::zeros(n, 3 * n), DMatrix::zeros(n, b));
    let mut out = Vec::with_capacity(times.len());
    let mut here = at(0)?;
    for i in 0..times.len() {
        out.push(torque_sensitivity(law, &s));
        let Some(&next) = times.get(i + 1) else { break };
        let there = at(i + 1)?;
        // The coefficients `share` of the way from this output time to the next.
        let between = |share: f64, g: &mut DMatrix<f64>, f: &mut DMatrix<f64>| {
            g.copy_from(&there.0);
            *g *= share;
            add_scaled(g, 1.0 - share, &here.0);
            f.copy_from(&there.1);
            *f *= share;
            add_scaled(f, 1.0 - share, &here.1);
        };
        let h = (next - times[i]) / steps as f64;
        for step in 0..steps {
            let share = step as f64 / steps as f64;
            let half = 0.5 / steps as f64;
            between(share, &mut g, &mut f);
            rate(&g, &f, &s, &mut k[0]);
            between(share + half, &mut g, &mut f);
            for stage in 1..4 {
                if stage == 3 {
                    between(share + 2.0 * half, &mut g, &mut f);
                }
                let along = if stage == 3 { h } else { 0.5 * h };
                probe.copy_from(&s);
                add_scaled(&mut probe, along, &k[stage - 1]);
                let (before, rest) = k.split_at_mut(stage);
                let _ = before;
                rate(&g, &f, &probe, &mut rest[0]);
            }
            for (stage, weight) in k.iter().zip([1.0, 2.0, 2.0, 1.0]) {
                add_scaled(&mut s, weight * h / 6.0, stage);
            }
        }
        here = there;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use crate::closed_loop::{friction_damping, ControlLaw, JointGains, Loop, Reference, Run};
    use crate::fixed_point::standard_of;
    use crate::fourier::FourierTrajectory;
    use dyngen_model::base_parameters::BaseParameterSet;
    use dyngen_model::description::load;
    use dyngen_model::dynamics::NumericDynamics;
    use dyngen_model::model::Model;
    use nalgebra::DMatrix;
    use std::path::Path;

    /// arm7 with friction and armature (smoothed Coulomb) run by a PID whose integral acts,
    /// for 0.25 s output at `rate` Hz from a start 2 mrad off the reference, with the base
    /// parameters `theta_b`: the run and, when `sensitivity`, its torques' sensitivity.
    fn run(
        model: &Model,
        base: &BaseParameterSet,
        theta_b: &[f64],
        rate: f64,
        sensitivity: bool,
    ) -> (Run, Vec<DMatrix<f64>>) {
        let n = model.dof();
        let trajectory = FourierTrajectory::random(n, 5, 0.1, 3);
        let times: Vec<f64> = (0..=(0.25 * rate) as usize).map(|k| k as f64 / rate).collect();
        let reference = Reference::from_trajectory(&trajectory, &times);
        let mass = NumericDynamics::new(model).mass_matrix(&reference.q[0]);
        let omega = 2.0 * std::f64::consts::PI * 5.0;
        let law = ControlLaw {
            gains: (0..n)
                .map(|j| JointGains {
                    kp: mass[(j, j)] * omega * omega,
                    kd: 2.0 * mass[(j, j)] * omega,
                    ki: 0.5 * mass[(j, j)] * omega * omega * omega,
                })
                .collect(),
        };
        let theta = standard_of(base, theta_b);
        let dynamics = NumericDynamics::with_parameters(model, &theta);
        let closed = Loop {
            dynamics: &dynamics,
            law: &law,
            reference: &reference,
            quantum: None,
            gravity_compensation: false,
            // The same steps at either rate: only the output times differ.
            min_steps: (3200.0 / rate) as usize,
        };
        let q0: Vec<f64> = reference.q[0].iter().map(|q| q + 0.002).collect();
        let run = closed
            .run(&times, &q0, &reference.qd[0], &friction_damping(model, &theta))
            .unwrap_or_else(|e| panic!("{e}"));
        let sensitivities = match sensitivity {
            true => super::torque_sensitivities(&dynamics, base, &law, &times, &run)
                .unwrap_or_else(|e| panic!("{e}")),
            false => Vec::new(),
        };
        (run, sensitivities)
    }

    /// The largest difference, over the columns, between the torques' sensitivity at output
    /// rate `rate` and central differences of the simulated torques (the same integration
    /// steps either side), relative to the column's largest entry.
    fn largest_difference(model: &Model, rate: f64) -> f64 {
        let base = BaseParameterSet::compute(model);
        let theta_b = base.base_parameters(&model.parameters());
        let (_, sensitivity) = run(model, &base, &theta_b, rate, true);
        let scale = theta_b.iter().map(|v| v.abs()).fold(0.0, f64::max);
        let mut worst = 0.0f64;
        for c in 0..theta_b.len() {
            let h = 3e-4 * theta_b[c].abs().max(1e-2 * scale);
            let shifted = |by: f64| {
                let mut t = theta_b.clone();
                t[c] += by;
                run(model, &base, &t, rate, false).0.tau
            };
            let (up, down) = (shifted(h), shifted(-h));
            let size = sensitivity.iter().map(|s| s.column(c).amax()).fold(0.0, f64::max);
            assert!(size > 0.0, "column {c} never moves the torques");
            for (k, s) in sensitivity.iter().enumerate() {
                for j in 0..model.dof() {
                    let difference = (up[k][j] - down[k][j]) / (2.0 * h);
                    worst = worst.max((difference - s[(j, c)]).abs() / size);
                }
            }
        }
        worst
    }

    /// Every column of the torques' sensitivity against central differences of the simulated
    /// torques, with the coefficients taken at output times 5 ms and 1.25 ms apart: the
    /// differences are those of the coefficients' linear interpolation, falling with the
    /// square of the interval (a wrong term would not fall).
    #[test]
    fn torque_sensitivity_matches_differences_of_the_simulation() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/arm7_friction.yaml");
        let model = load(&path).unwrap_or_else(|e| panic!("{e}")).model;
        let [coarse, fine] = [200.0, 800.0].map(|rate| largest_difference(&model, rate));
        println!(
            "largest difference of a column's largest entry: {coarse:.2e} at 200 Hz, {fine:.2e} at 800 Hz"
        );
        assert!(coarse <= 0.2, "{coarse}");
        assert!(fine <= coarse / 8.0, "{fine} against {coarse}");
    }
}
