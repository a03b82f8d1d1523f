//! `dyngen`: the installable command (`cargo install --path cli`). Thin: argument parsing and
//! reporting only; the work is done by `dyngen-codegen` and `dyngen-identify`.
//!
//! Exit status: 0 on success, 1 when the work failed (bad description, bad data, a file that
//! cannot be written), 2 for a command line clap refuses.

mod check;
mod excite;
mod failure;
mod functions;
mod generate;
mod identifiable;
mod identify;
mod info;
mod loading;
mod payload;
mod urdf;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "dyngen",
    version,
    about = "Rigid-body dynamics generated as flat Rust from robot descriptions (URDF or YAML)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    Gen(generate::GenArgs),
    Check(check::CheckArgs),
    Info(info::InfoArgs),
    Urdf(urdf::UrdfArgs),
    Excite(excite::ExciteArgs),
    Identify(identify::IdentifyArgs),
    Payload(payload::PayloadArgs),
}

fn main() -> ExitCode {
    // Usage errors exit with clap's status 2 from inside `parse`.
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Gen(args) => generate::run(args),
        Command::Check(args) => check::run(args),
        Command::Info(args) => info::run(args),
        Command::Urdf(args) => urdf::run(args),
        Command::Excite(args) => excite::run(args),
        Command::Identify(args) => identify::run(args),
        Command::Payload(args) => payload::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(failure) => {
            failure.report();
            ExitCode::FAILURE
        }
    }
}
