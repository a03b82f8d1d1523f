//! `cargo xtask`: the project's developer commands. Thin: argument parsing and reporting only;
//! the work is done by `dyngen-codegen`.

mod bench_render;
mod bench_table;
mod results;
mod sizes;

use clap::{Parser, Subcommand};
use dyngen_codegen::generate::{descriptions_in, generate_into_crate, CrateReport, Mode};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The recorded benchmark results, relative to the workspace root.
const RESULTS: &str = "benchmarks/results.csv";
/// The document whose tables are rendered from them.
const BENCHMARKS: &str = "BENCHMARKS.md";

#[derive(Parser)]
#[command(name = "cargo xtask", about = "dyngen developer commands")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Generate Rust dynamics for robot descriptions into `generated/src/`.
    Gen {
        /// Robot descriptions (`.yaml` or `.urdf`), relative to the current directory or the
        /// workspace root.
        #[arg(required_unless_present = "all")]
        descriptions: Vec<PathBuf>,
        /// Regenerate every description in `robots/`.
        #[arg(long, conflicts_with = "descriptions")]
        all: bool,
        /// Write nothing; exit non-zero if committed generated code is stale.
        #[arg(long)]
        check: bool,
    },
    /// Print the medians of the last `cargo bench --bench dynamics` run as a Markdown table;
    /// with `--record`, also append every generated benchmark of that run to the results file.
    BenchTable {
        /// Criterion's output directory (default: `target/criterion` of the workspace; set it
        /// when the benchmarks ran with another `CARGO_TARGET_DIR`).
        #[arg(long)]
        criterion: Option<PathBuf>,
        /// Append the run's medians to this results file (`benchmarks/results.csv`).
        #[arg(long, requires_all = ["machine", "build"])]
        record: Option<PathBuf>,
        /// The kind of machine the run was on, as the results file names it (e.g. "AMD EPYC Zen
        /// 3 (AVX2)").
        #[arg(long)]
        machine: Option<String>,
        /// How the benchmarks were built.
        #[arg(long, value_enum)]
        build: Option<results::Build>,
        /// The run's date, YYYY-MM-DD (default: today, UTC).
        #[arg(long)]
        date: Option<String>,
    },
    /// Render the tables of BENCHMARKS.md from the latest rows of `benchmarks/results.csv`
    /// (between its `<!-- rendered: MACHINE -->` and `<!-- /rendered -->` markers).
    BenchRender {
        /// Write nothing; exit non-zero if BENCHMARKS.md is not what the results render to.
        #[arg(long)]
        check: bool,
    },
    /// Fuzz the description loaders (`dyngen_testkit::fuzz`), in release, with progress. An
    /// abort without a finding is a stack overflow or a hang: rerun with `--threads 1` and
    /// replay the last case seeds.
    Fuzz {
        /// Number of cases.
        #[arg(long, default_value_t = 1_000_000)]
        cases: u64,
        /// Run seed (each case's seed derives from it and the case number).
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Worker threads.
        #[arg(long, default_value_t = 2)]
        threads: usize,
        /// Replay one case by its case seed (hex, as printed with a finding); writes its input
        /// to `target/fuzz-case-<seed>.txt`.
        #[arg(long)]
        replay: Option<String>,
    },
    /// Print the scale table of TESTING.md (chains to 30 DOF, trees to 20: operation counts,
    /// generation time, code size), in release; the modules go to `target/scale/`.
    Scale,
    /// Print the code-size and compile-time table of docs/performance-notes.md: per group of functions,
    /// chains of 7 to 30 joints and a 32-joint tree, in release; each module compiled alone in
    /// `target/sizes/` (run it on an otherwise idle machine).
    Sizes {
        /// Which modules to compile (`none`: sizes and generation times only).
        #[arg(long, value_enum, default_value_t = sizes::Compile::All)]
        compile: sizes::Compile,
        /// Compile only modules of at most this many MiB (the larger take many minutes each).
        #[arg(long, default_value_t = 16.0)]
        max_mib: f64,
    },
}

/// Timings and long runs belong to optimised code: a debug `cargo xtask` runs itself again
/// with `--release` and returns its exit code (`None`: this is the release build).
fn rerun_in_release() -> Option<ExitCode> {
    if !cfg!(debug_assertions) {
        return None;
    }
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = std::process::Command::new(cargo)
        .current_dir(workspace_root())
        .args(["run", "--release", "--quiet", "--package", "xtask", "--"])
        .args(std::env::args_os().skip(1))
        .status();
    Some(match status {
        Ok(s) if s.success() => ExitCode::SUCCESS,
        Ok(_) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: cannot run cargo: {e}");
            ExitCode::FAILURE
        }
    })
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}

/// A path as the user typed it, else relative to the workspace root (so the command works
/// from any directory of the repository).
fn resolve(path: &Path, root: &Path) -> PathBuf {
    if path.exists() {
        path.to_owned()
    } else {
        root.join(path)
    }
}

/// A path relative to the current directory when it is below it, for shorter messages.
fn shown(path: &Path) -> String {
    let cwd = std::env::current_dir().unwrap_or_default();
    let abs = path.canonicalize().unwrap_or_else(|_| path.to_owned());
    abs.strip_prefix(&cwd).unwrap_or(&abs).display().to_string()
}

