//! `dyngen excite`: an optimised excitation trajectory for identification, as a CSV of
//! positions, velocities and accelerations within the description's limits, and with frames
//! kept in boxes or above planes (`--box`, `--above`) when asked.

use crate::failure::Failure;
use crate::identifiable::load_identifiable;
use crate::loading::LoadingArgs;
use clap::Args;
use dyngen_identify::{
    optimise_within, to_csv, BaseModel, ExcitationOptions, Region, Samples, TrajectoryLimits, Workspace,
    WorkspaceConstraint, DEFAULT_ACCELERATION_PER_VELOCITY,
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
    /// Keep a frame inside an axis-aligned box of the base frame along the whole trajectory,
    /// in metres; without FRAME, the end-effector. Repeatable.
    #[arg(
        long = "box",
        value_name = "[FRAME:]XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX",
        allow_hyphen_values = true,
        value_parser = parse_box
    )]
    boxes: Vec<FrameRegion>,
    /// Keep a frame on the side of a plane its normal points to, `n·p ≥ d` in the base frame
    /// (`0,0,1,0.3`: at least 0.3 m above the base's xy plane); without FRAME, the
    /// end-effector. Repeatable.
    #[arg(
        long,
        value_name = "[FRAME:]NX,NY,NZ,D",
        allow_hyphen_values = true,
        value_parser = parse_above
    )]
    above: Vec<FrameRegion>,
    #[command(flatten)]
    loading: LoadingArgs,
}

/// A region and the frame it is for (`None`: the end-effector).
#[derive(Clone, Debug)]
struct FrameRegion {
    frame: Option<String>,
    region: Region,
}

/// `[FRAME:]x1,x2,…` with `count` numbers.
fn frame_and_numbers(text: &str, count: usize) -> Result<(Option<String>, Vec<f64>), String> {
    let (frame, numbers) = match text.rsplit_once(':') {
        Some((frame, numbers)) if !frame.is_empty() => (Some(frame.to_string()), numbers),
        Some((_, _)) => return Err("the frame name before ':' is empty".to_string()),
        None => (None, text),
    };
    let values = numbers
        .split(',')
        .map(|v| {
            v.trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("'{}' is not a finite number", v.trim()))
        })
        .collect::<Result<Vec<f64>, String>>()?;
    if values.len() != count {
        return Err(format!(
            "expected {count} comma-separated numbers, got {}",
            values.len()
        ));
    }
    Ok((frame, values))
}

fn parse_box(text: &str) -> Result<FrameRegion, String> {
    let (frame, v) = frame_and_numbers(text, 6)?;
    Ok(FrameRegion {
        frame,
        region: Region::between([v[0], v[1], v[2]], [v[3], v[4], v[5]]),
    })
}

fn parse_above(text: &str) -> Result<FrameRegion, String> {
    let (frame, v) = frame_and_numbers(text, 4)?;
    Ok(FrameRegion {
        frame,
        region: Region::above([v[0], v[1], v[2]], v[3]),
    })
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
    let constraints: Vec<WorkspaceConstraint> = args
        .boxes
        .iter()
        .chain(&args.above)
        .map(|r| WorkspaceConstraint {
            frame: r
                .frame
                .clone()
                .unwrap_or_else(|| model.end_effector().name.clone()),
            region: r.region.clone(),
        })
        .collect();
    let workspace = Workspace::new(&model, &constraints)?;
    let start = Instant::now();
    let excitation = optimise_within(&base, &limits, &workspace, &options)?;
    println!(
        "{}: {} base parameters; condition number {:.1} (random coefficients within the same limits: {:.1}), {} evaluations in {:.1} s",
        model.name(),
        base.base_count(),
        excitation.condition_number,
        excitation.random_condition_number,
        excitation.evaluations,
        start.elapsed().as_secs_f64()
    );
    if let Some(check) = &excitation.workspace {
        println!(
            "workspace: every frame inside its region at every time (closest: '{}', {:.4} m at t = {:.3} s; \
             proven on {} times with a frame speed bound of {:.2} m/s)",
            check.frame, check.smallest_margin, check.time, check.evaluations, check.speed_bound
        );
    }
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
