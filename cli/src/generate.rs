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

/// Generate the Rust module of a robot description (module name: the output file's stem), and
/// with `--c-library` the robot as a C library.
#[derive(Args, Debug)]
pub struct GenArgs {
    /// The robot description (`.yaml` or `.urdf`).
    description: PathBuf,
    /// The Rust file to write, e.g. `src/robot.rs`.
    #[arg(short, long, value_name = "FILE.rs", required_unless_present = "c_library")]
    output: Option<PathBuf>,
    /// Also (or only) write the robot as a C library into this directory: a crate building a
    /// static and a shared library, C headers, a CMake package and a pkg-config file
    /// (docs/c-library.md). The directory must be new, empty or one dyngen wrote.
    #[arg(long, value_name = "DIR")]
    c_library: Option<PathBuf>,
    /// The prefix of the C library's symbols and package (default: the module name, from the
    /// description's file name).
    #[arg(long, value_name = "NAME", requires = "c_library")]
    c_prefix: Option<String>,
    /// The C library's crate depends on dyngen-runtime at this path (a checkout's `runtime/`)
    /// instead of its published version.
    #[arg(long, value_name = "DIR", requires = "c_library")]
    runtime_path: Option<PathBuf>,
    /// The generated type's name (default: the module name in CamelCase, `robot` → `Robot`).
    #[arg(long, value_name = "NAME")]
    type_name: Option<String>,
    #[command(flatten)]
    loading: LoadingArgs,
    #[command(flatten)]
    functions: FunctionsArgs,
}

pub fn run(args: GenArgs) -> Result<(), Failure> {
    let mut regenerate = format!("dyngen gen {}", args.description.display());
    if let Some(output) = &args.output {
        regenerate += &format!(" -o {}", output.display());
    }
    if let Some(dir) = &args.c_library {
        regenerate += &format!(" --c-library {}", dir.display());
    }
    let choices = args.functions.choose(args.loading.choices())?;
    let mut builder = Builder::new(&args.description)
        .cargo_directives(false)
        .regenerate_command(regenerate)
        .choices(choices);
    if let Some(output) = &args.output {
        builder = builder.output_file(output);
    }
    if let Some(name) = &args.type_name {
        builder = builder.type_name(name);
    }
    if let Some(dir) = &args.c_library {
        builder = builder.c_library(dir);
    }
    if let Some(prefix) = &args.c_prefix {
        builder = builder.c_prefix(prefix);
    }
    if let Some(path) = &args.runtime_path {
        builder = builder.c_runtime_path(path);
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
    if let Some(library) = &report.c_library {
        let written = (library.files.iter())
            .filter(|(_, outcome)| *outcome == WriteOutcome::Written)
            .count();
        eprintln!(
            "C library `{}` → {} ({written} of {} files written); build it with CMake \
             (find_package({}_dynamics CONFIG)) or `cargo build --release` there",
            library.prefix,
            library.dir.display(),
            library.files.len(),
            library.prefix
        );
    }
    Ok(())
}