fn print_summary(report: &CrateReport, check: bool) {
    for r in &report.robots {
        let state = match (r.outcome, check) {
            (dyngen_codegen::generate::WriteOutcome::Unchanged, _) => "up to date",
            (_, false) => "written",
            (_, true) => "STALE",
        };
        println!(
            "{} → {} ({state})\n  {}, generated in {:.2} s",
            shown(
                r.robot
                    .sources
                    .first()
                    .map(PathBuf::as_path)
                    .unwrap_or(Path::new(""))
            ),
            shown(&r.file),
            r.robot.sizes(),
            r.robot.elapsed.as_secs_f64()
        );
        for note in &r.robot.notes {
            println!("  note: {note}");
        }
        for warning in &r.robot.warnings {
            println!("  warning: {warning}");
        }
        print!("{}", r.robot.op_count_table("  "));
    }
}

/// Prints a table on stdout, or the error on stderr.
fn print_table(table: Result<String, impl std::fmt::Display>) -> ExitCode {
    match table {
        Ok(table) => {
            print!("{table}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `cargo xtask bench-render [--check]`.
fn bench_render(root: &Path, check: bool) -> ExitCode {
    let path = root.join(BENCHMARKS);
    let rendered = results::read(&root.join(RESULTS)).and_then(|rows| {
        let document = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
        let rendered =
            bench_render::render_document(&document, &rows).map_err(|e| format!("{BENCHMARKS}: {e}"))?;
        Ok((document, rendered))
    });
    match rendered {
        Ok((document, rendered)) if document == rendered => {
            println!("{BENCHMARKS} is up to date with {RESULTS}");
            ExitCode::SUCCESS
        }
        Ok(_) if check => {
            eprintln!("error: {BENCHMARKS} is stale (run `cargo xtask bench-render`)");
            ExitCode::FAILURE
        }
        Ok((_, rendered)) => match std::fs::write(&path, rendered) {
            Ok(()) => {
                println!("{BENCHMARKS} rendered from {RESULTS}");
                ExitCode::SUCCESS
            }
            Err(e) => {
                eprintln!("error: {}: {e}", path.display());
                ExitCode::FAILURE
            }
        },
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let root = workspace_root();
    match cli.command {
        Command::BenchTable {
            criterion,
            record,
            machine,
            build,
            date,
        } => {
            let criterion = criterion.unwrap_or_else(|| root.join("target/criterion"));
            if let (Some(file), Some(machine), Some(build)) = (record, machine, build) {
                let date = date.unwrap_or_else(results::today);
                let recorded = results::check_date(&date)
                    .and_then(|()| bench_table::records(&criterion, &machine, build, &date))
                    .and_then(|rows| results::append(&resolve(&file, &root), &rows).map(|()| rows.len()));
                match recorded {
                    Ok(n) => eprintln!("recorded {n} rows in {}", file.display()),
                    Err(e) => {
                        eprintln!("error: {e}");
                        return ExitCode::FAILURE;
                    }
                }
            }
            print_table(bench_table::table(&criterion))
        }
        Command::BenchRender { check } => bench_render(&root, check),
        Command::Fuzz {
            cases,
            seed,
            threads,
            replay,
        } => {
            if let Some(code) = rerun_in_release() {
                return code;
            }
            let replay = match replay.map(|r| u64::from_str_radix(r.trim().trim_start_matches("0x"), 16)) {
                None => None,
                Some(Ok(s)) => Some(s),
                Some(Err(e)) => {
                    eprintln!("error: --replay takes a case seed in hex: {e}");
                    return ExitCode::FAILURE;
                }
            };
            match dyngen_testkit::fuzz::long_run(cases, seed, threads, replay) {
                Ok(()) => ExitCode::SUCCESS,
                Err(findings) => {
                    eprintln!("error: {findings}");
                    ExitCode::FAILURE
                }
            }
        }
        Command::Scale => {
            if let Some(code) = rerun_in_release() {
                return code;
            }
            print!("{}", dyngen_testkit::scale::report());
            ExitCode::SUCCESS
        }
        Command::Sizes { compile, max_mib } => {
            if let Some(code) = rerun_in_release() {
                return code;
            }
            print_table(sizes::report(&root, compile, max_mib))
        }
        Command::Gen {
            descriptions,
            all,
            check,
        } => {
            let list = if all {
                match descriptions_in(&root.join("robots")) {
                    Ok(list) => list,
                    Err(e) => {
                        eprintln!("error: {e}");
                        return ExitCode::FAILURE;
                    }
                }
            } else {
                descriptions.iter().map(|d| resolve(d, &root)).collect()
            };
            let mode = if check { Mode::Check } else { Mode::Write };
            match generate_into_crate(&root, &root.join("generated/src"), &list, mode) {
                Ok(report) => {
                    print_summary(&report, check);
                    let changed = report.changed();
                    if check && !changed.is_empty() {
                        eprintln!("error: stale generated code (run `cargo xtask gen --all`):");
                        for f in changed {
                            eprintln!("  {}", f.display());
                        }
                        return ExitCode::FAILURE;
                    }
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
            }
        }
    }
}
