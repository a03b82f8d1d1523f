//! Robot descriptions (URDF, and dyngen's YAML) → [`Model`].
//!
//! The pipeline, one file per step:
//! 1. read: `urdf` (XML), `yaml` (both YAML forms) or `import` (a [`urdf_rs::Robot`] in
//!    memory) → a raw link/joint graph (`raw`), with the place of every item (`source_map`,
//!    `yaml_spans`; none in memory) so later checks can point at it;
//! 2. `items`: each link and joint checked on its own (numbers, types, axes, limits, inertias;
//!    `non_physical`: inertias no real body can have, kept, repaired or refused as asked);
//! 3. `tree`: names resolved, one root, no cycles, depth-first joint order;
//! 4. `assemble`: fixed and locked joints welded away, inertias merged, frames placed,
//!    end-effector chosen;
//! 5. [`Model::new`] checks the invariants every algorithm relies on.
//!
//! Nothing here panics on user input, and nothing is silently dropped or guessed: what
//! cannot be modelled exactly (floating joints, a mimic joint whose master is fixed or locked)
//! is an error. Unlocked mimic joints follow their master (`model::Mimic`).
//!
//! The way back, [`to_urdf_rs`] (`export`), writes any [`Model`] as a URDF: to view it in
//! urdf-viz or RViz, or to hand it to another tool.

mod assemble;
mod error;
mod export;
mod import;
mod items;
mod joint_parameters;
mod near_exact;
mod non_physical;
mod options;
mod raw;
mod source_map;
mod tree;
mod urdf;
mod yaml;
mod yaml_spans;

pub use error::{DescriptionError, Location};
pub use export::{to_urdf_rs, ExportError, UrdfExport};
pub use options::{FrameSelection, FrameSpec, NonPhysicalInertia, UrdfOptions};

use crate::model::Model;
use options::Settings;
use raw::RawRobot;
use source_map::{link_path, SourceMap};
use std::path::{Path, PathBuf};

/// A description turned into a model, with what the user should know about it.
#[derive(Clone, Debug)]
pub struct Loaded {
    pub model: Model,
    /// Every file read (the YAML and the URDF it points to), for `cargo:rerun-if-changed`.
    pub sources: Vec<PathBuf>,
    /// Suspicious but legal values, e.g. `link 'x': zero mass and no children`.
    pub warnings: Vec<String>,
    /// Informational, e.g. `no end-effector given: using leaf link 'tool0' (...)`.
    pub notes: Vec<String>,
    /// The groups of functions the description chooses (`functions:`); `None`: it leaves the
    /// choice to the generator's default.
    pub functions: Option<crate::Functions>,
}

/// Warnings and notes gathered along the way, already formatted like errors.
#[derive(Debug, Default)]
pub(crate) struct Diagnostics {
    pub warnings: Vec<String>,
    pub notes: Vec<String>,
}

/// Loads a description file, by extension: `.yaml`/`.yml` (dyngen YAML) or `.urdf`/`.xml`
/// (URDF with default [`UrdfOptions`]).
pub fn load(path: &Path) -> Result<Loaded, DescriptionError> {
    load_with(path, &UrdfOptions::default())
}

/// [`load`], with `urdf` the choices for a bare URDF file. A YAML description states its own
/// choices, so non-default `urdf` options with a YAML file are an error (never ignored).
pub fn load_with(path: &Path, urdf: &UrdfOptions) -> Result<Loaded, DescriptionError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    let is_yaml = match ext.as_deref() {
        Some("yaml" | "yml") => true,
        Some("urdf" | "xml") => false,
        Some("xacro") => {
            return Err(DescriptionError::new(
                path,
                "a xacro file: expand it first (`xacro robot.urdf.xacro > robot.urdf`) and load the URDF",
            ))
        }
        _ => {
            return Err(DescriptionError::new(
                path,
                "unknown file type: expected .yaml/.yml (dyngen YAML) or .urdf/.xml (URDF)",
            ))
        }
    };
    let text =
        read_regular_file(path).map_err(|e| DescriptionError::new(path, format!("cannot read file: {e}")))?;
    let mut loaded = if is_yaml {
        if *urdf != UrdfOptions::default() {
            return Err(DescriptionError::new(
                path,
                "URDF options were given for a YAML description: set them in the YAML \
                 (`snap_angles:`, `inertia:`, `end_effector:`, `frames:`, `locked_joints:`, `gravity:`, `floating_base:`)",
            ));
        }
        load_yaml_str(&text, path)?
    } else {
        load_urdf_str(&text, path, urdf)?
    };
    loaded.sources.insert(0, path.to_path_buf());
    Ok(loaded)
}

/// Reads a description: a regular file only (`/dev/zero` or a FIFO would never end), UTF-8.
fn read_regular_file(path: &Path) -> std::io::Result<String> {
    if !std::fs::metadata(path)?.is_file() {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "not a regular file",
        ));
    }
    std::fs::read_to_string(path)
}

