//! `dyngen check`: does a description load, and what does the loader say about it.

use crate::failure::Failure;
use crate::loading::{print_diagnostics, LoadingArgs};
use clap::Args;
use dyngen_codegen::description::load_with;
use std::path::PathBuf;

/// Load a description and print its warnings and notes (exit 1 if it does not load).
#[derive(Args, Debug)]
pub struct CheckArgs {
    /// The robot description (`.yaml` or `.urdf`).
    description: PathBuf,
    /// Fail (exit 1) when the description loads with warnings.
    #[arg(long)]
    deny_warnings: bool,
    #[command(flatten)]
    loading: LoadingArgs,
}

pub fn run(args: CheckArgs) -> Result<(), Failure> {
    let loaded = load_with(&args.description, &args.loading.choices())?;
    print_diagnostics(&loaded.notes, &loaded.warnings);
    let model = &loaded.model;
    eprintln!(
        "{}: loads: {} DOF, end-effector '{}', {} warning(s)",
        args.description.display(),
        model.dof(),
        model.end_effector().name,
        loaded.warnings.len()
    );
    if args.deny_warnings && !loaded.warnings.is_empty() {
        return Err(Failure::from(format!(
            "{}: {} warning(s) and --deny-warnings",
            args.description.display(),
            loaded.warnings.len()
        )));
    }
    Ok(())
}
