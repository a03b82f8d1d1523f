//! The model identification works on: the description's, refused when it has unlocked mimic
//! joints (identification reads and writes one column per moving joint).

use crate::failure::Failure;
use dyngen_codegen::description::load;
use dyngen_codegen::model::Model;
use std::path::Path;

pub fn load_identifiable(description: &Path) -> Result<Model, Failure> {
    let model = load(description)?.model;
    if model.has_mimics() {
        return Err(Failure::from(format!(
            "{}: identification of robots with mimic joints is not supported; lock them (locked_joints)",
            description.display()
        )));
    }
    Ok(model)
}
