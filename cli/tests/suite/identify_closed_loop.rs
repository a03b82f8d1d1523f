//! `dyngen identify --method iv|didim` with the controller's `--gains` and the `--reference` it
//! tracked, and the torque channel's `--estimate-delay --fractional-delay` and
//! `--estimate-gain`, on a small arm carrying a 1.5 kg tool its description lacks, run by a PD
//! along a random excitation and logged at 200 Hz. The closed-loop methods land nearer the truth than
//! the least squares on coarse encoders; the gains read from a file and from the command line
//! give the same estimate; every flag that does not fit is one error line and writes nothing.

use crate::common;

use common::{arg, dyngen, repository_file, table};
use dyngen_codegen::base_parameters::BaseParameterSet;
use dyngen_codegen::description::load;
use dyngen_codegen::dynamics::NumericDynamics;
use dyngen_codegen::model::{JointTermValues, Model};
use dyngen_identify::{
    measure_closed_loop, to_csv, with_joint_terms, with_payload, ControlLaw, FourierTrajectory, Logging,
    Samples, TrajectoryLimits, DEFAULT_ACCELERATION_PER_VELOCITY,
};
use nalgebra::Vector3;
use std::path::{Path, PathBuf};

/// A log read by encoders of `encoder_bits` (`None`: exact), without delay or gains, seed 1.
fn read_by(encoder_bits: Option<u32>) -> Logging {
    Logging {
        encoder_bits,
        torque_noise: Vec::new(),
        torque_delay: 0.0,
        torque_gain: Vec::new(),
        seed: 1,
    }
}

/// The small arm of the identification tests as described (every joint column, Coulomb
/// friction smoothed over 0.01 rad/s), the robot it stands for (a 1.5 kg tool its
/// description lacks, friction and armature), the PD that runs it and what it tracks, in a
/// scratch directory.
struct Robot {
    dir: tempfile::TempDir,
    description: PathBuf,
    model: Model,
    truth: Model,
    law: ControlLaw,
    trajectory: FourierTrajectory,
}

impl Robot {
    fn new() -> Robot {
        let dir = tempfile::tempdir().expect("temp dir");
        let description = dir.path().join("arm3.yaml");
        let text = std::fs::read_to_string(repository_file("identify/tests/data/arm3.yaml")).expect("arm3.yaml")
            + "joint_parameters:\n  columns: [armature, viscous, coulomb, offset]\n  coulomb_smoothing: 0.01\n";
        std::fs::write(&description, text).expect("write");
        let model = load(&description).unwrap_or_else(|e| panic!("{e}")).model;
        let terms = JointTermValues {
            armature: 0.2,
            viscous: 1.0,
            coulomb: 1.5,
            offset: 0.1,
        };
        let tool = with_payload(&model, 1.5, Vector3::new(0.05, 0.02, 0.0), 0.04);
        let truth = with_joint_terms(&tool, &[terms; 3], Some(0.01));
        let mut trajectory = FourierTrajectory::random(3, 5, 0.1, 3);
        trajectory.fit_into(&TrajectoryLimits::from_model(
            &truth,
            DEFAULT_ACCELERATION_PER_VELOCITY,
        ));
        let mass = NumericDynamics::new(&truth).mass_matrix(&trajectory.at(0.0).q);
        let inertia: Vec<f64> = (0..3).map(|j| mass[(j, j)]).collect();
        let law = ControlLaw::critically_damped(&inertia, 2.0 * std::f64::consts::PI * 5.0);
        Robot {
            dir,
            description,
            model,
            truth,
            law,
            trajectory,
        }
    }

    fn path(&self, name: &str) -> PathBuf {
        self.dir.path().join(name)
    }

