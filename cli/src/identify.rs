//! `dyngen identify`: base parameters with uncertainties, a physically consistent full
//! parameter vector and an identified description, from measured data.

use crate::failure::Failure;
use crate::identifiable::load_identifiable;
use crate::loading::LoadingArgs;
use clap::{Args, ValueEnum};
use dyngen_codegen::description::load;
use dyngen_codegen::model::Model;
use dyngen_identify::{
    identify, identify_file, read_csv, BaseModel, ClosedLoop, ControlLaw, Estimator, Identification,
    IdentifyOptions, Observation, Progress, Reference, WrittenEstimate, DEFAULT_MAX_RELATIVE_STD,
    DEFAULT_WINDOW, DELAY_MARGIN,
};
use dyngen_identify::{wrapper_path, IdentifyError, UrdfFiles};
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Clone, Copy, Debug, ValueEnum)]
enum ObservationArg {
    Torque,
    Momentum,
    Energy,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
enum MethodArg {
    /// Weighted least squares on the measured regressor (IDIM-LS).
    Ls,
    /// Instrumental variables from a simulation of the identified robot (IDIM-IV).
    Iv,
    /// Closed-loop output error (DIDIM).
    Didim,
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
    /// With --estimate-delay: refine the delay to a fraction of a sample.
    #[arg(long, requires = "estimate_delay")]
    fractional_delay: bool,
    /// Estimate each joint's torque gain relative to REFERENCE_JOINT's (default: the first
    /// joint), which is taken as right (torque form, without --stream).
    #[arg(long, value_name = "REFERENCE_JOINT", num_args = 0..=1, default_missing_value = "")]
    estimate_gain: Option<String>,
    /// The estimator: `ls`, weighted least squares; `iv`, instrumental variables from a
    /// simulation of the identified robot in its loop (IDIM-IV; with --gains and --reference,
    /// or tracking the measured positions with a stiff PD); `didim`, the parameters whose
    /// simulated loop reproduces the torques (needs --gains and --reference).
    #[arg(long, value_enum, default_value_t = MethodArg::Ls)]
    method: MethodArg,
    /// The controller's gains: a CSV file (`joint,kp,kd[,ki]`, a line per joint), or
    /// `JOINT=KP,KD[,KI]` once per joint. Its law: τ = kp e + kd ė + ki ∫e, e = q_ref − q.
    #[arg(long, value_name = "FILE|JOINT=KP,KD[,KI]")]
    gains: Vec<String>,
    /// The reference the controller tracked: a CSV with `time` and `q[<joint>]` (and
    /// optionally `qd[<joint>]`), e.g. the excitation `dyngen excite` wrote, on the data's clock.
    #[arg(long, value_name = "reference.csv")]
    reference: Option<PathBuf>,
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
    let estimator = match args.method {
        MethodArg::Ls => Estimator::LeastSquares,
        MethodArg::Iv => Estimator::InstrumentalVariables,
        MethodArg::Didim => Estimator::Didim,
    };
    let torque_gains = match args.estimate_gain.as_deref() {
        None => None,
        Some("") => Some(0),
        Some(name) => Some(
            model
                .joints()
                .iter()
                .position(|j| j.name == name)
                .ok_or_else(|| {
                    let names: Vec<&str> = model.joints().iter().map(|j| j.name.as_str()).collect();
                    Failure::from(format!(
                        "--estimate-gain {name}: unknown joint (the robot's moving joints: {})",
                        names.join(", ")
                    ))
                })?,
        ),
    };
    let options = IdentifyOptions {
        cutoff: args.cutoff,
        observation: match args.observation {
            ObservationArg::Torque => Observation::Torque,
            ObservationArg::Momentum => Observation::Momentum { window: args.window },
            ObservationArg::Energy => Observation::Energy { window: args.window },
        },
        max_delay: args.estimate_delay,
        fractional_delay: args.fractional_delay,
        torque_gains,
        estimator,
        closed_loop: closed_loop(&args, &model, estimator)?,
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
        let seconds = rate.map_or_else(String::new, |r| format!(" ({:.4} s)", d / r));
        let whole = delay.whole();
        let around: Vec<String> = delay
            .criterion
            .iter()
            .filter(|(c, _)| (c - whole).abs() <= 1)
            .map(|(c, v)| format!("{c}: {v:.3}"))
            .collect();
        let margin = delay.log_likelihood_margin();
        let found = match delay.std_dev {
            Some(sd) => format!("{d:.3} ± {sd:.3} samples"),
            None => format!("{d} samples"),
        };
        println!(
            "torque delay: {found}{seconds} behind the positions (searched over ±{}; Σ ln σ_j at {}; \
             ln of the likelihood ratio to the next best whole delay {margin:.1})",
            args.estimate_delay.unwrap_or_default(),
            around.join(", ")
        );
        if delay.std_dev.is_none() && margin < DELAY_MARGIN {
            eprintln!(
                "warning: {}: the torque delay is barely determined (ln of the likelihood ratio to the next \
                 best {margin:.1}, below {DELAY_MARGIN}): it may be off by a sample; the torques change \
                 little over one sample against their noise",
                data_name(&args.data)
            );
        }
    }
    if let Some(gains) = &id.gains {
        println!(
            "torque gain per joint (what its channel reads per N·m, relative to '{}'):",
            model.joints()[gains.reference].name
        );
        for (j, joint) in model.joints().iter().enumerate() {
            if j != gains.reference {
                println!(
                    "  {}: {:.5} (σ {:.2e})",
                    joint.name, gains.gains[j], gains.std_dev[j]
                );
            }
        }
    }
    if let Some(how) = &id.closed_loop {
        if how.tracking_measured {
            println!(
                "{}: no control law given: the robot simulated tracking the measured positions with a stiff PD \
                 (natural frequency {:.1} Hz)",
                id.estimator,
                dyngen_identify::STIFF_PD_SHARE * args.cutoff
            );
        }
        let steps: Vec<String> = how.steps.iter().map(|s| format!("{s:.3}")).collect();
        let rms: Vec<String> = how.position_rms.iter().map(|r| format!("{r:.2e}")).collect();
        println!(
            "{}: converged in {} simulations from {} (largest change per iteration, in σ: {}); simulated \
             positions off the measured by RMS {} (rad or m, per joint)",
            id.estimator,
            how.steps.len(),
            how.started_from,
            steps.join(", "),
            rms.join(", ")
        );
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
    write_description(
        &id.model,
        &args.output,
        &args.description,
        || id.urdf(&data, &args.output),
        || id.written(&data, &args.output),
    )
}

/// The description `model` written at `output`: as URDF (`urdf`'s files, see [`write_urdf`])
/// when the name ends in `.urdf`, else as dyngen YAML (`yaml`'s text); then what the loader
/// says of the files as written, their names and lines, as warnings.
pub fn write_description(
    model: &Model,
    output: &Path,
    description: &Path,
    urdf: impl FnOnce() -> Result<UrdfFiles, IdentifyError>,
    yaml: impl FnOnce() -> Result<(String, Vec<String>), IdentifyError>,
) -> Result<(), Failure> {
    let as_urdf = output.extension().is_some_and(|e| e.eq_ignore_ascii_case("urdf"));
    let loader_warnings = if as_urdf {
        write_urdf(urdf()?, model, output, description)?
    } else {
        let (text, loader_warnings) = yaml()?;
        write(output, &text)?;
        loader_warnings
    };
    for warning in &loader_warnings {
        eprintln!("warning: {warning}");
    }
    Ok(())
}

/// The closed loop of --gains and --reference, checked against the method.
fn closed_loop(
    args: &IdentifyArgs,
    model: &Model,
    estimator: Estimator,
) -> Result<Option<ClosedLoop>, Failure> {
    let given = !args.gains.is_empty() || args.reference.is_some();
    match estimator {
        Estimator::LeastSquares if given => {
            return Err(Failure::from(
                "--gains and --reference are for --method iv and didim: the least squares simulate nothing",
            ))
        }
        Estimator::Didim if args.gains.is_empty() || args.reference.is_none() => {
            return Err(Failure::from(
                "--method didim simulates the loop the torques come from: give the controller's --gains \
                 and the --reference it tracked",
            ))
        }
        _ => {}
    }
    if !given {
        return Ok(None);
    }
    let Some(reference) = &args.reference else {
        return Err(Failure::from(
            "--gains needs --reference: the trajectory the controller tracked",
        ));
    };
    if args.gains.is_empty() {
        return Err(Failure::from(
            "--reference needs --gains: the controller that tracked it",
        ));
    }
    let law = if args.gains.iter().any(|g| g.contains('=')) {
        ControlLaw::from_assignments(&args.gains, model)?
    } else if let [file] = &args.gains[..] {
        ControlLaw::read_csv(Path::new(file), model)?
    } else {
        return Err(Failure::from(
            "--gains: one file, or JOINT=KP,KD[,KI] once per joint",
        ));
    };
    let samples = read_csv(reference, model, false)?;
    Ok(Some(ClosedLoop {
        law,
        reference: Reference::from_samples(&samples)?,
    }))
}

fn write(path: &Path, text: &str) -> Result<(), Failure> {
    std::fs::write(path, text)
        .map_err(|e| Failure::from(format!("{}: cannot write: {e}", path.display())))?;
    println!("wrote {}", path.display());
    Ok(())
}

/// The robot `model` as the URDF `files.urdf` at `output` and, when URDF cannot say
/// everything, its wrapper beside it (never over `description`); loaded back as written
/// (through the wrapper when there is one), which must give `model`'s parameters. Returns the
/// loader's warnings.
pub fn write_urdf(
    files: UrdfFiles,
    model: &Model,
    output: &Path,
    description: &Path,
) -> Result<Vec<String>, Failure> {
    let wrapper = wrapper_path(output);
    if files.wrapper.is_some() && same_file(&wrapper, description) {
        return Err(Failure::from(format!(
            "{}: the URDF's wrapper would be written over the description; choose another -o",
            wrapper.display()
        )));
    }
    write(output, &files.urdf)?;
    let loads = match &files.wrapper {
        Some(text) => {
            write(&wrapper, text)?;
            println!(
                "  {} loads {} as the robot written, with what URDF cannot say:",
                wrapper.display(),
                output.display()
            );
            for line in &files.missing {
                println!("  - {line}");
            }
            wrapper
        }
        None => output.to_path_buf(),
    };
    let loaded = load(&loads)?;
    let (written, identified) = (loaded.model.parameters(), model.parameters());
    let same = written.len() == identified.len()
        && written
            .iter()
            .zip(&identified)
            .all(|(a, b)| (a - b).abs() <= 1e-9 * b.abs().max(1.0));
    if !same {
        return Err(Failure::from(format!(
            "internal error: {} does not load back as the robot written",
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
