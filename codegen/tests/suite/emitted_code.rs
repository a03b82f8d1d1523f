//! The code the generator emits for a committed robot description, for tests that read it.

use dyngen_codegen::description::load;
use dyngen_codegen::internals::generate::{emit, trace, type_name, Provenance};
use std::path::Path;

/// The module emitted for `robot` (a path from the repository root).
pub fn emitted(robot: &str) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let model = load(&root.join(robot)).unwrap().model;
    let provenance = Provenance {
        source: robot.into(),
        source_hash: "0".into(),
        regenerate: "none".into(),
        type_name: type_name(model.name()),
    };
    emit(&model, &trace(&model), &provenance)
}