    /// 10 s of the robot in its loop, read as `logging` says with torque noise of `share` of
    /// the rated torque, written as `<name>.csv`; the reference as `reference.csv`.
    fn log(&self, name: &str, share: f64, logging: Logging) -> PathBuf {
        let noise = self
            .truth
            .joints()
            .iter()
            .map(|j| share * j.limits.map_or(1.0, |l| l.effort))
            .collect();
        let logging = Logging {
            torque_noise: noise,
            ..logging
        };
        let (samples, reference) =
            measure_closed_loop(&self.truth, &self.law, &self.trajectory, 10.0, 200.0, &logging)
                .unwrap_or_else(|e| panic!("{e}"));
        let data = self.path(&format!("{name}.csv"));
        std::fs::write(&data, to_csv(&self.model, &samples)).expect("write");
        let reference = Samples {
            time: reference.time,
            q: reference.q,
            qd: Some(reference.qd),
            ..Samples::default()
        };
        std::fs::write(self.path("reference.csv"), to_csv(&self.model, &reference)).expect("write");
        data
    }

    /// The law as `joint,kp,kd` lines, written as `gains.csv`.
    fn gains_file(&self) -> PathBuf {
        let mut text = String::from("joint,kp,kd\n");
        for (joint, g) in self.model.joints().iter().zip(&self.law.gains) {
            text += &format!("{},{},{}\n", joint.name, g.kp, g.kd);
        }
        let path = self.path("gains.csv");
        std::fs::write(&path, text).expect("write");
        path
    }

    /// The law as `--gains JOINT=KP,KD` arguments.
    fn gains_arguments(&self) -> Vec<String> {
        self.model
            .joints()
            .iter()
            .zip(&self.law.gains)
            .flat_map(|(joint, g)| ["--gains".to_string(), format!("{}={},{}", joint.name, g.kp, g.kd)])
            .collect()
    }

    /// `dyngen identify` of `data` with `extra` arguments, written to `out.yaml`; the run.
    fn identify(&self, data: &Path, extra: &[&str]) -> common::Run {
        let out = self.path("out.yaml");
        let _ = std::fs::remove_file(&out);
        let mut args = vec!["identify", arg(&self.description), arg(data), "-o", arg(&out)];
        args.extend_from_slice(extra);
        dyngen(&args)
    }

    /// The RMS over the base parameters of the errors of the table printed in `stdout`, each
    /// in units of its σ.
    fn errors_in_sigma(&self, stdout: &str) -> f64 {
        let truth = BaseParameterSet::compute(&self.model).base_parameters(&self.truth.parameters());
        let rows = table(stdout);
        assert_eq!(rows.len(), truth.len());
        let squares: f64 = rows
            .iter()
            .zip(&truth)
            .map(|((v, s), t)| ((v - t) / s).powi(2))
            .sum();
        (squares / truth.len() as f64).sqrt()
    }
}

