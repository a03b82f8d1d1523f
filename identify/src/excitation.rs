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
//!
//! Workspace constraints ([`optimise_within`], [`Workspace`]): a frame kept in a box or above
//! a plane. Fitting into the joint limits alone may carry the frame out, so every candidate is
//! then repaired: if the exact check of [`Workspace::check`] finds it outside, its excursions
//! are shrunk by bisection on one factor `s ∈ [0, 1]` (all coefficients times `s`) to the
//! largest proven inside. This needs a centre posture strictly inside every region, around
//! which the smaller motions shrink: the middle of the joint ranges when it is inside,
//! otherwise the deepest of random postures in the middle halves of the ranges (then in the
//! whole ranges); when none is inside, no excitation exists
//! ([`ExcitationError::Infeasible`]). Every candidate the search compares is thus feasible,
//! and the search itself is unchanged; a tight region costs amplitude, which the condition
//! number shows.

use crate::fourier::{FourierTrajectory, TrajectoryLimits};
use crate::observation::{BaseModel, BaseRegressorSource};
use crate::workspace::{ExcitationError, Workspace, WorkspaceCheck};
use dyngen_model::dynamics::NumericDynamics;
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
    /// The workspace check of the trajectory (none without constraints).
    pub workspace: Option<WorkspaceCheck>,
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

/// Bisections of the excursion factor of a candidate outside its workspace: the factor kept
/// is within 2⁻¹⁰ of the largest feasible one.
const SCALE_BISECTIONS: usize = 10;
/// Random postures tried for a centre inside the workspace.
const CENTRE_SAMPLES: usize = 4000;
/// Grid of the workspace check per harmonic (the refinement adds times where needed): the
/// same density as the fit into the joint limits.
const WORKSPACE_GRID_PER_HARMONIC: usize = 64;

/// Optimises an excitation for `base` within `limits`; see the module docs.
pub fn optimise(base: &BaseModel<'_>, limits: &TrajectoryLimits, options: &ExcitationOptions) -> Excitation {
    optimise_within(base, limits, &Workspace::default(), options)
        .expect("without workspace constraints every fitted trajectory is feasible")
}

/// A posture within the joint limits strictly inside every region of `workspace`; see the
/// module docs.
fn feasible_centre(
    dynamics: &NumericDynamics<'_>,
    workspace: &Workspace,
    limits: &TrajectoryLimits,
    seed: u64,
) -> Result<Vec<f64>, ExcitationError> {
    let middle: Vec<f64> = limits.position.iter().map(|(lo, hi)| 0.5 * (lo + hi)).collect();
    let (margin, frame) = workspace.margin(dynamics, &middle);
    if margin > 0.0 || workspace.is_empty() {
        return Ok(middle);
    }
    let mut rng = SplitMix64::new(seed ^ 0xCE47_4E00_0000_0001);
    let mut best = (margin, frame, middle.clone());
    for spread in [0.5, 1.0] {
        for _ in 0..CENTRE_SAMPLES / 2 {
            let q: Vec<f64> = limits
                .position
                .iter()
                .zip(&middle)
                .map(|((lo, hi), c)| c + spread * 0.5 * (hi - lo) * rng.uniform((-1.0, 1.0)))
                .collect();
            let (m, f) = workspace.margin(dynamics, &q);
            if m > best.0 {
                best = (m, f, q);
            }
        }
        if best.0 > 0.0 {
            return Ok(best.2);
        }
    }
    Err(ExcitationError::Infeasible(format!(
        "no posture within the joint limits puts frame '{}' inside its region (of {CENTRE_SAMPLES} \
         random postures, the best is {:.3} m outside)",
        workspace.frame_name(best.1),
        -best.0
    )))
}

/// [`optimise`] with the frames of `workspace` kept in their regions along the whole
/// trajectory (see the module docs); the error when no posture within the limits satisfies them.
pub fn optimise_within(
    base: &BaseModel<'_>,
    limits: &TrajectoryLimits,
    workspace: &Workspace,
    options: &ExcitationOptions,
) -> Result<Excitation, ExcitationError> {
    let n = base.dof();
    let dynamics = NumericDynamics::new(base.model);
    let centre = feasible_centre(&dynamics, workspace, limits, options.seed)?;
    let grid = WORKSPACE_GRID_PER_HARMONIC * options.harmonics.max(1);
    let mut rng = SplitMix64::new(options.seed);
    let evaluate = |t: &FourierTrajectory| condition_number(base, t, options.samples);
    let inside = |t: &FourierTrajectory| workspace.check(&dynamics, t, grid, true).inside;
    let feasible = |mut t: FourierTrajectory| {
        t.fit_around(limits, &centre);
        if workspace.is_empty() || inside(&t) {
            return t;
        }
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..SCALE_BISECTIONS {
            let s = 0.5 * (lo + hi);
            if inside(&t.scaled(s)) {
                lo = s;
            } else {
                hi = s;
            }
        }
        t.scaled(lo)
    };
    let fitted = |x: &[f64], template: &FourierTrajectory| feasible(template.with_coefficients(x));
    let mut starts = Vec::new();
    for k in 0..options.starts.max(1) {
        let seed = options
            .seed
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(k as u64);
        let t = feasible(FourierTrajectory::random(
            n,
            options.harmonics,
            options.base_frequency,
            seed,
        ));
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
    if !best_c.is_finite() {
        return Err(ExcitationError::Infeasible(
            "every candidate had to shrink to the centre posture to stay inside; widen the regions"
                .to_string(),
        ));
    }
    // The whole check (no early stop), for its report: the search proved the same already.
    let workspace = (!workspace.is_empty()).then(|| workspace.check(&dynamics, &best, grid, false));
    if let Some(check) = workspace.as_ref().filter(|c| !c.inside) {
        return Err(ExcitationError::Infeasible(format!(
            "the optimised trajectory leaves the region of frame '{}' at t = {:.4} s ({:.2e} m outside)",
            check.frame, check.time, -check.smallest_margin
        )));
    }
    Ok(Excitation {
        trajectory: best,
        condition_number: best_c,
        random_condition_number,
        evaluations,
        workspace,
    })
}
