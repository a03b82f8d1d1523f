//! `dyngen identify`: base parameters with uncertainties, a physically consistent full
//! parameter vector and an identified description, from measured data.

use crate::failure::Failure;
use crate::identifiable::load_identifiable;
use crate::loading::LoadingArgs;
use clap::{Args, ValueEnum};
use dyngen_codegen::description::load;
use dyngen_identify::wrapper_path;
use dyngen_identify::{
    identify, identify_file, read_csv, BaseModel, Identification, IdentifyOptions, Observation, Progress,
    WrittenEstimate, DEFAULT_MAX_RELATIVE_STD, DEFAULT_WINDOW, DELAY_MARGIN,
};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Clone, Copy, Debug, ValueEnum)]
enum ObservationArg {
    Torque,
    Momentum,
    Energy,
}

/// Identify a robot's parameters from a data CSV (time, q and tau per joint; qd and qdd
/// optional) and write the identified description.
#[derive(Args, Debug)]
pub struct IdentifyArgs {
    /// The robot description identification starts from (`.yaml` or `.urdf`).
    description: PathBuf,
    /// The measured data (CSV with columns `time`, `q[<joint>]`, `tau[<joint>]`, optionally
    /// `qd[<joint>]` and `qdd[<joint>]`); `-` reads the standard input.
    data: PathBuf,
    /// The identified description to write: dyngen YAML, or URDF when the name ends in
    /// `.urdf` (then, when URDF cannot say everything, such as armature and torque offsets,
    /// also `<name>.dyngen.yaml` beside it, which loads the URDF as the identified robot).
    #[arg(short, long, value_name = "identified.yaml")]
    output: PathBuf,
    /// Cutoff of the low-pass filter used when velocities or accelerations are missing, in Hz.
    #[arg(long, value_name = "HZ", default_value_t = IdentifyOptions::default().cutoff)]
    cutoff: f64,
    /// Read the data file line by line, for logs too long to hold: memory does not grow with
    /// the file, the estimate is the same (to the normal equations' accuracy), and progress
    /// goes to stderr. A pipe or the standard input is read in one pass.
    #[arg(long)]
    stream: bool,
    /// What is fitted to the torques: `torque`, the inverse dynamics at every sample (needs
    /// accelerations, given or differentiated twice); `momentum`, the Lagrange equations
    /// integrated over windows (no accelerations: better with a coarse encoder); `energy`, the
    /// energy theorem over windows (no accelerations, poorly conditioned).
    #[arg(long, value_enum, default_value_t = ObservationArg::Torque)]
    observation: ObservationArg,
    /// Window of the momentum and energy forms, in s.
    #[arg(long, value_name = "S", default_value_t = DEFAULT_WINDOW)]
    window: f64,
    /// Mark the base parameters whose standard deviation is above this percentage of their
    /// value as poorly determined; when every one is, the identification is refused (nothing
    /// written) unless --force.
    #[arg(long, value_name = "PCT", default_value_t = 100.0 * DEFAULT_MAX_RELATIVE_STD)]
    max_relative_std: f64,
    /// Write the identified description even when the identification cannot be trusted.
    #[arg(long)]
    force: bool,
    /// Search a delay of the torques behind the positions of up to MAX samples either way,
    /// estimated with the parameters (torque form, without --stream).
    #[arg(long, value_name = "MAX")]
    estimate_delay: Option<usize>,
    #[command(flatten)]
    loading: LoadingArgs,
}