/// 12-bit encoders: the least squares' errors are several σ, IDIM-IV's and DIDIM's (the law as
/// a file, or as arguments) a few times fewer; the two forms of the law give one estimate; without
/// the law IDIM-IV tracks the measured positions and says so.
#[test]
fn closed_loop_methods_from_the_command_line() {
    let robot = Robot::new();
    let data = robot.log("data", 0.005, read_by(Some(12)));
    let (gains, reference) = (robot.gains_file(), robot.path("reference.csv"));
    let ls = robot.identify(&data, &[]);
    assert_eq!(ls.code, Some(0), "{}", ls.output());
    let iv = robot.identify(
        &data,
        &[
            "--method",
            "iv",
            "--gains",
            arg(&gains),
            "--reference",
            arg(&reference),
        ],
    );
    assert_eq!(iv.code, Some(0), "{}", iv.output());
    assert!(iv.stdout.contains("IDIM-IV: converged in "), "{}", iv.stdout);
    // From the least squares, or (here: their model of the coarse log diverges in the loop)
    // from the description.
    assert!(
        iv.stdout
            .contains(" simulations from the least squares' estimate (")
            || iv.stdout.contains(" simulations from the description's values ("),
        "{}",
        iv.stdout
    );
    assert!(robot.path("out.yaml").exists());
    let arguments = robot.gains_arguments();
    let mut didim_args: Vec<&str> = vec!["--method", "didim", "--reference", arg(&reference)];
    didim_args.extend(arguments.iter().map(String::as_str));
    let didim = robot.identify(&data, &didim_args);
    assert_eq!(didim.code, Some(0), "{}", didim.output());
    assert!(didim.stdout.contains("DIDIM: converged in "), "{}", didim.stdout);
    assert!(
        didim
            .stdout
            .contains(" simulations from the description's values ("),
        "{}",
        didim.stdout
    );
    let (e_ls, e_iv, e_didim) = (
        robot.errors_in_sigma(&ls.stdout),
        robot.errors_in_sigma(&iv.stdout),
        robot.errors_in_sigma(&didim.stdout),
    );
    println!("errors (RMS, in σ): least squares {e_ls:.2}, IDIM-IV {e_iv:.2}, DIDIM {e_didim:.2}");
    // Measured: 5.2, 1.2 and 2.5.
    assert!(
        e_ls >= 3.0 * e_iv && e_ls >= 1.5 * e_didim,
        "{e_ls} {e_iv} {e_didim}"
    );

    // The law as arguments: the estimate of the law as a file.
    let mut iv_args: Vec<&str> = vec!["--method", "iv", "--reference", arg(&reference)];
    iv_args.extend(arguments.iter().map(String::as_str));
    let iv_arguments = robot.identify(&data, &iv_args);
    assert_eq!(iv_arguments.code, Some(0), "{}", iv_arguments.output());
    common::assert_same_table(
        &table(&iv.stdout),
        &table(&iv_arguments.stdout),
        "IDIM-IV, gains as arguments",
    );

    // No law: a stiff PD on the measured positions.
    let tracking = robot.identify(&data, &["--method", "iv"]);
    assert_eq!(tracking.code, Some(0), "{}", tracking.output());
    assert!(
        tracking
            .stdout
            .contains("IDIM-IV: no control law given: the robot simulated tracking the measured positions"),
        "{}",
        tracking.stdout
    );
}

