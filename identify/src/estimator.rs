//! The torque form's estimate: the torque channel (a delay, gains) and the estimator that
//! fits the base parameters (least squares, IDIM-IV, DIDIM).
//!
//! Order: the delay is searched with the weighted least squares (a wrong delay costs every
//! estimator alike, and the least squares' bias, a few percent of some parameters, does not
//! move it); the chosen estimator then fits the base parameters, and the gains with them
//! when asked, on the torques paired with the motion at that delay.

use crate::closed_loop::{smoothed, Reference};
use crate::data::Samples;
use crate::delay::{search_delay, DelaySearch};
use crate::error::IdentifyError;
use crate::fixed_point::{
    iterate, standard_of, stiff_law, ClosedLoopEstimate, IterationStart, LoopLaw, SimulatedRows, Simulator,
};
use crate::instrumental::Measured;
use crate::least_squares::{estimate_at_noise, BaseEstimate, Observations};
use crate::observation::{filtered_positions, BaseModel, BaseRegressorSource, Prepared};
use crate::pipeline::IdentifyOptions;
use crate::torque_channel::{fit_torques, Alignment, GainModel, TorqueGains};
use dyngen_model::model::Model;
use nalgebra::{DMatrix, DVector};
use std::fmt;

/// What fits the base parameters to the data in the torque form.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Estimator {
    /// Weighted least squares on the measured regressor (IDIM-LS): the fastest, and exact
    /// when positions are fine and the accelerations clean; biased when the accelerations,
    /// differentiated twice from coarse encoders, are noisy (errors in the variables).
    #[default]
    LeastSquares,
    /// Instrumental variables (IDIM-IV): the least squares' normal equations multiplied by the
    /// base regressor of a simulation of the identified model in the robot's loop, iterated
    /// to a fixed point. Unbiased with noisy accelerations; needs the law and reference, or
    /// tracks the measured positions with a stiff PD.
    InstrumentalVariables,
    /// Closed-loop output error (DIDIM): the parameters whose simulated loop reproduces the
    /// measured torques, by Gauss–Newton with the simulation's sensitivity; needs the torques, the reference and the law, no measured velocity
    /// or acceleration.
    Didim,
}

impl fmt::Display for Estimator {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Estimator::LeastSquares => "weighted least squares",
            Estimator::InstrumentalVariables => "IDIM-IV",
            Estimator::Didim => "DIDIM",
        })
    }
}

/// The natural frequency of the stiff PD that tracks the measured positions when no law is
/// given, as a share of the derivative filter's cutoff: fast enough to follow an excitation
/// (whose band is far below the cutoff), slow enough that the encoder's noise, which the
/// filter passes up to its cutoff, is filtered twice more by the loop.
pub const STIFF_PD_SHARE: f64 = 0.25;

/// The simulated model's Coulomb friction is smoothed over this share of the slowest joint's
/// RMS velocity along the reference, at least, and over enough that its slope at rest is at
/// most [`FRICTION_SLOPE`] times the law's damping `k_d` (a steeper slope would set the
/// integration step): a sign that flips within an integration step makes the simulated motion
/// jump with the estimate, and the iteration never settles (measured: a 6-axis arm's wrist
/// parameters cycling at 0.2–1 σ; smoothed, two to five iterations). The regressor of the
/// simulated motion is smoothed over this share only.
const SMOOTHING_SHARE: f64 = 0.01;
/// The smoothed Coulomb friction's slope at rest, at most, in units of the law's damping.
/// Sixteen: DIDIM fits the simulated loop's torques to the measured ones, so a friction
/// smoothed wider than the robot's is a model error it pays for (measured on the UR5 with a
/// 4 kg tool at 14 bits: a slope of four `k_d` gives a validation error of 0.76% and errors
/// of 1.5 σ, sixteen and forty both 0.51% and 1.0 σ, sixteen at two thirds of forty's cost).
const FRICTION_SLOPE: f64 = 16.0;

/// The base parameters identified from data, with what the torque channel and the estimator
/// found: the first half of an identification, before the consistent estimate and the
/// description ([`identify_base`](crate::identify_base)).
#[derive(Clone, Debug)]
pub struct BaseIdentification {
    /// The base parameters, their standard deviations and each joint's noise.
    pub base: BaseEstimate,
    /// Samples used (after the filter's end transients, when derivatives were computed, and
    /// those whose motion a delay puts outside the log).
    pub samples_used: usize,
    /// Whether velocities and accelerations were computed (filter and differences).
    pub differentiated: bool,
    /// What fitted the base parameters.
    pub estimator: Estimator,
    /// The torques' delay behind the positions, when it was searched.
    pub delay: Option<DelaySearch>,
    /// The torque channels' gains, when they were estimated.
    pub gains: Option<TorqueGains>,
    /// How IDIM-IV or DIDIM reached its estimate.
    pub closed_loop: Option<ClosedLoopEstimate>,
}

