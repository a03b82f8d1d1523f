//! Adaptive hybrid force/position control demo: approach a table, press with a smooth ramp to
//! 10 N, then track a 5 cm-radius circle at 0.25 Hz for 8 s while holding the force, with the
//! null space regulating the posture. Three runs side by side: adaptive from θ̂(0) = 0.5·θ_desc
//! (payload unknown), the same with adaptation off, and the known-parameter law. On a robot
//! with joint friction and armature in its regressor (`--robot arm7-friction`) the true robot's
//! joint terms differ from the nominal ones, the adaptive run adapts them too (`--joint-gain`)
//! and a fourth run adapts only the inertial parameters, the joint terms held at nominal. `--task pose`
//! also turns the tool to vertical and holds its orientation (task dimension 6), `--task
//! tool-axis` holds only the tool axis vertical (5). `--frame NAME` controls, and touches the
//! table with, the robot's frame `NAME` instead of the end-effector (`--frame panda_link8`: the
//! Panda's flange; an unknown name lists the robot's frames). `--surface rigid` makes the table
//! rigid (with a model stiffness the controller's force loop can run on, `--stiffness 1e5`).
//!
//! `cargo run --release -p dyngen-control --example hybrid_force -- -o out/hybrid_force`
//!
//! Prints a summary table and writes one CSV per run and SVG plots into `-o/--output`.
//! Exits with 1 if a run diverged (its data is still written), 2 on a usage error.

mod svg;

use clap::{Parser, ValueEnum};
use dyngen_control::controller::{frame_named, Composite, GammaByKind};
use dyngen_control::sim::{
    start_posture_for, summary_table, write_csv, Demo, DemoOptions, JointTermFactors, NoiseConfig, RunKind,
    RunResult, RunStatus, Sample, SurfaceKind,
};
use dyngen_generated::{
    arm7, arm7_friction, panda, panda_rounded, ur5, Arm7, Arm7Friction, Panda, PandaRounded, Ur5,
};
use dyngen_runtime::nalgebra::SVector;
use dyngen_runtime::{
    BaseParameters, ForwardDynamics, FrameKinematics, Kinematics, Parameterization, RobotFrame,
};
use std::io::{IsTerminal as _, Write as _};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

#[derive(Clone, Copy, Debug, ValueEnum)]
enum Robot {
    Arm7,
    /// arm7 with joint friction and armature columns (`robots/arm7_friction.yaml`).
    Arm7Friction,
    Panda,
    /// The Panda with its `rpy` rounded to 4 decimals, loaded with `snap_angles: 1e-4`
    /// (`robots/panda_rounded.yaml`).
    PandaRounded,
    Ur5,
}

/// What of the end-effector's pose the task controls.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Task {
    /// Position only (task dimension 3).
    Position,
    /// Position and the direction of the tool axis, free rotation about it (5).
    ToolAxis,
    /// Position and orientation (6).
    Pose,
}

/// What the table is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum SurfaceKindArg {
    /// `F = k·penetration`, k the `--stiffness`.
    Compliant,
    /// Never entered; the controller still models it with `--stiffness` (which must keep its
    /// force loop's gain below 2: a lower one is refused, naming the least).
    Rigid,
}