/// Loads URDF text. `file` names the text in messages. `sources` is empty: nothing was read.
pub fn load_urdf_str(text: &str, file: &Path, options: &UrdfOptions) -> Result<Loaded, DescriptionError> {
    let (robot, map) = urdf::read(text, file)?;
    build_bare_urdf(&robot, &map, options)
}

/// A URDF without a YAML wrapper (a file, or a `urdf_rs::Robot`): the user's choices come
/// from `options`, and nothing else was read.
fn build_bare_urdf(
    robot: &RawRobot,
    map: &SourceMap,
    options: &UrdfOptions,
) -> Result<Loaded, DescriptionError> {
    let settings = Settings {
        name: None,
        gravity: options.gravity,
        end_effector: options.end_effector.clone(),
        frames: options.frames.clone(),
        locked_joints: options.locked_joints.clone(),
        joint_parameters: None,
        snap_angles: options.snap_angles,
        inertia: options.inertia,
        floating_base: options.floating_base,
        map,
    };
    build(robot, map, &settings, Vec::new())
}

/// Turns a [`urdf_rs::Robot`] (what `k`, `urdf-viz` and openrr hold) into a model, with the same
/// checks, rules and messages as a URDF file.
///
/// There is no file, so messages name the robot instead (`<urdf_rs::Robot 'panda'>: joint
/// 'j2': ...`) and have no line and column; `sources` is empty. urdf-rs stores a missing
/// `<inertial>` and a missing `<limit>` as zeros, so an all-zero inertial is a massless link
/// and an all-zero limit is no limit (a revolute or prismatic joint then needs one, as in a
/// file). URDF 1.2's infinite "no limit" is rejected like any non-finite number. What dyngen
/// does not model (damping and friction, acceleration, deceleration and jerk limits) is
/// reported in `notes`; visuals, collisions and the like are skipped, as in a file.
///
/// ```
/// use dyngen_model::description::{from_urdf_rs, UrdfOptions};
/// let robot = dyngen_model::urdf_rs::read_from_string(
///     r#"<robot name="pendulum">
///          <link name="base"/>
///          <link name="arm"><inertial><origin xyz="0 0 -0.5"/><mass value="1"/>
///            <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial></link>
///          <joint name="swing" type="continuous"><parent link="base"/><child link="arm"/>
///            <axis xyz="0 1 0"/></joint>
///        </robot>"#,
/// )
/// .unwrap();
/// let loaded = from_urdf_rs(&robot, &UrdfOptions::default()).unwrap();
/// assert_eq!(loaded.model.dof(), 1);
/// assert_eq!(loaded.model.end_effector().name, "arm");
/// ```
pub fn from_urdf_rs(robot: &urdf_rs::Robot, options: &UrdfOptions) -> Result<Loaded, DescriptionError> {
    let (raw, notes) = import::read(robot)?;
    let map = SourceMap::new(&import::place(robot));
    let mut loaded = build_bare_urdf(&raw, &map, options)?;
    loaded.notes.extend(notes);
    Ok(loaded)
}

/// Loads dyngen YAML text (either form). `file` names the text in messages, and a `urdf:`
/// path is relative to its directory. `sources` lists the URDF read, if any (not `file`).
pub fn load_yaml_str(text: &str, file: &Path) -> Result<Loaded, DescriptionError> {
    let parsed = yaml::parse(text, file)?;
    let functions = parsed.functions()?;
    let mut loaded = build(
        &parsed.robot,
        &parsed.robot_map,
        &parsed.settings(),
        parsed.read.clone(),
    )?;
    loaded.functions = functions;
    Ok(loaded)
}

/// Steps 2–5 of the pipeline (see the module docs).
fn build(
    robot: &RawRobot,
    robot_map: &SourceMap,
    settings: &Settings<'_>,
    sources: Vec<PathBuf>,
) -> Result<Loaded, DescriptionError> {
    let mut diags = Diagnostics::default();
    let snap = settings.snap()?;
    let links = items::check_links(&robot.links, robot_map, snap, settings.inertia, &mut diags)?;
    let joints = items::check_joints(&robot.joints, robot_map, snap, &mut diags)?;
    let topo = tree::topology(robot, robot_map)?;
    let checked = assemble::Checked {
        raw: robot,
        robot_map,
        links: &links.inertias,
        non_physical: &links.non_physical,
        joints: &joints,
        topo: &topo,
    };
    let model = assemble::assemble(&checked, settings, &mut diags)?;

    for w in model.warnings() {
        let body = match &w {
            crate::model::Warning::MasslessLeaf { body, .. }
            | crate::model::Warning::MasslessBody { body, .. } => body,
        };
        let path = topo
            .link_by_name
            .get(body)
            .map(|&l| link_path(l))
            .unwrap_or_default();
        diags
            .warnings
            .push(robot_map.diagnostic(&path, None, &w.to_string()));
    }
    Ok(Loaded {
        model,
        sources,
        warnings: diags.warnings,
        notes: diags.notes,
        functions: None,
    })
}
