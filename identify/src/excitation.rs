//! Excitation: Fourier coefficients chosen so that the stacked base regressor is well
//! conditioned, within the joint limits.
//!
//! Criterion: the condition number of `W_b` (the torque-form base regressor stacked at
//! `samples` equally spaced times of one period) with its columns scaled to unit norm. Scaling
//! makes the number independent of units (kg against kg·m²) and it bounds the amplification
//! of torque noise into relative parameter errors, which is what an experiment designer wants
//! small; the raw condition number is dominated by the units.
//!
//! Search: every candidate is first fitted into the limits ([`FourierTrajectory::fit_into`]),
//! so it is feasible by construction and the search is unconstrained. The best of
//! `starts` random coefficient sets seeds a (1+1) evolution strategy with the one-fifth
//! success rule (Rechenberg): one Gaussian perturbation of all coefficients per iteration,
//! kept if it lowers the criterion; the step grows after a success and shrinks after a
//! failure. Derivative-free, as it must be (Coulomb friction makes `W_b` non-smooth in the
//! coefficients), deterministic for a seed, and one regressor stack per iteration.

use crate::fourier::{FourierTrajectory, TrajectoryLimits};
use crate::observation::{BaseModel, BaseRegressorSource};
use dyngen_runtime::SplitMix64;

/// Options of the search.
#[derive(Clone, Debug, PartialEq)]
pub struct ExcitationOptions {
    /// Base frequency (Hz): the period is `1/f`.
    pub base_frequency: f64,
    pub harmonics: usize,
    /// Times per period the regressor is stacked at.
    pub samples: usize,
    /// Random starts; the best seeds the evolution strategy.
    pub starts: usize,
    pub iterations: usize,
    pub seed: u64,
}

impl Default for ExcitationOptions {
    fn default() -> Self {
        ExcitationOptions {
            base_frequency: 0.1,
            harmonics: 5,
            samples: 200,
            starts: 8,
            iterations: 400,
            seed: 1,
        }
    }
}

/// The optimised trajectory, with the criterion before and after.
#[derive(Clone, Debug)]
pub struct Excitation {
    pub trajectory: FourierTrajectory,
    /// Condition number of the optimised trajectory.
    pub condition_number: f64,
    /// Median condition number of the random starts (the same limits, no optimisation).
    pub random_condition_number: f64,
    pub evaluations: usize,
}

/// Condition number of the column-scaled base regressor stacked along `trajectory`.
pub fn condition_number(base: &BaseModel<'_>, trajectory: &FourierTrajectory, samples: usize) -> f64 {
    let period = trajectory.period();
    let states: Vec<_> = (0..samples)
        .map(|k| trajectory.at(period * k as f64 / samples as f64))
        .collect();
    let w = base.stack(states.iter().map(|s| (&s.q[..], &s.qd[..], &s.qdd[..])));
    let mut w = w;
    for mut c in w.column_iter_mut() {
        let norm = c.norm();
        if norm > 0.0 {
            c /= norm;
        }
    }
    let s = w.singular_values();
    let (lo, hi) = (s.min(), s.max());
    if lo > 0.0 {
        hi / lo
    } else {
        f64::INFINITY
    }
}

/// A standard normal draw (Box–Muller).
pub(crate) fn normal(rng: &mut SplitMix64) -> f64 {
    let u1 = rng.uniform((f64::MIN_POSITIVE, 1.0));
    let u2 = rng.uniform((0.0, 1.0));
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// Optimises an excitation for `base` within `limits`; see the module docs.
pub fn optimise(base: &BaseModel<'_>, limits: &TrajectoryLimits, options: &ExcitationOptions) -> Excitation {
    let n = base.dof();
    let mut rng = SplitMix64::new(options.seed);
    let evaluate = |t: &FourierTrajectory| condition_number(base, t, options.samples);
    let fitted = |x: &[f64], template: &FourierTrajectory| {
        let mut t = template.with_coefficients(x);
        t.fit_into(limits);
        t
    };
    let mut starts = Vec::new();
    for k in 0..options.starts.max(1) {
        let seed = options
            .seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(k as u64);
        let mut t = FourierTrajectory::random(n, options.harmonics, options.base_frequency, seed);
        t.fit_into(limits);
        let c = evaluate(&t);
        starts.push((c, t));
    }
    starts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let random_condition_number = starts[starts.len() / 2].0;
    let (mut best_c, mut best) = starts.swap_remove(0);
    let mut evaluations = options.starts.max(1);
    // Coefficients of a fitted trajectory have the scale of the velocity limits.
    let mut sigma = 0.2;
    for _ in 0..options.iterations {
        let x = best.coefficients();
        let scale = x.iter().map(|v| v.abs()).fold(0.0, f64::max).max(1e-9);
        let trial: Vec<f64> = x.iter().map(|v| v + sigma * scale * normal(&mut rng)).collect();
        let t = fitted(&trial, &best);
        let c = evaluate(&t);
        evaluations += 1;
        if c < best_c {
            best_c = c;
            best = t;
            sigma *= 1.5;
        } else {
            sigma *= 1.5f64.powf(-0.25);
        }
        sigma = sigma.clamp(1e-4, 1.0);
    }
    Excitation {
        trajectory: best,
        condition_number: best_c,
        random_condition_number,
        evaluations,
    }
}