#[derive(Parser, Debug)]
#[command(about = "Adaptive hybrid force/position control on a table: three laws side by side")]
struct Args {
    /// Robot (a committed generated robot).
    #[arg(long, value_enum, default_value = "arm7")]
    robot: Robot,
    /// Task: position (m = 3), tool-axis (m = 5: position, tool axis held vertical) or pose
    /// (m = 6: position, tool turned to vertical and its orientation held).
    #[arg(long, value_enum, default_value = "position")]
    task: Task,
    /// The robot frame the task controls and the table is touched with, by its name in the
    /// description (e.g. panda_link8, panda_hand on the Panda; ee_link, wrist_3_link on the
    /// UR5); default: the end-effector.
    #[arg(long, value_name = "NAME")]
    frame: Option<String>,
    /// Directory for the CSV files and plots (created if missing).
    #[arg(short, long, default_value = "hybrid_force_out")]
    output: PathBuf,
    /// Adapt the ten standard parameters per body instead of the base parameters.
    #[arg(long)]
    standard: bool,
    /// Add sensor noise (σ = 1e-4 rad, 1e-3 rad/s, 0.05 N).
    #[arg(long)]
    noise: bool,
    /// Seed of the noise.
    #[arg(long, default_value_t = 0x5eed)]
    seed: u64,
    /// Start posture (rad, one per joint); default: the demo's posture for a committed robot.
    #[arg(long, num_args = 1.., value_name = "Q")]
    start: Option<Vec<f64>>,
    /// Estimate the surface stiffness online, starting from k̂(0) = FACTOR·k (no stability proof).
    #[arg(long, value_name = "FACTOR")]
    estimate_stiffness: Option<f64>,
    /// Rate γ of the stiffness estimate (1/s).
    #[arg(long, default_value_t = 20.0)]
    estimation_rate: f64,
    /// Duration of the circle at full speed (s).
    #[arg(long, default_value_t = 8.0)]
    circle_time: f64,
    /// Revolutions of the circle per second (Hz).
    #[arg(long, default_value_t = 0.25, value_name = "HZ")]
    circle_frequency: f64,
    /// Surface stiffness k (N/m): the compliant table's and the controller's model's.
    #[arg(long, default_value_t = 1e4)]
    stiffness: f64,
    /// The table.
    #[arg(long, value_enum, default_value = "compliant")]
    surface: SurfaceKindArg,
    /// Target normal force (N).
    #[arg(long, default_value_t = 10.0)]
    force: f64,
    /// G = κ·D̂(q₀).
    #[arg(long)]
    kappa: Option<f64>,
    /// λ (force and position error gain).
    #[arg(long)]
    lambda: Option<f64>,
    /// Diagonal Γ by parameter kind: mass, first moment, inertia.
    #[arg(long, num_args = 3, value_names = ["M", "MC", "I"])]
    gamma: Option<Vec<f64>>,
    /// Γ of the joint-level parameters (armature, friction, offset) of a robot that has them;
    /// 0 holds them at the description's nominal values (only the inertial parameters adapt).
    #[arg(long, default_value_t = GammaByKind::DEFAULT_JOINT, value_name = "GAIN")]
    joint_gain: f64,
    /// The true robot's armature, viscous friction, Coulomb friction and offset as multiples of
    /// the description's nominal values (default 1.25 2 2 2).
    #[arg(long, num_args = 4, value_names = ["ARMATURE", "VISCOUS", "COULOMB", "OFFSET"])]
    true_joint_terms: Option<Vec<f64>>,
    /// θ̂(0) of the inertial parameters as a multiple of the description's (the payload is
    /// unknown either way).
    #[arg(long, default_value_t = 0.5, value_name = "SCALE")]
    initial_estimate: f64,
    /// θ̂(0) of the joint-level parameters (armature, friction, offset) as a multiple of the
    /// description's nominal values; 0 starts from no friction model at all.
    #[arg(long, default_value_t = 1.0, value_name = "SCALE")]
    joint_estimate: f64,
    /// Add the composite adaptation's runs: the update also descends the prediction error of
    /// the filtered joint torque, θ̂̇ = −Γ (Yᵀ r + Wᵀ R e).
    #[arg(long)]
    composite: bool,
    /// Bandwidth λ_f (rad/s) of the composite adaptation's filter λ_f/(s + λ_f).
    #[arg(long, default_value_t = Composite::DEFAULT_BANDWIDTH, value_name = "RAD_PER_S")]
    prediction_bandwidth: f64,
    /// Weight ρ of the prediction error in the composite adaptation (R = ρ I; 0 is the
    /// Slotine–Li law).
    #[arg(long, default_value_t = Composite::DEFAULT_WEIGHT, value_name = "RHO")]
    prediction_weight: f64,
}

