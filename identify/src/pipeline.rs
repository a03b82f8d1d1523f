//! The whole identification in one call: data → base parameters with uncertainties → a
//! consistent full θ → an identified description.

use crate::consistent::{consistent_estimate, ConsistentEstimate};
use crate::data::Samples;
use crate::describe::{to_yaml, with_parameters};
use crate::error::IdentifyError;
use crate::least_squares::{estimate, BaseEstimate};
use crate::observation::{prepare, BaseModel, BaseRegressorSource};
use crate::physical_start::physical_start;
use dyngen_codegen::model::Model;

/// Options of [`identify`].
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyOptions {
    /// Cutoff (Hz) of the low-pass filter used when velocities or accelerations are missing.
    pub cutoff: f64,
}

impl Default for IdentifyOptions {
    fn default() -> Self {
        IdentifyOptions {
            cutoff: crate::differentiate::DEFAULT_CUTOFF_HZ,
        }
    }
}

/// What an identification produces.
#[derive(Clone, Debug)]
pub struct Identification {
    /// Least squares on the base parameters, with standard deviations.
    pub base: BaseEstimate,
    /// A physically consistent full θ near it.
    pub consistent: ConsistentEstimate,
    /// The description's model with the consistent θ.
    pub model: Model,
    /// Samples used (after the filter's end transients, when derivatives were computed).
    pub samples_used: usize,
    pub differentiated: bool,
    /// What a person should know about how the estimate was made, e.g. that a body of the
    /// description was not physical and the consistent estimate started from its nearest
    /// physical inertia.
    pub notes: Vec<String>,
}

impl Identification {
    /// The identified robot as dyngen YAML.
    pub fn yaml(&self, source: &str) -> String {
        let mut comment = vec![
            format!(
                "Identified by `dyngen identify` from {source}: {} samples.",
                self.samples_used
            ),
            "Inertial parameters: the physically consistent estimate (log-Cholesky); the directions".into(),
            "the data cannot see keep the values of the description identification started from.".into(),
        ];
        comment.extend(self.notes.iter().map(|note| format!("Note: {note}")));
        to_yaml(&self.model, &comment)
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
    let base_model = BaseModel::new(model);
    if source.dof() != model.dof() || source.base_names() != base_model.base.names {
        return Err(IdentifyError::WrongRobot(format!(
            "the compiled robot's base parameters are not those of the description '{}' \
             (regenerate it, or identify with the description alone)",
            model.name()
        )));
    }
    let prepared = prepare(samples, options.cutoff)?;
    let (w, tau) = prepared.stack(source);
    let base = estimate(&w, &tau, model.dof(), &base_model.base.names)?;
    // The consistent estimate needs a physical start; the least squares above do not.
    let (start, notes) = physical_start(model);
    let consistent = consistent_estimate(&start, &base_model.base, &base);
    // Consistent by construction; an error here would be a bug, said as one.
    let identified = with_parameters(model, &consistent.theta).map_err(IdentifyError::InvalidEstimate)?;
    Ok(Identification {
        base,
        consistent,
        model: identified,
        samples_used: prepared.q.len(),
        differentiated: prepared.differentiated,
        notes,
    })
}