/// Fits the torque form of `prepared` (from `samples`) as `options` say.
pub(crate) fn estimate_torque_form<S: BaseRegressorSource>(
    model: &Model,
    base_model: &BaseModel<'_>,
    source: &S,
    samples: &Samples,
    prepared: &Prepared,
    options: &IdentifyOptions,
) -> Result<BaseIdentification, IdentifyError> {
    let n = model.dof();
    let names = &base_model.base.names;
    let b = names.len();
    let joints: Vec<String> = model.joints().iter().map(|j| j.name.clone()).collect();
    let all_torques = samples
        .tau
        .as_ref()
        .ok_or_else(|| IdentifyError::data("the data has no torque columns (tau[<joint>])"))?;
    let gains = match options.torque_gains {
        Some(r) if r >= n => {
            return Err(IdentifyError::data(format!(
                "the gains' reference joint {r} is not one of the robot's {n} joints"
            )))
        }
        Some(reference) => Some(GainModel {
            b,
            joints: joints.clone(),
            reference,
        }),
        None => None,
    };
    let unknowns = match &gains {
        Some(g) => g.names(names),
        None => names.clone(),
    };
    // The equations of the unknowns `x` on regressor rows `m` and torques `tau`: with gains,
    // linearised at `x`.
    let equations = |m: &DMatrix<f64>, tau: &DVector<f64>, x: &[f64]| match &gains {
        Some(g) => g.linearised(m, tau, x),
        None => (m.clone(), tau.clone()),
    };
    // The weighted least squares, each joint's noise estimated or held at the one given.
    let least_squares = |m: &DMatrix<f64>, tau: &DVector<f64>, noise: Option<&[f64]>| match &gains {
        Some(g) => g.least_squares(m, tau, &unknowns, noise),
        None => fit_torques(m, tau, n, &unknowns, noise),
    };
    let (w, _) = prepared.stack(source);
    let len = samples.len();
    let delay = match options.max_delay {
        Some(max) => Some(search_delay(
            &prepared.kept,
            len,
            max,
            options.fractional_delay,
            |alignment, noise| least_squares(&alignment.rows(&w, n), &alignment.torques(all_torques), noise),
        )?),
        None => None,
    };
    let alignment = Alignment::new(
        &prepared.kept,
        len,
        delay.as_ref().map_or(0.0, |d| d.samples),
        |_| true,
    );
    let (measured, torques) = (alignment.rows(&w, n), alignment.torques(all_torques));
    let start = least_squares(&measured, &torques, None)?;
    // The description's values, every gain 1.
    let mut description = base_model.base.base_parameters(&model.parameters());
    description.resize(unknowns.len(), 1.0);
    let simulate = |from: &[f64], rows| simulator(model, base_model, samples, prepared, options, from, rows);
    let (fit, closed_loop) = match options.estimator {
        Estimator::LeastSquares => (start, None),
        Estimator::InstrumentalVariables => {
            let simulator = simulate(&start.theta_b[..b], SimulatedRows::Regressor)?;
            // From the least squares, or from the description (the least squares' gains)
            // when the least squares' model diverges in the loop.
            description[b..].copy_from_slice(&start.theta_b[b..]);
            let starts = vec![
                (IterationStart::LeastSquares, start.theta_b.clone()),
                (IterationStart::Description, description),
            ];
            let noise = start.joint_noise.clone();
            let (fit, how) = iterate("IDIM-IV", starts, noise, b, &simulator, |simulated, x, noise| {
                let (rows, target) = equations(&measured, &torques, x);
                let (instruments, _) = equations(&alignment.rows(&simulated.rows, n), &torques, x);
                Measured::new(&rows, &target, n, &unknowns)?.estimate(&instruments, noise)
            })?;
            (fit, Some(how))
        }
        Estimator::Didim => {
            let simulator = simulate(&start.theta_b[..b], SimulatedRows::TorqueSensitivity)?;
            // From the description, or from the least squares when the description's model
            // diverges in the loop.
            let starts = vec![
                (IterationStart::Description, description),
                (IterationStart::LeastSquares, start.theta_b.clone()),
            ];
            let noise = start.joint_noise.clone();
            let (fit, how) = iterate("DIDIM", starts, noise, b, &simulator, |simulated, x, noise| {
                // The simulated torques about the estimate simulated, `τ_s(θ₀) + J (θ − θ₀)`:
                // `J θ + c`, the Gauss–Newton model of the measured ones.
                let jacobian = alignment.rows(&simulated.rows, n);
                let at = alignment.rows(&simulated.torques, n).column(0).into_owned();
                let offset = at - &jacobian * DVector::from_column_slice(&x[..b]);
                let (rows, target) = match &gains {
                    Some(g) => g.linearised_affine(&jacobian, Some(&offset), &torques, x),
                    None => (jacobian, &torques - offset),
                };
                estimate_at_noise(
                    Observations::Stacked {
                        w: &rows,
                        tau: &target,
                        n,
                    },
                    &unknowns,
                    noise,
                )
            })?;
            (fit, Some(how))
        }
    };
    let (base, gains) = match &gains {
        Some(g) => {
            let (base, gains) = g.split(&fit)?;
            (base, Some(gains))
        }
        None => (fit, None),
    };
    Ok(BaseIdentification {
        base,
        samples_used: alignment.len(),
        differentiated: prepared.differentiated,
        estimator: options.estimator,
        delay,
        gains,
        closed_loop,
    })
}