fn main() -> ExitCode {
    let args = Args::parse();
    let result = match args.robot {
        Robot::Arm7 => {
            run_robot::<Arm7, { arm7::DOF }, { arm7::PARAMETER_COUNT }, { arm7::BASE_PARAMETER_COUNT }>(&args)
        }
        Robot::Arm7Friction => run_robot::<
            Arm7Friction,
            { arm7_friction::DOF },
            { arm7_friction::PARAMETER_COUNT },
            { arm7_friction::BASE_PARAMETER_COUNT },
        >(&args),
        Robot::Panda => {
            run_robot::<Panda, { panda::DOF }, { panda::PARAMETER_COUNT }, { panda::BASE_PARAMETER_COUNT }>(
                &args,
            )
        }
        Robot::PandaRounded => run_robot::<
            PandaRounded,
            { panda_rounded::DOF },
            { panda_rounded::PARAMETER_COUNT },
            { panda_rounded::BASE_PARAMETER_COUNT },
        >(&args),
        Robot::Ur5 => {
            run_robot::<Ur5, { ur5::DOF }, { ur5::PARAMETER_COUNT }, { ur5::BASE_PARAMETER_COUNT }>(&args)
        }
    };
    match result {
        Ok(true) => ExitCode::SUCCESS,
        // A diverged run is a failed run; 2 stays clap's code for a usage error.
        Ok(false) => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn options(args: &Args) -> DemoOptions {
    let mut o = DemoOptions {
        stiffness: args.stiffness,
        surface: match args.surface {
            SurfaceKindArg::Compliant => SurfaceKind::Compliant,
            SurfaceKindArg::Rigid => SurfaceKind::Rigid,
        },
        target_force: args.force,
        circle_time: args.circle_time,
        circle_frequency: args.circle_frequency,
        ..DemoOptions::default()
    };
    if let Some(k) = args.kappa {
        o.kappa = k;
    }
    if let Some(l) = args.lambda {
        o.lambda = l;
    }
    if let Some(g) = &args.gamma {
        o.gamma.mass = g[0];
        o.gamma.first_moment = g[1];
        o.gamma.inertia = g[2];
    }
    o.gamma.joint = args.joint_gain;
    o.initial_estimate_scale = args.initial_estimate;
    o.joint_estimate_scale = args.joint_estimate;
    if let Some(f) = &args.true_joint_terms {
        o.true_joint_terms = JointTermFactors {
            armature: f[0],
            viscous: f[1],
            coulomb: f[2],
            offset: f[3],
        };
    }
    if args.noise {
        o.sim.noise = Some(NoiseConfig::REFERENCE);
        o.sim.seed = args.seed;
    }
    o.stiffness_estimation = args.estimate_stiffness.map(|f| (f, args.estimation_rate));
    o.composite = args.composite.then_some(Composite {
        bandwidth: args.prediction_bandwidth,
        weight: args.prediction_weight,
    });
    o
}

/// The parameterisation is a type: the base parameters by default, `--standard` for all ten
/// per body.
fn run_robot<R, const N: usize, const P: usize, const B: usize>(args: &Args) -> Result<bool, String>
where
    R: BaseParameters<N, P, B> + ForwardDynamics<N, P> + FrameKinematics<N>,
{
    let q0 = start_posture_for::<R, N>(args.start.as_deref())?;
    // `None`: the end-effector through `Kinematics`, as for a robot without named frames.
    let frame = match &args.frame {
        Some(name) => Some(frame_named::<R, N>(name).map_err(|e| e.to_string())?),
        None => None,
    };
    if args.standard {
        run_task::<dyngen_runtime::Standard<R>, N, P>(args, q0, frame)
    } else {
        run_task::<dyngen_runtime::Base<R, P>, N, B>(args, q0, frame)
    }
}

/// The robot frame a `--frame` chose.
type FrameOf<Z, const N: usize, const M: usize> =
    <<Z as Parameterization<N, M>>::Robot as FrameKinematics<N>>::Frame;

/// The task dimension is a type too: 3, 5 or 6.
fn run_task<Z, const N: usize, const M: usize>(
    args: &Args,
    q0: SVector<f64, N>,
    frame: Option<FrameOf<Z, N, M>>,
) -> Result<bool, String>
where
    Z: Parameterization<N, M>,
    Z::Robot: FrameKinematics<N>,
{
    match args.task {
        Task::Position => run::<Z, N, M, 3>(args, q0, frame),
        Task::ToolAxis => run::<Z, N, M, 5>(args, q0, frame),
        Task::Pose => run::<Z, N, M, 6>(args, q0, frame),
    }
}

/// Runs the three laws; `Ok(false)` if one diverged (its data is still written).
fn run<Z, const N: usize, const M: usize, const T: usize>(
    args: &Args,
    q0: SVector<f64, N>,
    frame: Option<FrameOf<Z, N, M>>,
) -> Result<bool, String>
where
    Z: Parameterization<N, M>,
    Z::Robot: FrameKinematics<N>,
{
    let opts = options(args);
    let demo = match frame {
        Some(frame) => Demo::<Z, N, M, T>::new_at_frame(opts, q0, frame),
        None => Demo::<Z, N, M, T>::new(opts, q0),
    }
    .map_err(|e| e.to_string())?;
    std::fs::create_dir_all(&args.output)
        .map_err(|e| format!("cannot create {}: {e}", args.output.display()))?;

    let from = demo.metrics_from();
    println!(
        "robot {} ({N} DOF, {M} adapted parameters), {} k = {} N/m, target {} N, payload {} kg unknown, {}{}",
        <Z::Robot as Kinematics<N>>::NAME,
        match opts.surface {
            SurfaceKind::Compliant => "table",
            SurfaceKind::Rigid => "rigid table, modelled with",
        },
        opts.stiffness,
        opts.target_force,
        opts.payload.mass,
        if opts.sim.noise.is_some() {
            "sensor noise on"
        } else {
            "no noise"
        },
        match opts.stiffness_estimation {
            Some((f, g)) => format!(", stiffness estimated online from {f}·k (γ = {g})"),
            None => String::new(),
        }
    );
    println!(
        "controlled frame: {}",
        match demo.controlled_frame() {
            Some(name) => name.to_string(),
            None => format!(
                "{} (the end-effector)",
                <FrameOf<Z, N, M> as RobotFrame>::ALL
                    .first()
                    .map_or("", |f| f.name())
            ),
        }
    );
    println!(
        "task: {}",
        match args.task {
            Task::Position => "position (m = 3), orientation free".to_string(),
            Task::ToolAxis => format!(
                "position and tool axis (m = 5): tool axis turned by {:.1}° to vertical by t = {:.1} s and held, free rotation about it",
                demo.scenario.turn_angle.to_degrees(),
                demo.scenario.turn_time()
            ),
            Task::Pose => format!(
                "position and orientation (m = 6): tool turned by {:.1}° to vertical by t = {:.1} s and held",
                demo.scenario.turn_angle.to_degrees(),
                demo.scenario.turn_time()
            ),
        }
    );
    println!(
        "gains: G = {}·D̂(q₀), λ = {}, λ_n = {}, Γ = [{}, {}, {}] over [m, m·c, I]{}; controller 1 kHz, RK4 plant {} kHz; {:.1} s simulated",
        opts.kappa,
        opts.lambda,
        opts.lambda_null,
        opts.gamma.mass,
        opts.gamma.first_moment,
        opts.gamma.inertia,
        if args.standard { "" } else { " (base parameters: diag(Φ Γ Φᵀ))" },
        opts.sim.substeps as f64 / opts.sim.control_period / 1e3,
        demo.scenario.duration()
    );
    if let Some(c) = opts.composite {
        println!(
            "composite adaptation: filter λ_f/(s + λ_f), λ_f = {} rad/s; R = {}·I",
            c.bandwidth, c.weight
        );
    }
    if Demo::<Z, N, M, T>::has_joint_terms() {
        let f = opts.true_joint_terms;
        println!(
            "joint terms: true = [{}, {}, {}, {}] × nominal over [armature, viscous, Coulomb, offset]; θ̂(0) = {} × nominal{}; {}",
            f.armature,
            f.viscous,
            f.coulomb,
            f.offset,
            opts.joint_estimate_scale,
            if opts.joint_estimate_scale == 0.0 { " (no joint friction or armature modelled)" } else { "" },
            if opts.gamma.joint > 0.0 {
                format!("adapted with Γ = {} (\"adaptive\"), held at θ̂(0) (\"joint terms held\")", opts.gamma.joint)
            } else {
                "held at θ̂(0) (--joint-gain 0)".to_string()
            }
        );
    }

    let mut results: Vec<(RunKind, RunResult)> = Vec::new();
    let mut all_ok = true;
    // A live percentage on a terminal; in a log (CI, a pipe) one line per run instead of a
    // hundred carriage returns.
    let live = std::io::stderr().is_terminal();
    for kind in demo.run_kinds() {
        let started = Instant::now();
        let mut progress = |f: f64| {
            if !live && f < 1.0 {
                return;
            }
            eprint!(
                "\r  {:<29} {:>3.0} %  ({:.1} s)",
                kind.label(),
                100.0 * f,
                started.elapsed().as_secs_f64()
            );
            let _ = std::io::stderr().flush();
        };
        let res = demo.run(kind, &mut progress).map_err(|e| e.to_string())?;
        eprintln!();
        if let RunStatus::Diverged { time, reason } = &res.status {
            eprintln!(
                "  {} run diverged at t = {time:.3} s: {reason} (data so far is written)",
                kind.label()
            );
            all_ok = false;
        }
        let path = args.output.join(format!("{}.csv", kind.file_stem()));
        write_csv(&path, &res.samples).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        results.push((kind, res));
    }

    println!();
    println!("over the last 4 s (t ≥ {from:.1} s):");
    let oriented = T > 3;
    print!("{}", summary_table(&results, from, oriented));
    let mut written = write_plots(&args.output, &results).map_err(|e| format!("cannot write plots: {e}"))?;
    if oriented {
        written.push(
            write_orientation_plot(&args.output, &results).map_err(|e| format!("cannot write plots: {e}"))?,
        );
    }
    if opts.composite.is_some() {
        written.push(
            write_composite_plot(&args.output, &results).map_err(|e| format!("cannot write plots: {e}"))?,
        );
    }
    println!();
    println!(
        "wrote {} and the per-run CSV files into {}",
        written.join(", "),
        args.output.display()
    );
    Ok(all_ok)
}

const COLOURS: [&str; 6] = ["#1f77b4", "#ff7f0e", "#d62728", "#2ca02c", "#9467bd", "#8c564b"];

/// The colour of a run, the same in every figure whichever runs there are.
fn colour(kind: RunKind) -> &'static str {
    match kind {
        RunKind::Adaptive => COLOURS[0],
        RunKind::Composite => COLOURS[4],
        RunKind::AdaptiveJointTermsHeld => COLOURS[1],
        RunKind::CompositeJointTermsHeld => COLOURS[5],
        RunKind::AdaptationOff => COLOURS[2],
        RunKind::KnownParameters => COLOURS[3],
    }
}

fn write_plots(dir: &Path, results: &[(RunKind, RunResult)]) -> std::io::Result<Vec<String>> {
    let decimate = |samples: &[Sample], f: &dyn Fn(&Sample) -> f64| -> Vec<(f64, f64)> {
        let step = (samples.len() / 800).max(1);
        samples.iter().step_by(step).map(|s| (s.t, f(s))).collect()
    };
    type Getter = fn(&Sample) -> f64;
    let quantities: [(&str, &str, &str, bool, Getter); 6] = [
        ("force", "normal force F_t (N)", "N", false, |s| s.true_force),
        (
            "position_error",
            "in-plane position error ‖K⁻x̃‖ (mm)",
            "mm",
            true,
            |s| s.in_plane_error * 1e3,
        ),
        (
            "null_space_error",
            "null-space error ‖J⁻(q − q_ν)‖ (rad)",
            "rad",
            true,
            |s| s.null_error,
        ),
        (
            "lyapunov",
            "V(t) = ½rᵀDr + ½θ̃ᵀΓ⁻¹θ̃ (adaptive), ½rᵀDr (others)",
            "V",
            true,
            |s| s.lyapunov,
        ),
        (
            "theta_error",
            "parameter error ‖θ̃‖",
            "‖θ̃‖",
            true,
            |s| s.theta_error,
        ),
        (
            "joint_term_error",
            "joint-term error ‖θ̃_j‖/‖θ_j‖",
            "relative",
            true,
            |s| s.joint_term_error,
        ),
    ];
    // A robot without joint terms has no joint-term error to draw.
    let has_joint_terms = results
        .iter()
        .any(|(_, r)| r.samples.iter().any(|s| s.joint_term_error.is_finite()));
    let quantities: Vec<_> = quantities
        .into_iter()
        .filter(|q| q.0 != "joint_term_error" || has_joint_terms)
        .collect();
    let mut panels = Vec::new();
    for &(_, title, unit, log, get) in &quantities {
        let mut series: Vec<svg::Series> = results
            .iter()
            .map(|(k, r)| svg::Series {
                label: k.label(),
                colour: colour(*k),
                dashed: false,
                points: decimate(&r.samples, &get),
            })
            .collect();
        if unit == "N" {
            if let Some((_, r)) = results.first() {
                series.push(svg::Series {
                    label: "desired",
                    colour: "#000",
                    dashed: true,
                    points: decimate(&r.samples, &|s| s.desired_force.max(0.0)),
                });
            }
        }
        panels.push(svg::Panel {
            title,
            y_label: unit,
            log,
            series,
        });
    }
    let mut written = Vec::new();
    for (panel, (name, ..)) in panels.iter().zip(quantities.iter()) {
        let file = format!("{name}.svg");
        std::fs::write(dir.join(&file), svg::render(std::slice::from_ref(panel)))?;
        written.push(file);
    }
    std::fs::write(dir.join("hybrid_force.svg"), svg::render(&panels))?;
    written.insert(0, "hybrid_force.svg".into());
    Ok(written)
}

/// One panel of `get` over time for the runs `results`, decimated to about 800 points each.
fn panel<'a>(
    title: &'a str,
    y_label: &'a str,
    log: bool,
    results: impl Iterator<Item = &'a (RunKind, RunResult)>,
    get: fn(&Sample) -> f64,
) -> svg::Panel<'a> {
    let decimate = |samples: &[Sample]| -> Vec<(f64, f64)> {
        let step = (samples.len() / 800).max(1);
        samples.iter().step_by(step).map(|s| (s.t, get(s))).collect()
    };
    svg::Panel {
        title,
        y_label,
        log,
        series: results
            .map(|(k, r)| svg::Series {
                label: k.label(),
                colour: colour(*k),
                dashed: false,
                points: decimate(&r.samples),
            })
            .collect(),
    }
}