/// Torques 2.4 samples behind the positions, each joint's channel reading its own gain (torque
/// noise 0.1% of the rated torque: a small arm's torques change little in a sample):
/// `--estimate-delay 5 --fractional-delay --estimate-gain` finds both (measured: 2.484
/// samples, where a whole delay is 0.4 off; gains within 0.7%).
#[test]
fn the_torque_channel_from_the_command_line() {
    let robot = Robot::new();
    let gains = [1.0, 0.93, 1.08];
    let data = robot.log(
        "delayed",
        0.001,
        Logging {
            torque_delay: 2.4,
            torque_gain: gains.to_vec(),
            seed: 2,
            ..read_by(None)
        },
    );
    let run = robot.identify(
        &data,
        &["--estimate-delay", "5", "--fractional-delay", "--estimate-gain"],
    );
    assert_eq!(run.code, Some(0), "{}", run.output());
    let line = run
        .stdout
        .lines()
        .find(|l| l.starts_with("torque delay: "))
        .unwrap_or_else(|| panic!("{}", run.stdout));
    println!("{line}");
    let delay: f64 = line["torque delay: ".len()..]
        .split_whitespace()
        .next()
        .and_then(|d| d.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!((delay - 2.4).abs() <= 0.15, "{line}");
    assert!(line.contains(" ± "), "{line}");
    let names: Vec<&str> = robot.model.joints().iter().map(|j| j.name.as_str()).collect();
    assert!(
        run.stdout.contains(&format!(
            "torque gain per joint (what its channel reads per N·m, relative to '{}'):",
            names[0]
        )),
        "{}",
        run.stdout
    );
    for (j, name) in names.iter().enumerate().skip(1) {
        let prefix = format!("  {name}: ");
        let line = run
            .stdout
            .lines()
            .find(|l| l.starts_with(&prefix) && l.contains("(σ "))
            .unwrap_or_else(|| panic!("{}", run.stdout));
        let found: f64 = line[prefix.len()..]
            .split_whitespace()
            .next()
            .and_then(|g| g.parse().ok())
            .unwrap_or_else(|| panic!("{line}"));
        println!("{line}");
        assert!((found / gains[j] - 1.0).abs() <= 0.02, "{line}");
    }
}

/// Flags that do not go together, and gains or a reference that do not fit the robot or the
/// data: exit status 1 (2 for what the argument parser refuses) and one `error:` line, nothing
/// written.
#[test]
fn closed_loop_flags_that_do_not_fit_are_one_error_line() {
    let robot = Robot::new();
    let data = robot.log("data", 0.005, read_by(Some(12)));
    let (gains, reference) = (robot.gains_file(), robot.path("reference.csv"));
    let (gains, reference) = (arg(&gains).to_string(), arg(&reference).to_string());
    let bad_gains = robot.path("bad-gains.csv");
    let text = std::fs::read_to_string(&gains).expect("read");
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    lines[1] = "j1,1000,x".into();
    std::fs::write(&bad_gains, lines.join("\n")).expect("write");
    let missing_joint = robot.path("two-gains.csv");
    std::fs::write(
        &missing_joint,
        text.lines().take(3).collect::<Vec<_>>().join("\n"),
    )
    .expect("write");
    let half = robot.path("half-reference.csv");
    let reference_text = std::fs::read_to_string(&reference).expect("read");
    std::fs::write(
        &half,
        reference_text.lines().take(1001).collect::<Vec<_>>().join("\n"),
    )
    .expect("write");
    let cases: Vec<(Vec<&str>, i32, String)> = vec![
        (
            vec!["--method", "didim"],
            1,
            "error: --method didim simulates the loop the torques come from: give the controller's --gains \
             and the --reference it tracked"
                .into(),
        ),
        (
            vec!["--gains", &gains, "--reference", &reference],
            1,
            "error: --gains and --reference are for --method iv and didim: the least squares simulate nothing"
                .into(),
        ),
        (
            vec!["--method", "iv", "--gains", &gains],
            1,
            "error: --gains needs --reference: the trajectory the controller tracked".into(),
        ),
        (
            vec!["--method", "iv", "--reference", &reference],
            1,
            "error: --reference needs --gains: the controller that tracked it".into(),
        ),
        (
            vec!["--method", "iv", "--gains", "elbow=1,2", "--reference", &reference],
            1,
            "error: gains 'elbow=1,2': unknown joint 'elbow' (the robot's moving joints: j1, j2, j3)".into(),
        ),
        (
            vec!["--method", "iv", "--gains", arg(&bad_gains), "--reference", &reference],
            1,
            format!("error: {}:2: kd 'x' is not a finite number", bad_gains.display()),
        ),
        (
            vec!["--method", "iv", "--gains", arg(&missing_joint), "--reference", &reference],
            1,
            format!(
                "error: {}: no gains for joint j3 (every joint needs kp and kd)",
                missing_joint.display()
            ),
        ),
        (
            vec!["--method", "iv", "--gains", &gains, "--reference", arg(&half)],
            1,
            format!("error: {}: the reference covers 0 s to 4.995 s, the data 0 s to 9.", data.display()),
        ),
        (
            vec!["--method", "didim", "--gains", &gains, "--reference", &reference, "--stream"],
            1,
            "error: DIDIM simulates the robot along the whole log: identify it without streaming".into(),
        ),
        (
            vec!["--method", "iv", "--observation", "momentum"],
            1,
            "error: IDIM-IV fits the torque form: the windowed forms are fitted by least squares".into(),
        ),
        (
            vec!["--estimate-gain", "elbow"],
            1,
            "error: --estimate-gain elbow: unknown joint (the robot's moving joints: j1, j2, j3)".into(),
        ),
        (vec!["--fractional-delay"], 2, "error: the following required arguments were not provided".into()),
    ];
    for (extra, code, expected) in cases {
        let run = robot.identify(&data, &extra);
        assert_eq!(run.code, Some(code), "{extra:?}: {}", run.output());
        let errors: Vec<&str> = run.stderr.lines().filter(|l| l.starts_with("error:")).collect();
        assert_eq!(errors.len(), 1, "{extra:?}: {}", run.output());
        assert!(
            errors[0].starts_with(&expected),
            "{extra:?}: {}\nexpected: {expected}",
            errors[0]
        );
        if code == 1 {
            assert_eq!(run.stderr.lines().count(), 1, "{extra:?}: {}", run.output());
        }
        assert!(!robot.path("out.yaml").exists(), "{extra:?}");
    }
}
