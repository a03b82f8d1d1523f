//! `dyngen-identify`: excitation trajectories and identification from the command line.
//!
//! ```text
//! dyngen-identify excite   <description> <trajectory.csv> [--duration S] [--rate HZ] [--frequency HZ]
//!                          [--harmonics L] [--iterations N] [--seed S] [--acceleration-per-velocity K]
//! dyngen-identify identify <description> <data.csv> [--out identified.yaml] [--cutoff HZ]
//! ```
//!
//! A binary of its own rather than an xtask command: identification is for users of a robot,
//! not for developers of this workspace (xtask is the latter's), and a binary can be
//! installed and run anywhere (`cargo install --path identify`).

use dyngen_codegen::description::load;
use dyngen_identify::data::{read_csv, to_csv, Samples};
use dyngen_identify::excitation::{optimise, ExcitationOptions};
use dyngen_identify::fourier::{TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY};
use dyngen_identify::observation::BaseModel;
use dyngen_identify::pipeline::{identify, IdentifyOptions};
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

const USAGE: &str = "usage:
  dyngen-identify excite   <description> <trajectory.csv> [--duration S] [--rate HZ] [--frequency HZ]
                           [--harmonics L] [--iterations N] [--seed S] [--acceleration-per-velocity K]
  dyngen-identify identify <description> <data.csv> [--out identified.yaml] [--cutoff HZ]";

/// Positional arguments and `--name value` options.
struct Args {
    positional: Vec<String>,
    options: Vec<(String, String)>,
}

fn parse(args: &[String]) -> Result<Args, String> {
    let mut out = Args {
        positional: Vec::new(),
        options: Vec::new(),
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if let Some(name) = a.strip_prefix("--") {
            let value = it.next().ok_or_else(|| format!("--{name} needs a value"))?;
            out.options.push((name.to_string(), value.clone()));
        } else {
            out.positional.push(a.clone());
        }
    }
    Ok(out)
}

impl Args {
    fn number<T: std::str::FromStr>(&mut self, name: &str, default: T) -> Result<T, String> {
        match self.options.iter().position(|(n, _)| n == name) {
            None => Ok(default),
            Some(i) => {
                let (_, v) = self.options.remove(i);
                v.parse().map_err(|_| format!("--{name} {v}: not a valid number"))
            }
        }
    }

    fn text(&mut self, name: &str) -> Option<String> {
        let i = self.options.iter().position(|(n, _)| n == name)?;
        Some(self.options.remove(i).1)
    }

    fn finish(&self) -> Result<(), String> {
        match self.options.first() {
            Some((n, _)) => Err(format!("unknown option --{n}")),
            None => Ok(()),
        }
    }
}

fn excite(mut args: Args) -> Result<(), String> {
    let [description, out] = &args.positional[..] else {
        return Err(USAGE.into());
    };
    let (description, out) = (PathBuf::from(description), PathBuf::from(out));
    let duration: f64 = args.number("duration", 30.0)?;
    let rate: f64 = args.number("rate", 500.0)?;
    let defaults = ExcitationOptions::default();
    let options = ExcitationOptions {
        base_frequency: args.number("frequency", defaults.base_frequency)?,
        harmonics: args.number("harmonics", defaults.harmonics)?,
        iterations: args.number("iterations", defaults.iterations)?,
        seed: args.number("seed", defaults.seed)?,
        ..defaults
    };
    let per_velocity = args.number("acceleration-per-velocity", DEFAULT_ACCELERATION_PER_VELOCITY)?;
    args.finish()?;
    if !(duration > 0.0 && rate > 0.0 && options.base_frequency > 0.0 && options.harmonics > 0) {
        return Err("--duration, --rate, --frequency and --harmonics must be positive".into());
    }
    let model = load_without_mimics(&description)?;
    let base = BaseModel::new(&model);
    let limits = TrajectoryLimits::from_model(&model, per_velocity);
    let start = Instant::now();
    let excitation = optimise(&base, &limits, &options);
    println!(
        "{}: {} base parameters; condition number {:.1} (random coefficients within the same limits: {:.1}), {} evaluations in {:.1} s",
        model.name(),
        base.base_count(),
        excitation.condition_number,
        excitation.random_condition_number,
        excitation.evaluations,
        start.elapsed().as_secs_f64()
    );
    let count = (duration * rate).round() as usize;
    let mut samples = Samples {
        qd: Some(Vec::new()),
        qdd: Some(Vec::new()),
        ..Samples::default()
    };
    for k in 0..count {
        let t = k as f64 / rate;
        let s = excitation.trajectory.at(t);
        samples.time.push(t);
        samples.q.push(s.q);
        if let (Some(qd), Some(qdd)) = (samples.qd.as_mut(), samples.qdd.as_mut()) {
            qd.push(s.qd);
            qdd.push(s.qdd);
        }
    }
    std::fs::write(&out, to_csv(&model, &samples)).map_err(|e| format!("{}: {e}", out.display()))?;
    println!(
        "wrote {} ({count} samples, {duration} s at {rate} Hz, period {} s)",
        out.display(),
        excitation.trajectory.period()
    );
    Ok(())
}

