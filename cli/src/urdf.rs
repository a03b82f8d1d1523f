//! `dyngen urdf`: a description as the URDF of the model dyngen generates code for (fixed and
//! locked joints welded away), to view it in urdf-viz or RViz.

use crate::failure::Failure;
use crate::loading::LoadingArgs;
use clap::Args;
use dyngen_codegen::description::{load_with, to_urdf_rs};
use dyngen_codegen::urdf_rs;
use std::path::PathBuf;

/// Write a description's model as URDF, fixed and locked joints welded away (to view it)
///
/// The URDF goes to stdout, or to -o. What URDF cannot say (gravity, a non-default
/// end-effector) goes to stderr, with the YAML wrapper that loads it back as the same model.
#[derive(Args, Debug)]
pub struct UrdfArgs {
    /// The robot description (`.yaml` or `.urdf`).
    description: PathBuf,
    /// Write the URDF to this file instead of stdout.
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    #[command(flatten)]
    loading: LoadingArgs,
}

pub fn run(args: UrdfArgs) -> Result<(), Failure> {
    let loaded = load_with(&args.description, &args.loading.choices())?;
    for warning in &loaded.warnings {
        eprintln!("warning: {warning}");
    }
    let export = to_urdf_rs(&loaded.model)?;
    let text = urdf_rs::write_to_string(&export.robot)
        .map_err(|e| Failure::from(format!("cannot write the URDF: {e}")))?;
    let text = format!(
        "<?xml version=\"1.0\"?>\n<!-- Written by `dyngen urdf` from {}: the model dyngen generates code for \
         (fixed and locked joints welded away). -->\n{text}\n",
        args.description
            .file_name()
            .map(|f| f.to_string_lossy())
            .unwrap_or_default()
    );
    match &args.output {
        None => print!("{text}"),
        Some(path) => {
            std::fs::write(path, &text)
                .map_err(|e| Failure::from(format!("{}: cannot write: {e}", path.display())))?;
            eprintln!(
                "{} → {} ({} DOF, end-effector '{}')",
                args.description.display(),
                path.display(),
                loaded.model.dof(),
                loaded.model.end_effector().name
            );
        }
    }
    for warning in &export.warnings {
        eprintln!("warning: {warning}");
    }
    if export.needs_wrapper() {
        let file = args
            .output
            .as_ref()
            .and_then(|p| p.file_name())
            .map_or_else(|| "robot.urdf".to_owned(), |f| f.to_string_lossy().into_owned());
        eprintln!(
            "to load it as the same model, use this YAML wrapper beside it:\n{}",
            export.yaml_wrapper(&file)
        );
    }
    Ok(())
}
