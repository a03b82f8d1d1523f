//! The identified robot as a URDF, for the tools that read URDF (RViz, Gazebo, Drake, `k`),
//! through `dyngen-model`'s export ([`to_urdf_rs`]).
//!
//! URDF holds the inertials and, per joint, `<dynamics damping= friction=>`: viscous and
//! Coulomb friction, as Gazebo reads them (and dyngen's loader, which uses them when the
//! description chooses those columns). It has no element for a joint's armature (reflected
//! rotor inertia) or torque offset, nor for the choice of joint-level columns, the Coulomb
//! smoothing, a gravity other than the default or an end-effector its leaf rule would not
//! pick. Those go into a dyngen YAML wrapper beside the URDF (`<name>.dyngen.yaml`, with
//! `urdf: <name>.urdf`: the export's own [`UrdfExport::yaml_wrapper`]) which loads the URDF as
//! the identified robot; the URDF's header comment says so, and lists the armature and offset
//! of every joint for readers of other tools. Without any of them the URDF alone is the
//! identified robot, and no wrapper is written.

use crate::error::IdentifyError;
use dyngen_model::description::{to_urdf_rs, UrdfExport};
use dyngen_model::model::Model;
use dyngen_model::urdf_rs;
use std::path::{Path, PathBuf};

/// The identified robot as URDF text, and the YAML wrapper that makes it the identified robot
/// when the URDF alone cannot.
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfFiles {
    /// The URDF text, with a header comment.
    pub urdf: String,
    /// The dyngen YAML wrapper, to write at [`wrapper_path`] of the URDF's path; `None` when
    /// the URDF alone loads as the identified robot.
    pub wrapper: Option<String>,
    /// What a reader of the URDF alone misses, one line each (also in its header comment).
    pub missing: Vec<String>,
}

/// Where the wrapper of the URDF written at `urdf` goes: beside it, `<stem>.dyngen.yaml`.
pub fn wrapper_path(urdf: &Path) -> PathBuf {
    let stem = urdf
        .file_stem()
        .map_or_else(|| "robot".into(), |s| s.to_string_lossy().into_owned());
    urdf.with_file_name(format!("{stem}.dyngen.yaml"))
}

/// Text safe inside an XML comment (which may not hold `--`).
fn comment_safe(line: &str) -> String {
    let mut s = line.to_owned();
    while s.contains("--") {
        s = s.replace("--", "- -");
    }
    s
}

/// `model` as the files of [`UrdfFiles`], the URDF to be written at `urdf_path`; `comment`
/// lines go into both files' headers.
pub fn to_urdf(model: &Model, comment: &[String], urdf_path: &Path) -> Result<UrdfFiles, IdentifyError> {
    let export: UrdfExport = to_urdf_rs(model).map_err(|e| IdentifyError::InvalidEstimate(e.to_string()))?;
    let body = urdf_rs::write_to_string(&export.robot)
        .map_err(|e| IdentifyError::InvalidEstimate(format!("cannot write the URDF: {e}")))?;
    let file_name = urdf_path
        .file_name()
        .map_or_else(|| "robot.urdf".into(), |f| f.to_string_lossy().into_owned());
    let wrapper_name = wrapper_path(urdf_path)
        .file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_default();
    let terms = model.joint_terms();
    let mut missing: Vec<String> = Vec::new();
    let chosen = |kind| terms.kinds.contains(&kind);
    use dyngen_model::model::JointTermKind::{Armature, Offset};
    for (kind, what) in [(Armature, "armature"), (Offset, "offset")] {
        if !chosen(kind) {
            continue;
        }
        let values: Vec<String> = model
            .joints()
            .iter()
            .enumerate()
            .map(|(j, joint)| format!("{} {}", joint.name, terms.value(j).get(kind)))
            .collect();
        missing.push(format!("{what} (no URDF element): {}", values.join(", ")));
    }
    if !terms.kinds.is_empty() {
        let kinds: Vec<&str> = terms.kinds.iter().map(|k| k.keyword()).collect();
        let mut line = format!(
            "the joint-level columns [{}] (a URDF alone loads as the rigid-body robot; its <dynamics> \
             damping and friction are the viscous and Coulomb friction)",
            kinds.join(", ")
        );
        if let Some(eps) = terms.coulomb_smoothing {
            line.push_str(&format!(", and Coulomb friction smoothed as tanh(q̇/{eps})"));
        }
        missing.push(line);
    }
    missing.extend(export.warnings.iter().cloned());
    let wrapper = export.needs_wrapper().then(|| {
        let mut text = String::new();
        for line in comment {
            text.push_str(&format!("# {line}\n"));
        }
        text.push_str(&format!(
            "# The identified robot: {file_name} beside this file, with what URDF cannot say.\n"
        ));
        text + &export.yaml_wrapper(&file_name)
    });
    let mut header: Vec<String> = comment.to_vec();
    if wrapper.is_some() {
        header.push(format!(
            "This URDF alone is not the identified robot: {wrapper_name} beside it loads it as that \
             robot. What URDF cannot say:"
        ));
        header.extend(missing.iter().map(|m| format!("- {m}")));
    }
    let comment_block: String = header
        .iter()
        .map(|l| format!("     {}\n", comment_safe(l)))
        .collect();
    let body = body
        .strip_prefix("<?xml version=\"1.0\"?>")
        .or_else(|| body.strip_prefix("<?xml version=\"1.0\" encoding=\"UTF-8\"?>"))
        .unwrap_or(&body)
        .trim_start();
    let urdf = format!("<?xml version=\"1.0\"?>\n<!--\n{comment_block}-->\n{body}\n");
    Ok(UrdfFiles {
        urdf,
        wrapper,
        missing,
    })
}
