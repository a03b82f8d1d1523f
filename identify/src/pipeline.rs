//! The whole identification in one call: data → base parameters with uncertainties → a
//! consistent full θ → an identified description that loads.

use crate::closed_loop::ClosedLoop;
use crate::consistent::{consistent_estimate, misfit_bound, ConsistentEstimate};
use crate::data::Samples;
use crate::delay::DelaySearch;
use crate::describe::to_yaml;
use crate::energy::{estimate_by_energy, estimate_by_momentum, Observation};
use crate::error::IdentifyError;
use crate::estimator::{estimate_torque_form, BaseIdentification, Estimator};
use crate::fixed_point::ClosedLoopEstimate;
use crate::least_squares::BaseEstimate;
use crate::loadable::{loadable, warnings_of};
use crate::objective::Problem;
use crate::observation::{prepare, BaseModel, BaseRegressorSource, Prepared};
use crate::physical_start::physical_start;
use crate::starts::{description_start, least_squares_start};
use crate::streaming::{estimate_streaming, Progress};
use crate::torque_channel::TorqueGains;
use crate::urdf::{to_urdf, UrdfFiles};
use dyngen_model::model::Model;
use std::fmt;
use std::path::Path;

/// Options of [`identify`].
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyOptions {
    /// Cutoff (Hz) of the low-pass filter used when velocities or accelerations are missing.
    pub cutoff: f64,
    /// Samples the filter runs over at once when a file is identified line by line
    /// ([`identify_file`]), besides the overlaps that make the result that of the whole
    /// signal.
    pub stream_window: usize,
    /// The torque form (default), or a form over windows that needs no accelerations.
    pub observation: Observation,
    /// Search a delay of the torques behind the positions of up to this many samples either
    /// way, estimated with the parameters ([`Identification::delay`]); torque form only, on
    /// the whole log (not [`identify_file`]).
    pub max_delay: Option<usize>,
    /// With [`IdentifyOptions::max_delay`]: refine the delay to a fraction of a sample (the
    /// motion interpolated), with its standard deviation.
    pub fractional_delay: bool,
    /// Estimate each joint's torque gain relative to this joint's (an index in joint order),
    /// which is held at 1 ([`Identification::gains`]); torque form only.
    pub torque_gains: Option<usize>,
    /// What fits the base parameters in the torque form.
    pub estimator: Estimator,
    /// The loop the robot was measured in, for IDIM-IV and DIDIM: the law and the reference
    /// it tracked. DIDIM needs it; IDIM-IV without it tracks the measured positions with a
    /// stiff PD.
    pub closed_loop: Option<ClosedLoop>,
}

impl Default for IdentifyOptions {
    fn default() -> Self {
        IdentifyOptions {
            cutoff: crate::differentiate::DEFAULT_CUTOFF_HZ,
            stream_window: 1 << 14,
            observation: Observation::Torque,
            max_delay: None,
            fractional_delay: false,
            torque_gains: None,
            estimator: Estimator::LeastSquares,
            closed_loop: None,
        }
    }
}

/// Which estimate the identified description holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrittenEstimate {
    /// The consistent estimate: physically valid, and the closest to the data such a robot
    /// can be.
    Consistent,
    /// The least squares, each body brought to the nearest physically valid one: written when
    /// no consistent estimate fits the data and this fits it better.
    LeastSquares,
    /// The description identification started from, with the joint terms the least squares
    /// determine alone: written only if neither estimate would load (a bug).
    Description,
}

impl fmt::Display for WrittenEstimate {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            WrittenEstimate::Consistent => "the consistent estimate",
            WrittenEstimate::LeastSquares => "the least squares made physically valid",
            WrittenEstimate::Description => "the description with the least squares' joint terms",
        })
    }
}

/// What an identification produces.
#[derive(Clone, Debug)]
pub struct Identification {
    /// Least squares on the base parameters, with standard deviations and the noise of each
    /// joint.
    pub base: BaseEstimate,
    /// A physically consistent full θ near it.
    pub consistent: ConsistentEstimate,
    /// The description's model with the identified θ; its YAML ([`Identification::yaml`])
    /// loads.
    pub model: Model,
    /// Which estimate `model` holds.
    pub written: WrittenEstimate,
    /// Samples used (after the filter's end transients, when derivatives were computed, and
    /// those whose torques a delay puts outside the log).
    pub samples_used: usize,
    /// The torques' delay behind the positions, when it was searched
    /// ([`IdentifyOptions::max_delay`]): the estimate pairs each torque with the motion that
    /// many samples earlier.
    pub delay: Option<DelaySearch>,
    /// The torque channels' gains, when they were estimated ([`IdentifyOptions::torque_gains`]).
    pub gains: Option<TorqueGains>,
    /// What fitted the base parameters.
    pub estimator: Estimator,
    /// How IDIM-IV or DIDIM reached its estimate.
    pub closed_loop: Option<ClosedLoopEstimate>,
    pub differentiated: bool,
    /// What the user should know about the data and the estimate: a noise estimate that did
    /// not settle, no consistent estimate compatible with the data, an estimate that would not
    /// load. (The loader's warnings about the identified description come with the text as
    /// written: [`Identification::written`].)
    pub warnings: Vec<String>,
    /// How the estimate was made, where it differs from the usual: a body of the description
    /// that is not physical, and the nearest physical inertia the consistent estimate started
    /// from instead (and took as its prior).
    pub notes: Vec<String>,
}

