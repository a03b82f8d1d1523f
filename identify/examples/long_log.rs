//! A long log identified line by line, to show what it costs in time and memory.
//!
//! ```sh
//! cargo run --release -p dyngen-identify --example long_log -- write 1000000 target/long_log/1e6.csv
//! cargo run --release -p dyngen-identify --example long_log -- stream target/long_log/1e6.csv
//! cargo run --release -p dyngen-identify --example long_log -- stack target/long_log/1e6.csv
//! ```
//!
//! `write`: `N` samples at 1 kHz of the "real" `robots/arm7_friction.yaml` (1.5 kg payload,
//! joint terms twice the description's) along a Fourier trajectory, positions and torques
//! with 1% noise (as an encoder log has them: no velocities, no accelerations). `stream`:
//! [`identify_file`] with the compiled robot's base regressor; `stack`: [`read_csv`] then
//! [`identify_with`], for comparison. Each prints its time and the process's peak resident
//! memory (`VmHWM`), so run them as separate processes.

use dyngen_generated::arm7_friction::{Arm7Friction, BASE_PARAMETER_COUNT, DOF, PARAMETER_COUNT};
use dyngen_identify::{
    identify_file, identify_with, read_csv, with_payload, Compiled, FourierTrajectory, IdentifyOptions,
    Sample, SampleWriter, Samples, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY,
};
use dyngen_model::description::load;
use dyngen_model::model::{JointTermValues, JointTerms};
use dyngen_runtime::{JointTrig, Regressors, SplitMix64};
use nalgebra::{SVector, Vector3};
use std::path::Path;
use std::time::Instant;

const RATE: f64 = 1000.0;

type Robot = Compiled<Arm7Friction, DOF, PARAMETER_COUNT, BASE_PARAMETER_COUNT>;

/// Peak resident memory of this process (MiB), from `/proc/self/status`.
fn peak_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

fn description() -> dyngen_model::model::Model {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    load(&root.join("robots/arm7_friction.yaml"))
        .unwrap_or_else(|e| panic!("{e}"))
        .model
}

fn write(count: usize, path: &Path) {
    let model = description();
    let terms = model.joint_terms();
    let doubled: Vec<JointTermValues> = terms
        .values
        .iter()
        .map(|v| JointTermValues {
            armature: 2.0 * v.armature,
            viscous: 2.0 * v.viscous,
            coulomb: 2.0 * v.coulomb,
            offset: 2.0 * v.offset,
        })
        .collect();
    let truth = with_payload(&model, 1.5, Vector3::new(0.0, 0.0, 0.05), 0.04)
        .with_joint_terms(JointTerms {
            values: doubled,
            ..terms.clone()
        })
        .expect("physical joint terms");
    let theta = SVector::<f64, PARAMETER_COUNT>::from_vec(truth.parameters());
    let noise: Vec<f64> = model
        .joints()
        .iter()
        .map(|j| 0.01 * j.limits.map_or(1.0, |l| l.effort))
        .collect();
    let limits = TrajectoryLimits::from_model(&model, DEFAULT_ACCELERATION_PER_VELOCITY);
    let mut trajectory = FourierTrajectory::random(DOF, 5, 0.1, 7);
    trajectory.fit_into(&limits);
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).expect("output directory");
    }
    let file = std::fs::File::create(path).expect("create the log");
    let like = Samples {
        tau: Some(Vec::new()),
        ..Samples::default()
    };
    let mut writer = SampleWriter::new(file, &model, &like).expect("write");
    let mut rng = SplitMix64::new(1);
    for k in 0..count {
        let time = k as f64 / RATE;
        let s = trajectory.at(time);
        let q = SVector::<f64, DOF>::from_column_slice(&s.q);
        let (qd, qdd) = (
            SVector::<f64, DOF>::from_column_slice(&s.qd),
            SVector::<f64, DOF>::from_column_slice(&s.qdd),
        );
        let tau = Arm7Friction::torque_regressor(&JointTrig::new(&q), &qd, &qdd) * theta;
        let tau: Vec<f64> = (0..DOF).map(|j| tau[j] + noise[j] * normal(&mut rng)).collect();
        let sample = Sample {
            line: 0,
            time,
            q: s.q,
            qd: None,
            qdd: None,
            tau: Some(tau),
            wrench: None,
        };
        writer.write(&sample).expect("write");
    }
    println!("wrote {count} samples to {}", path.display());
}

/// A standard normal number (Box–Muller).
fn normal(rng: &mut SplitMix64) -> f64 {
    let u1 = rng.uniform((f64::MIN_POSITIVE, 1.0));
    let u2 = rng.uniform((0.0, 1.0));
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: long_log write <samples> <file> | stream <file> | stack <file>";
    match args.iter().map(String::as_str).collect::<Vec<_>>()[..] {
        ["write", count, path] => write(count.parse().expect("a sample count"), Path::new(path)),
        [mode @ ("stream" | "stack"), path] => {
            let model = description();
            let path = Path::new(path);
            let start = Instant::now();
            let options = IdentifyOptions::default();
            let id = if mode == "stream" {
                identify_file(&model, &Robot::default(), path, &options, |_| {})
            } else {
                let samples = read_csv(path, &model, true).unwrap_or_else(|e| panic!("{e}"));
                identify_with(&model, &Robot::default(), &samples, &options)
            }
            .unwrap_or_else(|e| panic!("{e}"));
            let seconds = start.elapsed().as_secs_f64();
            println!(
                "{mode}: {} samples used, {} base parameters, scaled condition number {:.1}, \
                 whitened misfit {:.1}: {seconds:.2} s, peak memory {:.1} MiB",
                id.samples_used,
                id.base.theta_b.len(),
                id.base.condition_number,
                id.consistent.misfit,
                peak_mib().unwrap_or(f64::NAN)
            );
        }
        _ => {
            eprintln!("{usage}");
            std::process::exit(2);
        }
    }
}
