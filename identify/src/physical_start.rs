//! Where the consistent estimate starts when the description is not physical.
//!
//! The consistent estimate (`consistent`) starts from the description's θ and keeps it as the
//! prior for what the data cannot see; its log-Cholesky coordinates exist only for a physical
//! body. A description may be loaded with inertias no real body has (dyngen's default keeps
//! them as written, with a warning), so such bodies are replaced by their nearest physical
//! inertia (`Inertia::repaired`, the loader's `inertia: repair`) for the start, and a note says
//! which and by how much.

use dyngen_model::model::physical_inertia::moments_text;
use dyngen_model::model::{Body, Model};

/// The model identification starts from: `model`, or a copy with every non-physical body
/// repaired; and one note per repaired body.
pub(crate) fn physical_start(model: &Model) -> (Model, Vec<String>) {
    let mut notes = Vec::new();
    let bodies: Vec<Body> = model
        .bodies()
        .iter()
        .map(|body| match body.inertia.defect() {
            None => body.clone(),
            Some(defect) => {
                let repaired = body.inertia.repaired();
                notes.push(format!(
                    "body '{}' of the description: {defect}; the consistent estimate starts from the \
                     nearest physical inertia (principal moments {} → {} kg·m²)",
                    body.name,
                    moments_text(&defect.moments),
                    moments_text(&principal_moments(&repaired.inertia_com))
                ));
                Body {
                    name: body.name.clone(),
                    inertia: repaired,
                }
            }
        })
        .collect();
    if notes.is_empty() {
        return (model.clone(), notes);
    }
    match model.clone().with_bodies(bodies) {
        Ok(start) => (start, notes),
        // Repaired bodies are physical, so this cannot fail; if it did, the description's own
        // values are still a start (log-Cholesky regularises it), and the note says so.
        Err(e) => {
            notes.push(format!(
                "the repaired start was refused ({e}): starting from the description"
            ));
            (model.clone(), notes)
        }
    }
}

fn principal_moments(inertia: &nalgebra::Matrix3<f64>) -> [f64; 3] {
    let e = inertia.symmetric_eigenvalues();
    let mut m = [e[0], e[1], e[2]];
    m.sort_by(f64::total_cmp);
    m
}
