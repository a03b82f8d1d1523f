//! The model identification works on: the description's, refused when it has unlocked mimic
//! joints (identification reads and writes one column per moving joint) or a floating base.

use crate::failure::Failure;
use crate::loading::LoadingArgs;
use dyngen_codegen::description::load_with;
use dyngen_codegen::model::Model;
use std::path::Path;

/// The description's model; its warnings go to stderr (a non-physical inertia among them:
/// identification then starts from the nearest physical one, and says so).
pub fn load_identifiable(description: &Path, loading: &LoadingArgs) -> Result<Model, Failure> {
    let loaded = load_with(description, &loading.choices())?;
    for warning in &loaded.warnings {
        eprintln!("warning: {warning}");
    }
    let model = loaded.model;
    if model.floating_base().is_some() {
        return Err(Failure::from(format!(
            "{}: identification of a floating-base robot is not supported yet (its base body's \
             parameters and base wrench are not in the identification model); identify it on a \
             fixed base",
            description.display()
        )));
    }
    if model.has_mimics() {
        return Err(Failure::from(format!(
            "{}: identification of robots with mimic joints is not supported; lock them (locked_joints)",
            description.display()
        )));
    }
    Ok(model)
}
