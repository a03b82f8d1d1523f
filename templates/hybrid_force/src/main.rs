//! The adaptive hybrid force/position demo (press on a table, circle, the laws side by side)
//! on whatever robot `build.rs` generated, with no code to write:
//!
//! ```sh
//! DYNGEN_ROBOT=/path/to/myrobot.yaml cargo run --release -p dyngen-hybrid-force-template -- \
//!     --task pose --start 0 0.6 0 -1.3 0 1 0 -o target/myrobot
//! ```
//!
//! `--start Q1 … QN` (rad; default: the middle of the description's joint limits),
//! `--task position|tool-axis|pose` (m = 3, 5, 6), `--standard` (all ten parameters per body
//! instead of the base parameters), `-o/--output DIR` (CSV per run). Torques are clamped to the
//! description's effort limits. Exits with 1 if a run diverged (its data is still written) or
//! failed, 2 on a usage error. For plots, noise and the other options, see the `hybrid_force`
//! example of `dyngen-control`.

dyngen_runtime::include_robot!(robot);

use dyngen_control::sim::{start_posture_for, summary_table, write_csv, Demo, DemoOptions};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{Base, Kinematics, Parameterization, Standard};
use robot::{BASE_PARAMETER_COUNT as B, DOF as N, PARAMETER_COUNT as P};
use std::path::PathBuf;
use std::process::ExitCode;

struct Args {
    start: Option<Vec<f64>>,
    task: usize,
    standard: bool,
    output: PathBuf,
}

fn parse(mut args: impl Iterator<Item = String>) -> Result<Args, String> {
    let mut a = Args {
        start: None,
        task: 3,
        standard: false,
        output: PathBuf::from("hybrid_force_out"),
    };
    let mut pending: Option<String> = args.next();
    while let Some(flag) = pending.take() {
        match flag.as_str() {
            "--standard" => a.standard = true,
            "-o" | "--output" => a.output = args.next().ok_or(format!("{flag} needs a directory"))?.into(),
            "--task" => {
                a.task = match args.next().as_deref() {
                    Some("position") => 3,
                    Some("tool-axis") => 5,
                    Some("pose") => 6,
                    other => return Err(format!("--task position|tool-axis|pose, got {other:?}")),
                }
            }
            "--start" => {
                let mut q = Vec::new();
                for v in args.by_ref() {
                    if v.starts_with("--") && v.parse::<f64>().is_err() {
                        pending = Some(v);
                        break;
                    }
                    q.push(
                        v.parse::<f64>()
                            .map_err(|e| format!("--start value '{v}': {e}"))?,
                    );
                }
                a.start = Some(q);
            }
            other => return Err(format!("unknown argument '{other}'")),
        }
        if pending.is_none() {
            pending = args.next();
        }
    }
    Ok(a)
}

fn main() -> ExitCode {
    let args = match parse(std::env::args().skip(1)) {
        Ok(args) => args,
        Err(e) => {
            eprintln!("error: {e}");
            // 2 for a usage error, as clap-based tools report it; 1 stays for a failed run.
            return ExitCode::from(2);
        }
    };
    match run_laws(&args) {
        Ok(true) => ExitCode::SUCCESS,
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The demo's laws with the parameterisation and task dimension the flags chose.
fn run_laws(args: &Args) -> Result<bool, String> {
    let q0 = start_posture_for::<robot::Robot, N>(args.start.as_deref())?;
    match (args.standard, args.task) {
        (false, 3) => run::<Base<robot::Robot, P>, B, 3>(args, q0),
        (false, 5) => run::<Base<robot::Robot, P>, B, 5>(args, q0),
        (false, _) => run::<Base<robot::Robot, P>, B, 6>(args, q0),
        (true, 3) => run::<Standard<robot::Robot>, P, 3>(args, q0),
        (true, 5) => run::<Standard<robot::Robot>, P, 5>(args, q0),
        (true, _) => run::<Standard<robot::Robot>, P, 6>(args, q0),
    }
}

/// The laws of the demo (three; four for a robot with joint friction) on its scenario; `Ok(false)` if one diverged (its data is still written).
fn run<Z: Parameterization<N, M>, const M: usize, const T: usize>(
    args: &Args,
    q0: SVector<f64, N>,
) -> Result<bool, String> {
    let demo = Demo::<Z, N, M, T>::new(DemoOptions::default(), q0).map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&args.output)
        .map_err(|e| format!("cannot create {}: {e}", args.output.display()))?;
    println!(
        "robot {} ({N} DOF, {M} adapted parameters), task dimension {T}, start {:?}",
        <Z::Robot as Kinematics<N>>::NAME,
        q0.as_slice()
    );
    let mut results = Vec::new();
    let mut ok = true;
    for kind in demo.run_kinds() {
        let res = demo.run(kind, &mut |_| {}).map_err(|e| e.to_string())?;
        if let dyngen_control::sim::RunStatus::Diverged { time, reason } = &res.status {
            eprintln!("{} run diverged at t = {time:.3} s: {reason}", kind.label());
            ok = false;
        }
        let path = args.output.join(format!("{}.csv", kind.file_stem()));
        write_csv(&path, &res.samples).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        results.push((kind, res));
    }
    println!("over the last 4 s (t ≥ {:.1} s):", demo.metrics_from());
    print!("{}", summary_table(&results, demo.metrics_from(), T > 3));
    println!("CSV files in {}", args.output.display());
    Ok(ok)
}