fn identify_command(mut args: Args) -> Result<(), String> {
    let [description, data] = &args.positional[..] else {
        return Err(USAGE.into());
    };
    let (description, data) = (PathBuf::from(description), PathBuf::from(data));
    let out = args.text("out").map(PathBuf::from);
    let cutoff = args.number("cutoff", IdentifyOptions::default().cutoff)?;
    args.finish()?;
    let model = load_without_mimics(&description)?;
    if model.joint_terms().kinds.is_empty() {
        eprintln!(
            "note: {} chooses no joint-level columns (joint_parameters.columns): friction and armature are not identified",
            description.display()
        );
    }
    let samples = read_csv(&data, &model, true).map_err(|e| e.to_string())?;
    let start = Instant::now();
    let id = identify(&model, &samples, &IdentifyOptions { cutoff }).map_err(|e| e.to_string())?;
    let elapsed = start.elapsed().as_secs_f64();
    println!(
        "{}: {} samples used{}, {} base parameters, scaled condition number {:.1}, identified in {elapsed:.2} s",
        model.name(),
        id.samples_used,
        if id.differentiated { " (q̇, q̈ by filter and differences)" } else { "" },
        id.base.theta_b.len(),
        id.base.condition_number
    );
    println!("{:>14} {:>14} {:>9}  base parameter", "θ_b", "σ", "σ/|θ_b|");
    for k in 0..id.base.theta_b.len() {
        println!(
            "{:>14.6e} {:>14.3e} {:>8.2}%  {}",
            id.base.theta_b[k],
            id.base.std_dev[k],
            100.0 * id.base.relative_std_dev(k),
            id.base.names[k]
        );
    }
    for (j, joint) in model.joints().iter().enumerate() {
        println!("torque noise of {}: {:.4}", joint.name, id.base.joint_noise[j]);
    }
    println!(
        "consistent estimate: whitened misfit {:.2} for {} base parameters ({} iterations)",
        id.consistent.misfit,
        id.base.theta_b.len(),
        id.consistent.iterations
    );
    if let Some(out) = out {
        let yaml = id.yaml(&data.display().to_string());
        std::fs::write(&out, yaml).map_err(|e| format!("{}: {e}", out.display()))?;
        println!("wrote {}", out.display());
    }
    Ok(())
}

/// The description's model; identification reads and writes one column per moving joint, so a
/// robot with unlocked mimic joints is refused (lock them, or identify the robot without them).
fn load_without_mimics(description: &std::path::Path) -> Result<dyngen_codegen::model::Model, String> {
    let model = load(description).map_err(|e| e.to_string())?.model;
    if model.has_mimics() {
        return Err(format!(
            "{}: identification of robots with mimic joints is not supported; lock them (locked_joints)",
            description.display()
        ));
    }
    Ok(model)
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.split_first() {
        Some((command, rest)) => match (command.as_str(), parse(rest)) {
            (_, Err(e)) => Err(e),
            ("excite", Ok(a)) => excite(a),
            ("identify", Ok(a)) => identify_command(a),
            _ => Err(USAGE.into()),
        },
        None => Err(USAGE.into()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
