//! `dyngen excite`: an optimised excitation trajectory for identification, as a CSV of
//! positions, velocities and accelerations within the description's limits.

use crate::failure::Failure;
use crate::identifiable::load_identifiable;
use crate::loading::LoadingArgs;
use clap::Args;
use dyngen_identify::{
    optimise, to_csv, BaseModel, ExcitationOptions, Samples, TrajectoryLimits,
    DEFAULT_ACCELERATION_PER_VELOCITY,
};
use std::path::PathBuf;
use std::time::Instant;

/// Write an excitation trajectory (periodic Fourier series optimised for a well-conditioned
/// base regressor) within the joint limits.
#[derive(Args, Debug)]
pub struct ExciteArgs {
    /// The robot description (`.yaml` or `.urdf`).
    description: PathBuf,
    /// The trajectory CSV to write (time, q, qd, qdd per joint).
    #[arg(short, long, value_name = "trajectory.csv")]
    output: PathBuf,
    /// Length of the trajectory, in seconds.
    #[arg(long, value_name = "S", default_value_t = 30.0)]
    duration: f64,
    /// Sampling rate, in Hz.
    #[arg(long, value_name = "HZ", default_value_t = 500.0)]
    rate: f64,
    /// Base frequency of the Fourier series, in Hz (the trajectory's period is its inverse).
    #[arg(long, value_name = "HZ", default_value_t = ExcitationOptions::default().base_frequency)]
    frequency: f64,
    /// Harmonics per joint.
    #[arg(long, value_name = "L", default_value_t = ExcitationOptions::default().harmonics)]
    harmonics: usize,
    /// Iterations of the condition-number optimisation.
    #[arg(long, value_name = "N", default_value_t = ExcitationOptions::default().iterations)]
    iterations: usize,
    /// Seed of the random starting coefficients.
    #[arg(long, value_name = "S", default_value_t = ExcitationOptions::default().seed)]
    seed: u64,
    /// Acceleration limit of each joint as a multiple of its velocity limit (per second).
    #[arg(long, value_name = "K", default_value_t = DEFAULT_ACCELERATION_PER_VELOCITY)]
    acceleration_per_velocity: f64,
    #[command(flatten)]
    loading: LoadingArgs,
}

pub fn run(args: ExciteArgs) -> Result<(), Failure> {
    let positive = [args.duration, args.rate, args.frequency, args.harmonics as f64];
    if !positive.iter().all(|&v| v > 0.0) {
        return Err(Failure::from(
            "--duration, --rate, --frequency and --harmonics must be positive",
        ));
    }
    let model = load_identifiable(&args.description, &args.loading)?;
    let base = BaseModel::new(&model);
    let limits = TrajectoryLimits::from_model(&model, args.acceleration_per_velocity);
    let options = ExcitationOptions {
        base_frequency: args.frequency,
        harmonics: args.harmonics,
        iterations: args.iterations,
        seed: args.seed,
        ..ExcitationOptions::default()
    };
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
    let count = (args.duration * args.rate).round() as usize;
    let mut samples = Samples {
        qd: Some(Vec::new()),
        qdd: Some(Vec::new()),
        ..Samples::default()
    };
    for k in 0..count {
        let t = k as f64 / args.rate;
        let s = excitation.trajectory.at(t);
        samples.time.push(t);
        samples.q.push(s.q);
        if let (Some(qd), Some(qdd)) = (samples.qd.as_mut(), samples.qdd.as_mut()) {
            qd.push(s.qd);
            qdd.push(s.qdd);
        }
    }
    std::fs::write(&args.output, to_csv(&model, &samples))
        .map_err(|e| Failure::from(format!("{}: cannot write: {e}", args.output.display())))?;
    println!(
        "wrote {} ({count} samples, {} s at {} Hz, period {} s)",
        args.output.display(),
        args.duration,
        args.rate,
        excitation.trajectory.period()
    );
    Ok(())
}