/// For tasks with orientation rows: force, in-plane error and orientation error of the three
/// runs stacked in one figure, `hybrid_force_orientation.svg`.
fn write_orientation_plot(dir: &Path, results: &[(RunKind, RunResult)]) -> std::io::Result<String> {
    type Getter = fn(&Sample) -> f64;
    let quantities: [(&str, &str, bool, Getter); 3] = [
        ("normal force F_t (N)", "N", false, |s| s.true_force),
        ("in-plane position error ‖K⁻x̃‖ (mm)", "mm", true, |s| {
            s.in_plane_error * 1e3
        }),
        (
            "orientation error: angle to the desired orientation (mrad)",
            "mrad",
            true,
            |s| s.orientation_error * 1e3,
        ),
    ];
    let panels: Vec<svg::Panel> = quantities
        .iter()
        .map(|(title, unit, log, get)| panel(title, unit, *log, results.iter(), *get))
        .collect();
    let file = "hybrid_force_orientation.svg".to_string();
    std::fs::write(dir.join(&file), svg::render(&panels))?;
    Ok(file)
}

/// With the composite adaptation: the force error of every run, the composite runs' prediction
/// error and, for a robot with joint terms, the joint-term error, stacked in one figure,
/// `hybrid_force_composite.svg`.
fn write_composite_plot(dir: &Path, results: &[(RunKind, RunResult)]) -> std::io::Result<String> {
    let composite = |k: RunKind| matches!(k, RunKind::Composite | RunKind::CompositeJointTermsHeld);
    type Getter = fn(&Sample) -> f64;
    let mut quantities: Vec<(&str, &str, Getter, bool)> = vec![
        ("force error |F_t − F_d| (N)", "N", |s| s.force_error.abs(), false),
        (
            "prediction error ‖e‖ = ‖W θ̂ − τ_f‖ of the composite runs (N·m)",
            "N·m",
            |s| s.prediction_error,
            true,
        ),
    ];
    if results
        .iter()
        .any(|(_, r)| r.samples.iter().any(|s| s.joint_term_error.is_finite()))
    {
        quantities.push((
            "joint-term error ‖θ̃_j‖/‖θ_j‖",
            "relative",
            |s| s.joint_term_error,
            false,
        ));
    }
    let panels: Vec<svg::Panel> = quantities
        .iter()
        .map(|(title, unit, get, composite_only)| {
            let runs = results.iter().filter(|(k, _)| !composite_only || composite(*k));
            panel(title, unit, true, runs, *get)
        })
        .collect();
    let file = "hybrid_force_composite.svg".to_string();
    std::fs::write(dir.join(&file), svg::render(&panels))?;
    Ok(file)
}
