//! `dyngen gen`: one description → one generated Rust module, through the build-script
//! [`Builder`] (the same atomic write that never replaces a file dyngen did not write).

use crate::failure::Failure;
use crate::functions::FunctionsArgs;
use crate::loading::{print_diagnostics, LoadingArgs};
use clap::Args;
use dyngen_codegen::generate::WriteOutcome;
use dyngen_codegen::Builder;
use std::io::IsTerminal;
use std::path::PathBuf;

/// Generate the Rust module of a robot description (module name: the output file's stem).
#[derive(Args, Debug)]
pub struct GenArgs {
    /// The robot description (`.yaml` or `.urdf`).
    description: PathBuf,
    /// The Rust file to write, e.g. `src/robot.rs`.
    #[arg(short, long, value_name = "FILE.rs")]
    output: PathBuf,
    /// The generated type's name (default: the module name in CamelCase, `robot` → `Robot`).
    #[arg(long, value_name = "NAME")]
    type_name: Option<String>,
    #[command(flatten)]
    loading: LoadingArgs,
    #[command(flatten)]
    functions: FunctionsArgs,
}

pub fn run(args: GenArgs) -> Result<(), Failure> {
    let regenerate = format!(
        "dyngen gen {} -o {}",
        args.description.display(),
        args.output.display()
    );
    let choices = args.loading.choices(args.functions.functions()?);
    let mut builder = Builder::new(&args.description)
        .output_file(&args.output)
        .cargo_directives(false)
        .regenerate_command(regenerate)
        .choices(choices);
    if let Some(name) = &args.type_name {
        builder = builder.type_name(name);
    }
    // Only for a person watching: in a pipe, a failure stays the one `error:` line.
    if std::io::stderr().is_terminal() {
        eprintln!(
            "generating {} (tracing and emitting take a few seconds)…",
            args.description.display()
        );
    }
    let report = builder.compile_report()?;
    let robot = &report.robot;
    print_diagnostics(&robot.notes, &robot.warnings);
    let state = match report.outcome {
        WriteOutcome::Written => "written",
        WriteOutcome::Unchanged => "unchanged",
    };
    eprintln!(
        "{} → {} ({state}): {}, functions: {}; generated in {:.2} s",
        args.description.display(),
        report.file.display(),
        robot.sizes(),
        robot.functions,
        robot.elapsed.as_secs_f64()
    );
    Ok(())
}