impl Identification {
    /// The identified robot as dyngen YAML written to `path`, with the loader's warnings about
    /// that text, each naming `path` and its line there. The warnings are not in the text: the
    /// loader says them, with their place, each time the file is loaded.
    pub fn written(&self, source: &str, path: &Path) -> Result<(String, Vec<String>), IdentifyError> {
        let text = self.yaml(source);
        let warnings = warnings_of(&text, path)?;
        Ok((text, warnings))
    }

    /// The identified robot as dyngen YAML: a comment says where it came from, which estimate
    /// it holds, the notes and the warnings about the data.
    pub fn yaml(&self, source: &str) -> String {
        to_yaml(&self.model, &self.comment(source))
    }

    /// The identified robot as a URDF to be written at `urdf_path`, with the dyngen YAML
    /// wrapper that loads it as the identified robot when URDF cannot say everything
    /// (armature, offsets, the joint-level columns: see [`to_urdf`](crate::to_urdf)); both
    /// with [`Identification::yaml`]'s comment.
    pub fn urdf(&self, source: &str, urdf_path: &Path) -> Result<UrdfFiles, IdentifyError> {
        to_urdf(&self.model, &self.comment(source), urdf_path)
    }

    /// The header comment of the identified description's files.
    fn comment(&self, source: &str) -> Vec<String> {
        let mut comment = vec![format!(
            "Identified by `dyngen identify` from {source}: {} samples.",
            self.samples_used
        )];
        match self.written {
            WrittenEstimate::Consistent => comment.extend([
                "Inertial parameters: the physically consistent estimate (log-Cholesky); the directions"
                    .into(),
                "the data cannot see keep the values of the description identification started from.".into(),
            ]),
            WrittenEstimate::LeastSquares => comment.extend([
                "Inertial parameters: the least-squares estimate, each body brought to the nearest".into(),
                "physically valid one: no physically consistent estimate fits the data.".into(),
            ]),
            WrittenEstimate::Description => comment.extend([
                "Inertial parameters: the description's; joint terms: the least squares' where they".into(),
                "are determined alone (neither estimate would load).".into(),
            ]),
        }
        if self.estimator != Estimator::LeastSquares {
            comment.push(format!("Base parameters estimated by {}.", self.estimator));
        }
        if let Some(delay) = &self.delay {
            comment.push(format!(
                "Each torque was paired with the motion {} samples earlier: the torques' delay behind \
                 the positions, estimated with the parameters.",
                delay.samples
            ));
        }
        if let Some(gains) = &self.gains {
            comment.push(format!(
                "The torques were divided by each joint's estimated torque gain (relative to joint {}'s): {}.",
                gains.reference + 1,
                gains
                    .gains
                    .iter()
                    .map(|g| format!("{g:.4}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        comment.extend(self.notes.iter().map(|n| format!("note: {n}")));
        comment.extend(self.warnings.iter().map(|w| format!("warning: {w}")));
        comment
    }
}

/// Identifies `model`'s parameters from `samples` (which must have torques), with the generic
/// numeric regressor.
pub fn identify(
    model: &Model,
    samples: &Samples,
    options: &IdentifyOptions,
) -> Result<Identification, IdentifyError> {
    identify_with(model, &BaseModel::new(model), samples, options)
}

/// [`identify`] with the base regressor from `source`, e.g. a compiled robot
/// ([`Compiled`](crate::Compiled)), which must have the description's base parameters.
pub fn identify_with(
    model: &Model,
    source: &impl BaseRegressorSource,
    samples: &Samples,
    options: &IdentifyOptions,
) -> Result<Identification, IdentifyError> {
    let base_model = matching(model, source)?;
    let fit = fit_base(model, &base_model, source, samples, options)?;
    complete(model, &base_model, fit)
}

/// The base parameters of `model` identified from `samples` (which must have torques), with
/// the generic numeric regressor: [`identify`] without the consistent estimate and the
/// description, for comparisons and studies.
pub fn identify_base(
    model: &Model,
    samples: &Samples,
    options: &IdentifyOptions,
) -> Result<BaseIdentification, IdentifyError> {
    identify_base_with(model, &BaseModel::new(model), samples, options)
}

/// [`identify_base`] with the base regressor from `source` (as [`identify_with`]).
pub fn identify_base_with(
    model: &Model,
    source: &impl BaseRegressorSource,
    samples: &Samples,
    options: &IdentifyOptions,
) -> Result<BaseIdentification, IdentifyError> {
    let base_model = matching(model, source)?;
    fit_base(model, &base_model, source, samples, options)
}

/// [`identify_base_with`] with the description's base parameters, checked.
fn fit_base(
    model: &Model,
    base_model: &BaseModel<'_>,
    source: &impl BaseRegressorSource,
    samples: &Samples,
    options: &IdentifyOptions,
) -> Result<BaseIdentification, IdentifyError> {
    check_options(options)?;
    samples.check(model).map_err(|e| samples.locate(e))?;
    let prepared = prepare(samples, options.cutoff).map_err(|e| samples.locate(e))?;
    Ok(match options.observation {
        Observation::Torque => estimate_torque_form(model, base_model, source, samples, &prepared, options)
            .map_err(|e| samples.locate(e))?,
        Observation::Energy { window } => windowed(
            estimate_by_energy(base_model, samples, &prepared, window).map_err(|e| samples.locate(e))?,
            &prepared,
        ),
        Observation::Momentum { window } => windowed(
            estimate_by_momentum(base_model, samples, &prepared, window).map_err(|e| samples.locate(e))?,
            &prepared,
        ),
    })
}

/// A windowed form's estimate, which knows no torque channel or closed loop.
fn windowed(base: BaseEstimate, prepared: &Prepared) -> BaseIdentification {
    BaseIdentification {
        base,
        samples_used: prepared.q.len(),
        differentiated: prepared.differentiated,
        estimator: Estimator::LeastSquares,
        delay: None,
        gains: None,
        closed_loop: None,
    }
}

/// Options that do not go together, refused before any work.
fn check_options(options: &IdentifyOptions) -> Result<(), IdentifyError> {
    let torque_form = options.observation == Observation::Torque;
    if !torque_form && options.max_delay.is_some() {
        return Err(IdentifyError::data(
            "a delay is searched in the torque form only: the windowed forms integrate the torques",
        ));
    }
    if !torque_form && options.torque_gains.is_some() {
        return Err(IdentifyError::data(
            "torque gains are estimated in the torque form only",
        ));
    }
    if !torque_form && options.estimator != Estimator::LeastSquares {
        return Err(IdentifyError::data(format!(
            "{} fits the torque form: the windowed forms are fitted by least squares",
            options.estimator
        )));
    }
    if options.fractional_delay && options.max_delay.is_none() {
        return Err(IdentifyError::data(
            "a fractional delay refines a delay search: give the largest delay to search (max_delay)",
        ));
    }
    if options.estimator == Estimator::Didim && options.closed_loop.is_none() {
        return Err(IdentifyError::data(
            "DIDIM simulates the loop the torques come from: it needs the control law's gains and \
             the reference they tracked",
        ));
    }
    Ok(())
}

/// [`identify_with`] on the data file `path` read line by line, for logs too long to hold:
/// memory does not grow with the file, the samples and the estimate are those of
/// [`identify_with`] (to the normal equations' accuracy: [`NormalEquations`]), and
/// `progress` hears how far it has come.
///
/// [`NormalEquations`]: crate::NormalEquations
pub fn identify_file(
    model: &Model,
    source: &impl BaseRegressorSource,
    path: &Path,
    options: &IdentifyOptions,
    progress: impl FnMut(&Progress),
) -> Result<Identification, IdentifyError> {
    let base_model = matching(model, source)?;
    if options.observation != Observation::Torque {
        return Err(IdentifyError::data(
            "a file read line by line is identified in the torque form: the windowed forms need \
             the whole log (identify it without streaming)",
        ));
    }
    if options.max_delay.is_some() {
        return Err(IdentifyError::data(
            "a delay is searched on the whole log: identify it without streaming",
        ));
    }
    if options.torque_gains.is_some() {
        return Err(IdentifyError::data(
            "torque gains are estimated on the whole log: identify it without streaming",
        ));
    }
    if options.estimator != Estimator::LeastSquares {
        return Err(IdentifyError::data(format!(
            "{} simulates the robot along the whole log: identify it without streaming",
            options.estimator
        )));
    }
    let streamed = estimate_streaming(model, source, path, options, progress)?;
    let fit = BaseIdentification {
        base: streamed.base,
        samples_used: streamed.samples_used,
        differentiated: streamed.differentiated,
        estimator: Estimator::LeastSquares,
        delay: None,
        gains: None,
        closed_loop: None,
    };
    complete(model, &base_model, fit)
}

/// The description's base parameters, checked to be those of `source`.
fn matching<'m>(model: &'m Model, source: &impl BaseRegressorSource) -> Result<BaseModel<'m>, IdentifyError> {
    refuse_floating_base(model)?;
    let base_model = BaseModel::new(model);
    if source.dof() != model.dof() || source.base_names() != base_model.base.names {
        return Err(IdentifyError::WrongRobot(format!(
            "the compiled robot's base parameters are not those of the description '{}' \
             (regenerate it, or identify with the description alone)",
            model.name()
        )));
    }
    Ok(base_model)
}

/// A floating base's body and base wrench are not in the identification model (its regressor
/// is the fixed tree's): refused rather than identified as if the base were fixed.
pub(crate) fn refuse_floating_base(model: &Model) -> Result<(), IdentifyError> {
    match model.floating_base() {
        Some(_) => Err(IdentifyError::WrongRobot(format!(
            "'{}' has a floating base: identification of floating-base robots is not supported yet",
            model.name()
        ))),
        None => Ok(()),
    }
}

/// The body that carries `frame`. Only a floating base carries frames itself, and
/// identification refuses those ([`refuse_floating_base`]).
pub(crate) fn carrier(frame: &dyngen_model::model::Frame) -> usize {
    frame
        .parent
        .expect("identification refuses a floating base, the only one that carries frames itself")
}

/// From the least squares to the identified description.
fn complete(
    model: &Model,
    base_model: &BaseModel<'_>,
    fit: BaseIdentification,
) -> Result<Identification, IdentifyError> {
    let base = fit.base;
    let mut warnings = Vec::new();
    if !base.noise_settled {
        warnings.push(format!(
            "the torque noise estimate did not settle in {} re-estimates: the standard deviations \
             assume the last one",
            base.noise_iterations
        ));
    }
    // The consistent estimate's starts and prior need physical bodies; the least squares
    // above do not.
    let (start, notes) = physical_start(model);
    let problem = Problem::new(&start, &base_model.base, &base);
    let consistent = consistent_estimate(&problem, &base);
    let b = base.theta_b.len();
    // The description written: the consistent estimate when it fits the data; else whichever
    // fits better of it and the least squares made physically valid body by body; the
    // description (with the least squares' joint terms) if neither loads.
    let mut candidates = vec![(WrittenEstimate::Consistent, consistent.theta.clone())];
    if !consistent.compatible {
        warnings.push(format!(
            "no physically consistent parameters fit the data: the closest found has a whitened \
             misfit of {:.1} for {b} base parameters (noise explains up to {:.1}); check the data \
             (units, torque signs, time alignment) and the description's kinematics and joint terms",
            consistent.misfit,
            misfit_bound(b)
        ));
        if let Some(theta) = least_squares_start(&problem) {
            let projected = problem.consistent_point(&theta);
            let least_squares = (WrittenEstimate::LeastSquares, projected);
            if problem.misfit(&least_squares.1) < consistent.misfit {
                candidates.insert(0, least_squares);
            } else {
                candidates.push(least_squares);
            }
        }
    }
    let description = problem.consistent_point(&description_start(&problem, &base));
    candidates.push((WrittenEstimate::Description, description));
    let mut refused = Vec::new();
    for (written, theta) in candidates {
        match loadable(model, &theta) {
            Ok(identified) => {
                warnings.extend(refused.iter().map(|(what, why)| {
                    format!("{what} would not load ({why}): the description written holds {written}")
                }));
                return Ok(Identification {
                    base,
                    consistent,
                    model: identified,
                    written,
                    samples_used: fit.samples_used,
                    delay: fit.delay,
                    gains: fit.gains,
                    estimator: fit.estimator,
                    closed_loop: fit.closed_loop,
                    differentiated: fit.differentiated,
                    warnings,
                    notes,
                });
            }
            Err(why) => refused.push((written, why)),
        }
    }
    let reasons: Vec<String> = refused
        .iter()
        .map(|(what, why)| format!("{what}: {why}"))
        .collect();
    Err(IdentifyError::InvalidEstimate(reasons.join("; ")))
}