pub fn run(args: IdentifyArgs) -> Result<(), Failure> {
    let model = load_identifiable(&args.description, &args.loading)?;
    if model.joint_terms().kinds.is_empty() {
        eprintln!(
            "note: {} chooses no joint-level columns (joint_parameters.columns): friction and armature are not identified",
            args.description.display()
        );
    }
    if !(args.max_relative_std > 0.0 && args.max_relative_std.is_finite()) {
        return Err(Failure::from(format!(
            "--max-relative-std {}: a limit is a positive percentage",
            args.max_relative_std
        )));
    }
    if !(args.window > 0.0 && args.window.is_finite()) {
        return Err(Failure::from(format!(
            "--window {}: a window is a positive number of seconds",
            args.window
        )));
    }
    let options = IdentifyOptions {
        cutoff: args.cutoff,
        observation: match args.observation {
            ObservationArg::Torque => Observation::Torque,
            ObservationArg::Momentum => Observation::Momentum { window: args.window },
            ObservationArg::Energy => Observation::Energy { window: args.window },
        },
        max_delay: args.estimate_delay,
        ..IdentifyOptions::default()
    };
    let start = Instant::now();
    let mut rate = None;
    let id = if args.stream {
        let mut last = Instant::now();
        let progress = |p: &Progress| {
            if last.elapsed().as_secs_f64() >= 2.0 {
                last = Instant::now();
                let what = if p.pass == 1 {
                    "checking the file"
                } else {
                    "accumulating"
                };
                if p.file_bytes > 0 {
                    let share = 100.0 * p.bytes_read as f64 / p.file_bytes as f64;
                    eprintln!("{what}: {share:.0}% ({} samples)", p.samples);
                } else {
                    eprintln!("{what}: {} samples", p.samples);
                }
            }
        };
        identify_file(&model, &BaseModel::new(&model), &args.data, &options, progress)?
    } else {
        let samples = read_csv(&args.data, &model, true)?;
        if samples.len() > 1 {
            rate = Some((samples.len() - 1) as f64 / (samples.time[samples.len() - 1] - samples.time[0]));
        }
        identify(&model, &samples, &options)?
    };
    let elapsed = start.elapsed().as_secs_f64();
    for note in &id.notes {
        eprintln!("note: {}: {note}", args.description.display());
    }
    println!(
        "{}: {} samples used{}, {} base parameters, scaled condition number {:.1}, identified in {elapsed:.2} s",
        model.name(),
        id.samples_used,
        if id.differentiated { " (q̇, q̈ by filter and differences)" } else { "" },
        id.base.theta_b.len(),
        id.base.condition_number
    );
    if let Some(delay) = &id.delay {
        let d = delay.samples;
        let seconds = rate.map_or_else(String::new, |r| format!(" ({:.4} s)", d as f64 / r));
        let around: Vec<String> = delay
            .criterion
            .iter()
            .filter(|(c, _)| (c - d).abs() <= 1)
            .map(|(c, v)| format!("{c}: {v:.3}"))
            .collect();
        let margin = delay.log_likelihood_margin();
        println!(
            "torque delay: {d} samples{seconds} behind the positions (searched over ±{}; Σ ln σ_j at {}; \
             ln of the likelihood ratio to the next best {margin:.1})",
            args.estimate_delay.unwrap_or_default(),
            around.join(", ")
        );
        if margin < DELAY_MARGIN {
            eprintln!(
                "warning: {}: the torque delay is barely determined (ln of the likelihood ratio to the next \
                 best {margin:.1}, below {DELAY_MARGIN}): it may be off by a sample; the torques change \
                 little over one sample against their noise",
                data_name(&args.data)
            );
        }
    }
    let trust = id.base.trust(args.max_relative_std / 100.0);
    print_table(&id, &trust.flagged, args.max_relative_std);
    println!(
        "torque noise per joint (σ, from the weighted residuals; re-estimated {} times{}):",
        id.base.noise_iterations,
        if id.base.noise_settled {
            ", settled"
        } else {
            ", NOT settled"
        }
    );
    for (j, joint) in model.joints().iter().enumerate() {
        println!("  {}: σ = {:.4}", joint.name, id.base.joint_noise[j]);
    }
    println!(
        "consistent estimate: whitened misfit {:.2} for {} base parameters ({}), from {} ({} steps)",
        id.consistent.misfit,
        id.base.theta_b.len(),
        if id.consistent.compatible {
            "compatible with the data"
        } else {
            "NOT compatible with the data"
        },
        id.consistent.start,
        id.consistent.iterations
    );
    if id.written != WrittenEstimate::Consistent {
        println!("the description written holds {}", id.written);
    }
    let data = data_name(&args.data);
    for warning in &id.warnings {
        eprintln!("warning: {data}: {warning}");
    }
    if let Some(why) = &trust.untrusted {
        if !args.force {
            return Err(Failure::from(format!(
                "{data}: the identification cannot be trusted: {why}; nothing written (--force writes it anyway)"
            )));
        }
        eprintln!("warning: {data}: the identification cannot be trusted: {why}; written anyway (--force)");
    }
    let urdf = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("urdf"));
    let loader_warnings = if urdf {
        write_urdf(&id, &data, &args)?
    } else {
        let (text, loader_warnings) = id.written(&data, &args.output)?;
        write(&args.output, &text)?;
        loader_warnings
    };
    // What the loader says of the files as written: their names and lines.
    for warning in &loader_warnings {
        eprintln!("warning: {warning}");
    }
    Ok(())
}

