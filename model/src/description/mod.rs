//! Robot descriptions (URDF, and dyngen's YAML) → [`Model`](crate::model::Model).
//!
//! The pipeline, one file per step:
//! 1. read: `urdf` (XML), `yaml` (both YAML forms) or `import` (a [`urdf_rs::Robot`] in
//!    memory) → a raw link/joint graph (`raw`), with the place of every item (`source_map`,
//!    `yaml_spans`; none in memory) so later checks can point at it;
//! 2. `items`: each link and joint checked on its own (numbers, types, axes, limits, inertias;
//!    `non_physical`: inertias no real body can have, kept, repaired or refused as asked);
//! 3. `tree`: names resolved, one root, no cycles, depth-first joint order;
//! 4. `assemble`: fixed and locked joints welded away, inertias merged, frames placed,
//!    end-effector chosen, contacts resolved against the frames (`contacts`);
//! 5. [`Model::new`](crate::model::Model::new) checks the invariants every algorithm relies on.
//!
//! The user's choices on top of a description (end-effector, frames, locked joints, gravity,
//! snapping, inertias, floating base, joint-level parameters, functions, contacts) are one value,
//! [`Choices`] (`choices`): a YAML file's keys, or the caller's for a bare URDF. `load` runs
//! the pipeline.
//!
//! Modules use only modules listed after them in this order: `export`, `load`, `yaml`,
//! `assemble`, `items`, `non_physical`, `choices`, `contacts`, `joint_parameters`, `tree`, `urdf`, `import`,
//! `yaml_spans`, `near_exact`, `source_map`, `raw`, `error` (no cycle).
//!
//! Nothing here panics on user input, and nothing is silently dropped or guessed: what
//! cannot be modelled exactly (floating joints, a mimic joint whose master is fixed or locked)
//! is an error. Unlocked mimic joints follow their master (`model::Mimic`).
//!
//! The way back, [`to_urdf_rs`] (`export`), writes any [`Model`](crate::model::Model) as a
//! URDF: to view it in urdf-viz or RViz, or to hand it to another tool.

mod assemble;
mod choices;
mod contacts;
mod error;
mod export;
mod import;
mod items;
mod joint_parameters;
mod load;
mod near_exact;
mod non_physical;
mod raw;
mod source_map;
mod tree;
mod urdf;
mod yaml;
mod yaml_spans;

pub use choices::{Choices, CodeShape, FrameReferences, FrameSelection, FrameSpec, NonPhysicalInertia};
pub use contacts::ContactSpec;
pub use error::{DescriptionError, Location};
pub use export::{to_urdf_rs, ExportError, UrdfExport};
pub use joint_parameters::{JointParameters, JointValues};
pub use load::{from_urdf_rs, load, load_urdf_str, load_with, load_yaml_str, Loaded};
