//! The pipeline of the module docs, run: a description file, text or `urdf_rs::Robot`, and the
//! user's [`Choices`], in; a [`Loaded`] model out.

use super::assemble::{self, Settings};
use super::choices::{chosen_twice, Choices};
use super::error::{DescriptionError, Diagnostics};
use super::raw::RawRobot;
use super::source_map::{link_path, read_regular_file, SourceMap};
use super::{import, items, tree, urdf, yaml};
use crate::model::Model;
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
    /// The choices the model was loaded with: a YAML description's, with those the caller
    /// made on top; the caller's for a bare URDF. Its `functions` are what the generator makes
    /// (`None`: the generator's default).
    pub choices: Choices,
}

/// Loads a description file, by extension: `.yaml`/`.yml` (dyngen YAML) or `.urdf`/`.xml`
/// (URDF), choosing nothing on top of it.
pub fn load(path: &Path) -> Result<Loaded, DescriptionError> {
    load_with(path, &Choices::default())
}

/// [`load`], with the caller's `choices`: all the choices of a bare URDF; for a YAML
/// description, those it does not make itself (a key both choose is an error naming it,
/// never a silent preference).
pub fn load_with(path: &Path, choices: &Choices) -> Result<Loaded, DescriptionError> {
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
    let mut loaded = match is_yaml {
        true => load_yaml_with(&text, path, choices)?,
        false => load_urdf_str(&text, path, choices)?,
    };
    loaded.sources.insert(0, path.to_path_buf());
    Ok(loaded)
}

/// Loads URDF text. `file` names the text in messages. `sources` is empty: nothing was read.
pub fn load_urdf_str(text: &str, file: &Path, choices: &Choices) -> Result<Loaded, DescriptionError> {
    let (robot, map) = urdf::read(text, file)?;
    build_bare_urdf(&robot, &map, choices)
}

/// A URDF without a YAML wrapper (a file, or a `urdf_rs::Robot`): the user's choices are the
/// caller's, and nothing else was read.
fn build_bare_urdf(robot: &RawRobot, map: &SourceMap, choices: &Choices) -> Result<Loaded, DescriptionError> {
    let settings = Settings {
        name: None,
        choices,
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
/// use dyngen_model::description::{from_urdf_rs, Choices};
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
/// let loaded = from_urdf_rs(&robot, &Choices::default()).unwrap();
/// assert_eq!(loaded.model.dof(), 1);
/// assert_eq!(loaded.model.end_effector().name, "arm");
/// ```
pub fn from_urdf_rs(robot: &urdf_rs::Robot, choices: &Choices) -> Result<Loaded, DescriptionError> {
    let (raw, notes) = import::read(robot)?;
    let map = SourceMap::new(&import::place(robot));
    let mut loaded = build_bare_urdf(&raw, &map, choices)?;
    loaded.notes.extend(notes);
    Ok(loaded)
}

/// Loads dyngen YAML text (either form), with the choices it makes. `file` names the text in
/// messages, and a `urdf:` path is relative to its directory. `sources` lists the URDF read,
/// if any (not `file`).
pub fn load_yaml_str(text: &str, file: &Path) -> Result<Loaded, DescriptionError> {
    load_yaml_with(text, file, &Choices::default())
}

/// [`load_yaml_str`], with the caller's choices on top of the file's.
fn load_yaml_with(text: &str, file: &Path, caller: &Choices) -> Result<Loaded, DescriptionError> {
    let parsed = yaml::parse(text, file)?;
    if let Some(key) = caller
        .chosen_keys()
        .into_iter()
        .find(|&key| parsed.written.iter().any(|k| k == key))
    {
        return Err(parsed.yaml_map.key_error(key, chosen_twice(key)));
    }
    let choices = parsed.choices.clone().with(caller.clone());
    let settings = Settings {
        name: parsed.name.as_deref(),
        choices: &choices,
        map: &parsed.yaml_map,
    };
    build(&parsed.robot, &parsed.robot_map, &settings, parsed.read.clone())
}

/// Steps 2–5 of the pipeline (the `description` module docs).
fn build(
    robot: &RawRobot,
    robot_map: &SourceMap,
    settings: &Settings<'_>,
    sources: Vec<PathBuf>,
) -> Result<Loaded, DescriptionError> {
    let mut diags = Diagnostics::default();
    let snap = settings.snap()?;
    let inertia = settings.choices.inertia;
    let links = items::check_links(&robot.links, robot_map, snap, inertia, &mut diags)?;
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
        choices: settings.choices.clone(),
    })
}