fn write(path: &Path, text: &str) -> Result<(), Failure> {
    std::fs::write(path, text)
        .map_err(|e| Failure::from(format!("{}: cannot write: {e}", path.display())))?;
    println!("wrote {}", path.display());
    Ok(())
}

/// The identified robot as the URDF `args.output` and, when URDF cannot say everything, its
/// wrapper beside it; loaded back as written (through the wrapper when there is one), which
/// must give the identified robot's parameters. Returns the loader's warnings.
fn write_urdf(id: &Identification, data: &str, args: &IdentifyArgs) -> Result<Vec<String>, Failure> {
    let files = id.urdf(data, &args.output)?;
    let wrapper = wrapper_path(&args.output);
    if files.wrapper.is_some() && same_file(&wrapper, &args.description) {
        return Err(Failure::from(format!(
            "{}: the URDF's wrapper would be written over the description; choose another -o",
            wrapper.display()
        )));
    }
    write(&args.output, &files.urdf)?;
    let loads = match &files.wrapper {
        Some(text) => {
            write(&wrapper, text)?;
            println!(
                "  {} loads {} as the identified robot, with what URDF cannot say:",
                wrapper.display(),
                args.output.display()
            );
            for line in &files.missing {
                println!("  - {line}");
            }
            wrapper
        }
        None => args.output.clone(),
    };
    let loaded = load(&loads)?;
    let (written, identified) = (loaded.model.parameters(), id.model.parameters());
    let same = written.len() == identified.len()
        && written
            .iter()
            .zip(&identified)
            .all(|(a, b)| (a - b).abs() <= 1e-9 * b.abs().max(1.0));
    if !same {
        return Err(Failure::from(format!(
            "internal error: {} does not load back as the identified robot",
            loads.display()
        )));
    }
    Ok(loaded.warnings)
}

/// Whether `a` and `b` name one existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    matches!((a.canonicalize(), b.canonicalize()), (Ok(a), Ok(b)) if a == b)
}

/// The data file as messages name it (`<stdin>` for `-`).
pub fn data_name(data: &std::path::Path) -> String {
    match data.to_str() {
        Some("-") => "<stdin>".to_owned(),
        _ => data.display().to_string(),
    }
}

/// The base parameters: the least squares' value, σ and σ relative to the value, the consistent
/// estimate's value and σ (by linearisation at its optimum), a `*` on those whose relative σ
/// is above `limit` percent, and the name.
fn print_table(id: &Identification, flagged: &[usize], limit: f64) {
    let (base, consistent) = (&id.base, &id.consistent);
    println!(
        "{:>14} {:>11} {:>9}  {:>14} {:>11}    base parameter",
        "θ_b", "σ", "%σ", "consistent θ_b", "σ"
    );
    for k in 0..base.theta_b.len() {
        println!(
            "{:>14.6e} {:>11.3e} {:>8.2}%  {:>14.6e} {:>11.3e}  {}  {}",
            base.theta_b[k],
            base.std_dev[k],
            100.0 * base.relative_std_dev(k),
            consistent.theta_b[k],
            consistent.std_dev[k],
            if flagged.contains(&k) { '*' } else { ' ' },
            base.names[k]
        );
    }
    let b = base.theta_b.len();
    if flagged.is_empty() {
        println!("every base parameter has σ within {limit}% of its value");
    } else {
        println!(
            "* {} of {b} base parameters have σ above {limit}% of their value (--max-relative-std): \
             poorly determined by this data",
            flagged.len()
        );
    }
}