/// The model in the robot's loop along the log: the law and reference given, from the log's
/// first sample (the measured position, the reference's velocity, the integral at zero); or,
/// without them, a stiff PD ([`STIFF_PD_SHARE`]) on the filtered positions and velocities of
/// the kept samples, from the first. The stiff PD's gains and the friction's smoothing are
/// set once, with the model of `start` (the least squares).
fn simulator<'a>(
    model: &'a Model,
    base_model: &'a BaseModel<'_>,
    samples: &Samples,
    prepared: &'a Prepared,
    options: &IdentifyOptions,
    start: &[f64],
    rows: SimulatedRows,
) -> Result<Simulator<'a>, IdentifyError> {
    let last = prepared.kept[prepared.kept.len() - 1];
    let (law, reference, first, from) = match &options.closed_loop {
        Some(closed) => {
            closed.law.check(model)?;
            let reference = &closed.reference;
            if reference.q.first().map(Vec::len) != Some(model.dof()) || reference.time.len() < 3 {
                return Err(IdentifyError::data(format!(
                    "the reference needs at least 3 samples of the robot's {} joints",
                    model.dof()
                )));
            }
            reference
                .covers(samples.time[0], samples.time[last])
                .map_err(IdentifyError::data)?;
            let (_, qd) = reference.at(samples.time[0]);
            let law = LoopLaw::Given(closed.law.clone());
            (law, reference.clone(), 0, (samples.q[0].clone(), qd))
        }
        None => {
            let omega = 2.0 * std::f64::consts::PI * STIFF_PD_SHARE * options.cutoff;
            let q = filtered_positions(samples, &prepared.kept, options.cutoff)?;
            let law = stiff_law(model, &base_model.base, start, &q[0], omega);
            let reference = Reference {
                time: prepared.kept.iter().map(|&k| samples.time[k]).collect(),
                q,
                qd: prepared.qd.clone(),
            };
            let state = (reference.q[0].clone(), prepared.qd[0].clone());
            (LoopLaw::Stiff(law), reference, prepared.kept[0], state)
        }
    };
    // Coulomb friction smoothed over a hundredth of the slowest joint's RMS velocity, or
    // over more: its slope at rest at most [`FRICTION_SLOPE`] times the law's damping.
    let slowest = (0..model.dof())
        .map(|j| (reference.qd.iter().map(|v| v[j] * v[j]).sum::<f64>() / reference.qd.len() as f64).sqrt())
        .fold(f64::INFINITY, f64::min);
    let theta = standard_of(&base_model.base, start);
    let gains = match &law {
        LoopLaw::Given(law) | LoopLaw::Stiff(law) => &law.gains,
    };
    let coulomb = model.joint_term_values_from(&theta);
    let damped = coulomb
        .iter()
        .zip(gains)
        .map(|(v, g)| v.coulomb.abs() / (FRICTION_SLOPE * g.kd.max(f64::MIN_POSITIVE)))
        .fold(0.0, f64::max);
    let least = (SMOOTHING_SHARE * slowest).max(f64::MIN_POSITIVE);
    let simulated = smoothed(model, least.max(damped));
    Ok(Simulator {
        model: simulated,
        regressor: smoothed(model, least),
        base: &base_model.base,
        law,
        rows,
        reference,
        times: samples.time[first..=last].to_vec(),
        first,
        start: from,
        kept: &prepared.kept,
        measured: &prepared.q,
    })
}
