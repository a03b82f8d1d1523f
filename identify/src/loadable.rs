//! An identified θ is only useful as a description that loads: checked the way a user will use
//! it, by writing the YAML and reading it back with the description loader, and by requiring
//! every body to keep half the consistent estimate's margin, so that rounding in a file
//! written or edited later cannot tip a body over the loader's tolerance.

use crate::consistent::body_margins;
use crate::describe::{to_yaml, with_parameters};
use crate::error::IdentifyError;
use crate::log_cholesky::MARGIN;
use dyngen_model::description::load_yaml_str;
use dyngen_model::model::Model;
use std::path::Path;

/// `model` with parameters `theta`; or why it would not load. (What the loader warns about
/// is said when the file is written, with its name and lines: [`warnings_of`].)
pub(crate) fn loadable(model: &Model, theta: &[f64]) -> Result<Model, String> {
    if let Some(i) = theta.iter().position(|v| !v.is_finite()) {
        return Err(format!("parameter {} is not finite", model.parameter_names()[i]));
    }
    for (b, margin) in body_margins(model, theta).iter().enumerate() {
        if margin.is_nan() || *margin < 0.5 * MARGIN {
            return Err(format!(
                "link '{}': its inertia is within {margin:.1e} of the physically valid limit (at least {:.0e} is kept)",
                model.bodies()[b].name,
                0.5 * MARGIN
            ));
        }
    }
    let identified = with_parameters(model, theta).map_err(|e| e.to_string())?;
    let yaml = to_yaml(&identified, &[]);
    load_yaml_str(&yaml, Path::new("identified.yaml")).map_err(|e| e.to_string())?;
    Ok(identified)
}

/// The loader's warnings about the description `text` written to `path`, each naming `path`
/// and its line there (the text as written, comments included); or the loader's error, as
/// an [`IdentifyError::InvalidEstimate`] (a description [`loadable`] accepted always loads).
pub(crate) fn warnings_of(text: &str, path: &Path) -> Result<Vec<String>, IdentifyError> {
    load_yaml_str(text, path)
        .map(|loaded| loaded.warnings)
        .map_err(|e| IdentifyError::InvalidEstimate(e.to_string()))
}
